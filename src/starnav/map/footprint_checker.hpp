#pragma once
// The robot's footprint against the obstacles of a clearance window (map/clearance_window.hpp):
// one collision checker for every controller, planner and recovery that moves a footprint (circle
// or rectangle) over the map; exact for its rule, quick where the distance field decides.
#include <cmath>
#include <cstdint>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/map/clearance_window.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// The robot's outline for collision tests: a circle, or a rectangle, centred on base_link or
// `center_x_m` ahead of it (a car's base_link is its rear axle, its body centred between the
// axles). Every test grows it by `grow_m` and by half the diagonal of a cell, so that an obstacle
// cell (a square) touching the outline is always found from its centre.
struct FootprintModel {
  bool circle = true;
  double radius_m = 0.25;       // circle
  double half_length_m = 0.0;   // rectangle, along x
  double half_width_m = 0.0;    // rectangle, along y
  double center_x_m = 0.0;      // the outline's centre in base_link (x forward)
  // About base_link: the smallest circle holding the outline, the largest circle inside it (0
  // when base_link lies outside the outline).
  double bounding_radius_m() const;
  double inscribed_radius_m() const;
};

// What the distance field alone says about a footprint at a pose.
enum class FootprintTest : std::uint8_t { Clear, Collides, Unsure };

class FootprintChecker {
 public:
  FootprintChecker() = default;
  // A rectangle is also covered by discs along its length (for the quick clear test).
  FootprintChecker(const FootprintModel& model, double grow_m);
  const FootprintModel& model() const { return model_; }
  double grow_m() const { return grow_m_; }

  // True when the footprint at `pose`, grown by grow_m() + `extra_m` + half a cell's diagonal
  // (never by less than nothing: `extra_m` may be negative), holds an obstacle cell centre, or when
  // `pose` lies outside the window. Exact for that rule:
  // quick_test decides most poses, the cells near the outline the rest.
  bool collides(const ClearanceWindow& map, const Pose2& pose, double extra_m = 0.0) const;
  // The distance field's verdict alone: Clear when the discs covering the footprint hold no
  // obstacle, Collides when a nearest obstacle it looked up lies inside, Unsure otherwise.
  // `heading` is (cos yaw, sin yaw) of the pose.
  FootprintTest quick_test(const ClearanceWindow& map, const Pose2& pose, const Vec2& heading, double extra_m = 0.0) const;
  // The exact test of the cells near the pose (what collides() does when quick_test is unsure).
  bool exact_test(const ClearanceWindow& map, const Pose2& pose, const Vec2& heading, double extra_m = 0.0) const;
  // The same by brute force over every obstacle cell of the window (tests).
  bool collides_brute_force(const ClearanceWindow& map, const Pose2& pose, double extra_m = 0.0) const;

 private:
  // The grown footprint at `pose` (heading = its cos, sin) holds `point`.
  bool holds(const Pose2& pose, const Vec2& heading, const Vec2& point, double grow) const {
    const double dx = point.x() - pose.x, dy = point.y() - pose.y;
    if (model_.circle) {
      const double r = model_.radius_m + grow;
      const double cx = dx - heading.x() * model_.center_x_m, cy = dy - heading.y() * model_.center_x_m;
      return cx * cx + cy * cy <= r * r;
    }
    const double qx = heading.x() * dx + heading.y() * dy - model_.center_x_m;
    const double qy = -heading.y() * dx + heading.x() * dy;
    const double ox = std::max(std::abs(qx) - model_.half_length_m, 0.0);
    const double oy = std::max(std::abs(qy) - model_.half_width_m, 0.0);
    return ox * ox + oy * oy <= grow * grow;
  }

  FootprintModel model_;
  double grow_m_ = 0.0;
  double bounding_m_ = 0.0;  // the model's bounding radius
  std::vector<Vec2> cover_;      // base_link centres of the covering discs (along the long axis)
  double cover_radius_m_ = 0.0;
};

// Whether driving a constant body twist from a pose keeps a footprint clear of the obstacles of a
// map, tested every `step_s` along the exact arc: the map's distance field (refreshed), or the
// occupied cells of an occupancy grid (unknown cells free). The window around the pose is built
// anew for each question (reusing its buffers).
class FootprintMotionChecker {
 public:
  explicit FootprintMotionChecker(const FootprintModel& model);
  bool clear(const ObstacleDistanceField& field, const Pose2& pose, const BodyTwist& twist, double duration_s,
             double step_s = 0.05) const;
  bool clear(const OccupancyGrid& obstacles, const Pose2& pose, const BodyTwist& twist, double duration_s,
             double step_s = 0.05) const;

 private:
  double reach_m(const BodyTwist& twist, double duration_s) const;
  bool clear_in_window(const Pose2& pose, const BodyTwist& twist, double duration_s, double step_s) const;

  FootprintModel model_;
  FootprintChecker checker_;
  mutable ClearanceWindow window_;
};

}  // namespace starnav
