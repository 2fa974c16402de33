#include "starnav/map/footprint_checker.hpp"

#include "starnav/core/planar_motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

namespace starnav {

namespace {
constexpr double kFootprintScanBig = 1e300;
}  // namespace

double FootprintModel::bounding_radius_m() const {
  const double off = std::abs(center_x_m);
  return circle ? radius_m + off : std::hypot(half_length_m + off, half_width_m);
}

double FootprintModel::inscribed_radius_m() const {
  const double off = std::abs(center_x_m);
  return std::max(0.0, circle ? radius_m - off : std::min(half_length_m - off, half_width_m));
}

FootprintChecker::FootprintChecker(const FootprintModel& model, double grow_m)
    : model_(model), grow_m_(grow_m), bounding_m_(model.bounding_radius_m()) {
  if (model_.circle) {
    cover_ = {Vec2(model_.center_x_m, 0.0)};
    cover_radius_m_ = model_.radius_m;
    return;
  }
  // k discs centred along the long axis at the middles of k equal slices of the rectangle; more
  // discs hug it closer but cost a lookup each (three for a near-square body).
  const bool along_x = model_.half_length_m >= model_.half_width_m;
  const double hl = along_x ? model_.half_length_m : model_.half_width_m;
  const double hw = along_x ? model_.half_width_m : model_.half_length_m;
  const int k = std::clamp(static_cast<int>(std::ceil(hl / hw)) + 1, 1, 8);
  const double slice = 2.0 * hl / k;
  for (int i = 0; i < k; ++i) {
    const double a = -hl + slice * (i + 0.5);
    cover_.push_back(along_x ? Vec2(model_.center_x_m + a, 0.0) : Vec2(model_.center_x_m, a));
  }
  cover_radius_m_ = std::hypot(0.5 * slice, hw);
}

FootprintTest FootprintChecker::quick_test(const ClearanceWindow& map, const Pose2& pose, const Vec2& heading,
                                           double extra_m) const {
  const double grow = std::max(0.0, grow_m_ + extra_m + map.resolution() * std::sqrt(0.5));
  // Every obstacle centre lies at least d - |q - c| from a point q whose cell (centre c) has
  // clearance d: clear when that exceeds `radius`.
  const auto clear_within = [&](const Vec2& q, std::size_t i, const Cell& cell, double radius) {
    const double d = map.clearance_m(i);
    if (!std::isfinite(d)) return true;
    const double room = d - radius;
    return room > 0.0 && (q - map.cell_center(cell.x, cell.y)).squaredNorm() < room * room;
  };
  const Cell centre = map.cell_of(pose.translation());
  if (!map.contains(centre.x, centre.y)) return FootprintTest::Collides;
  // One lookup settles open space.
  if (clear_within(pose.translation(), map.index(centre.x, centre.y), centre, bounding_m_ + grow))
    return FootprintTest::Clear;
  const double c = heading.x(), s = heading.y();
  bool clear = true;
  for (const Vec2& o : cover_) {
    const Vec2 q(pose.x + c * o.x() - s * o.y(), pose.y + s * o.x() + c * o.y());
    const Cell cell = map.cell_of(q);
    if (!map.contains(cell.x, cell.y)) {
      clear = false;  // beyond the window's distances: the exact test decides
      continue;
    }
    const std::size_t i = map.index(cell.x, cell.y);
    if (clear_within(q, i, cell, cover_radius_m_ + grow)) continue;
    clear = false;
    if (holds(pose, heading, map.nearest_obstacle(i), grow)) return FootprintTest::Collides;
  }
  return clear ? FootprintTest::Clear : FootprintTest::Unsure;
}

bool FootprintChecker::exact_test(const ClearanceWindow& map, const Pose2& pose, const Vec2& heading, double extra_m) const {
  const double grow = std::max(0.0, grow_m_ + extra_m + map.resolution() * std::sqrt(0.5));
  // Only the obstacle cells whose centres lie in a polygon holding the grown outline are tested:
  // row by row (in the window's cell coordinates, where a cell's centre is (ix + 0.5, iy + 0.5)),
  // the columns between the polygon's edges. The rectangle grown by `grow` on each side holds the
  // rounded one; the circle is cut exactly. A margin of 1e-6 cell keeps rounding on the safe side.
  constexpr double kMargin = 1e-6;
  const auto test = [&](const Vec2& o) { return holds(pose, heading, o, grow); };
  const double c = heading.x(), s = heading.y();
  const Vec2 centre(pose.x + c * model_.center_x_m, pose.y + s * model_.center_x_m);
  if (model_.circle) {
    const Vec2 q = map.continuous_cell(centre);
    const double rr = (model_.radius_m + grow) / map.resolution() + kMargin;
    const int y0 = static_cast<int>(std::ceil(q.y() - rr - 0.5)), y1 = static_cast<int>(std::floor(q.y() + rr - 0.5));
    for (int iy = y0; iy <= y1; ++iy) {
      const double dy = iy + 0.5 - q.y();
      const double half = std::sqrt(std::max(0.0, rr * rr - dy * dy));
      if (map.any_obstacle_in_row(iy, static_cast<int>(std::ceil(q.x() - half - 0.5)),
                                  static_cast<int>(std::floor(q.x() + half - 0.5)), test))
        return true;
    }
    return false;
  }
  const double hl = model_.half_length_m + grow, hw = model_.half_width_m + grow;
  Vec2 corner[4];
  const double u[4] = {hl, -hl, -hl, hl}, v[4] = {hw, hw, -hw, -hw};
  double ylo = kFootprintScanBig, yhi = -kFootprintScanBig;
  for (int k = 0; k < 4; ++k) {
    corner[k] = map.continuous_cell(Vec2(centre.x() + c * u[k] - s * v[k], centre.y() + s * u[k] + c * v[k]));
    ylo = std::min(ylo, corner[k].y());
    yhi = std::max(yhi, corner[k].y());
  }
  const int y0 = static_cast<int>(std::ceil(ylo - kMargin - 0.5)), y1 = static_cast<int>(std::floor(yhi + kMargin - 0.5));
  for (int iy = y0; iy <= y1; ++iy) {
    const double yc = iy + 0.5;
    double xlo = kFootprintScanBig, xhi = -kFootprintScanBig;
    for (int k = 0; k < 4; ++k) {
      const Vec2& a = corner[k];
      const Vec2& b = corner[(k + 1) % 4];
      const double lo = std::min(a.y(), b.y()) - kMargin, hi = std::max(a.y(), b.y()) + kMargin;
      if (yc < lo || yc > hi) continue;
      const double dy = b.y() - a.y();
      // An edge (nearly) along the row: both its ends; otherwise where it crosses the row.
      if (std::abs(dy) < kMargin) {
        xlo = std::min({xlo, a.x(), b.x()});
        xhi = std::max({xhi, a.x(), b.x()});
      } else {
        const double t = std::clamp((yc - a.y()) / dy, 0.0, 1.0);
        const double x = a.x() + t * (b.x() - a.x());
        xlo = std::min(xlo, x);
        xhi = std::max(xhi, x);
      }
    }
    if (xlo > xhi) continue;
    if (map.any_obstacle_in_row(iy, static_cast<int>(std::ceil(xlo - kMargin - 0.5)),
                                static_cast<int>(std::floor(xhi + kMargin - 0.5)), test))
      return true;
  }
  return false;
}

bool FootprintChecker::collides(const ClearanceWindow& map, const Pose2& pose, double extra_m) const {
  const Cell c = map.cell_of(pose.translation());
  if (!map.contains(c.x, c.y)) return true;
  const Vec2 heading(std::cos(pose.yaw), std::sin(pose.yaw));
  switch (quick_test(map, pose, heading, extra_m)) {
    case FootprintTest::Clear: return false;
    case FootprintTest::Collides: return true;
    case FootprintTest::Unsure: break;
  }
  return exact_test(map, pose, heading, extra_m);
}

bool FootprintChecker::collides_brute_force(const ClearanceWindow& map, const Pose2& pose, double extra_m) const {
  const Cell c = map.cell_of(pose.translation());
  if (!map.contains(c.x, c.y)) return true;
  const double grow = std::max(0.0, grow_m_ + extra_m + map.resolution() * std::sqrt(0.5));
  const Vec2 heading(std::cos(pose.yaw), std::sin(pose.yaw));
  bool hit = false;
  map.for_each_obstacle_near(pose.translation(), 1e9, [&](const Vec2& o) { hit = hit || holds(pose, heading, o, grow); });
  return hit;
}

FootprintMotionChecker::FootprintMotionChecker(const FootprintModel& model) : model_(model), checker_(model, 0.0) {}

double FootprintMotionChecker::reach_m(const BodyTwist& twist, double duration_s) const {
  return model_.bounding_radius_m() + std::hypot(twist.vx, twist.vy) * duration_s + 0.5;
}

bool FootprintMotionChecker::clear_in_window(const Pose2& pose, const BodyTwist& twist, double duration_s, double step_s) const {
  for (double s = step_s; s <= duration_s + 1e-9; s += step_s)
    if (checker_.collides(window_, advance_on_arc(pose, twist.vx, twist.vy, twist.wz, s))) return false;
  return true;
}

bool FootprintMotionChecker::clear(const ObstacleDistanceField& field, const Pose2& pose, const BodyTwist& twist, double duration_s,
                                   double step_s) const {
  window_.build(field, pose.translation(), reach_m(twist, duration_s), model_.bounding_radius_m() + 0.2);
  return clear_in_window(pose, twist, duration_s, step_s);
}

bool FootprintMotionChecker::clear(const OccupancyGrid& obstacles, const Pose2& pose, const BodyTwist& twist, double duration_s,
                                   double step_s) const {
  window_.build(obstacles, pose.translation(), reach_m(twist, duration_s), model_.bounding_radius_m() + 0.2);
  return clear_in_window(pose, twist, duration_s, step_s);
}

}  // namespace starnav
