#pragma once
// The MPPI controller's critics, one small class each as Nav2's MPPI has them (docs/local_planning.md,
// "MPPI"). Each adds its cost to every sample of a batch at once: the term below (a mean or sum over
// the sample's steps, >= 0), times its weight, to the power cost_power: (weight * term)^power. A
// critic whose condition does not hold at this step adds nothing. Distances in metres, angles in
// radians; "the goal" is the path's end, "near" compares the robot's distance to it with the
// critic's threshold_to_consider_m (for path_align, path_follow, path_angle and prefer_forward on
// a path of poses: the length of the stretch left, MppiScene::path_left_m).
//
//   constraint      sum over steps of dt x the speed beyond [vx_min, vx_max] (omni: the signed
//                   speed |(vx, vy)| beyond the combined bounds; Ackermann: also R_min - |vx / wz|
//                   where positive)
//   goal            near the goal: mean distance of the poses to the goal
//   goal_angle      near the goal, with a goal heading: mean |yaw - goal yaw|
//   path_align      away from the goal, once the batch reaches offset_from_furthest path points:
//                   mean distance of every trajectory_point_step-th pose to the path point as far
//                   along the path (from the robot's place on it) as the pose is along its
//                   trajectory (from the robot; the chords between the poses compared) (free path points only; off
//                   when more than max_path_occupancy_ratio of the path is blocked)
//   path_follow     away from the goal: distance of the last pose to the first free path point
//                   offset_from_furthest beyond the furthest point the batch reaches
//   path_angle      away from the goal, when the robot's heading is more than max_angle_to_furthest
//                   off the direction to the path point offset_from_furthest beyond the furthest
//                   reached: mean |yaw - direction from the pose to that point| (mode 1: the
//                   smaller of that and its reverse)
//   prefer_forward  away from the goal: sum over steps of dt x max(-vx, 0)
//   obstacles       per sample: critical_weight x (collision_cost if a pose collides (the inscribed
//                   circle on an obstacle, or with consider_footprint the footprint), else the sum
//                   of (collision_margin_distance - gap) over the poses up to it whose gap (distance
//                   to the nearest obstacle less the inscribed radius) is below the margin), plus
//                   (away from near_goal_distance) repulsion_weight x the sum over those poses of
//                   (inflation_radius - distance) within the inflation radius / time_steps; the
//                   whole to the power cost_power (its weight is 1). Every sample colliding marks
//                   the batch failed.
//   twirling        away from the goal (its tolerance): mean |wz|
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "starnav/control/mppi_optimizer.hpp"
#include "starnav/map/clearance_window.hpp"
#include "starnav/map/footprint_checker.hpp"

namespace starnav {

// What the critics see at one evaluation of a batch.
struct MppiScene {
  Pose2 pose;                  // the robot (map frame)
  Vec2 goal = Vec2::Zero();    // the path's end
  std::optional<double> goal_yaw;
  double goal_tolerance_m = 0.05;  // the navigator's goal check
  double model_dt_s = 0.05;
  MppiLimits limits;
  const MppiControls* controls = nullptr;          // the velocities of every step (after the limits)
  const MppiTrajectories* trajectories = nullptr;  // the poses after every step
  // The path ahead of the robot, from its place on the path, resampled every map cell, up to
  // prune_distance_m; and whether each point is free (the inscribed circle clear of obstacles).
  std::vector<Vec2> path;
  std::vector<std::uint8_t> path_free;
  bool reversing = false;      // the path ahead is driven in reverse (a planner's reverse stretch)
  // The window of obstacles around the robot the batch reaches (its clearance per cell), and the
  // footprint on it.
  const ClearanceWindow* map = nullptr;
  const FootprintChecker* footprint = nullptr;
  double inscribed_radius_m = 0.0;
  double circumscribed_radius_m = 0.0;

  // A path of poses (a planner's, cut at its cusps): the length of the stretch left from the
  // robot's place on it. Its path critics are switched by this length instead of the distance to
  // the goal, and path_align's offset_from_furthest is at most the points left: a stretch is often
  // shorter than Nav2's thresholds, tuned for long paths, and a car must follow it to its end.
  std::optional<double> path_left_m;

  double distance_to_goal_m() const { return (pose.translation() - goal).norm(); }
  // What the path critics' threshold_to_consider_m is compared with.
  double path_gate_m() const { return path_left_m ? *path_left_m : distance_to_goal_m(); }
  // The largest over the samples of the index of the path point nearest the sample's last pose
  // (Nav2's furthest reached path point); computed once per batch.
  std::size_t furthest_reached() const;
  // The clearance (m) at a world point: the distance from its cell's centre to the nearest
  // obstacle cell's centre; 0 outside the window. Valid after prepare_map().
  float clearance_at(float x, float y) const {
    const float dx = x - origin_x_, dy = y - origin_y_;
    const float gx = (cos_ * dx + sin_ * dy) * inv_resolution_, gy = (-sin_ * dx + cos_ * dy) * inv_resolution_;
    // In the window (NaN fails both tests too).
    if (!(gx >= 0.0f && gy >= 0.0f && gx < width_ && gy < height_)) return 0.0f;
    return clearance_[static_cast<std::size_t>(gy) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(gx)];
  }
  // The window's clearances in single precision for clearance_at (once `map` is set).
  void prepare_map();

  mutable std::optional<std::size_t> furthest_cache;

 private:
  std::vector<float> clearance_;
  float origin_x_ = 0.0f, origin_y_ = 0.0f, cos_ = 1.0f, sin_ = 0.0f, inv_resolution_ = 1.0f, width_ = 0.0f, height_ = 0.0f;
};

// What a batch's critics produce.
struct MppiCosts {
  Eigen::ArrayXf total;     // per sample
  bool failed = false;      // every sample collides
};

class MppiCritic {
 public:
  MppiCritic(double weight, int power) : weight_(weight), power_(power) {}
  virtual ~MppiCritic() = default;
  virtual std::string_view name() const = 0;
  double weight() const { return weight_; }
  int power() const { return power_; }
  virtual void score(const MppiScene& scene, MppiCosts& costs) const = 0;

 protected:
  // costs += (weight * term)^power.
  void add(const Eigen::ArrayXf& term, MppiCosts& costs) const;

 private:
  double weight_;
  int power_;
};

class MppiConstraintCritic final : public MppiCritic {
 public:
  using MppiCritic::MppiCritic;
  std::string_view name() const override { return "constraint"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;
};

// The critics gated by the distance to the goal: active near it (goal, goal_angle) or away from it.
class MppiGoalCritic final : public MppiCritic {
 public:
  MppiGoalCritic(double weight, int power, double threshold_m) : MppiCritic(weight, power), threshold_m_(threshold_m) {}
  std::string_view name() const override { return "goal"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;

 private:
  double threshold_m_;
};

class MppiGoalAngleCritic final : public MppiCritic {
 public:
  MppiGoalAngleCritic(double weight, int power, double threshold_m) : MppiCritic(weight, power), threshold_m_(threshold_m) {}
  std::string_view name() const override { return "goal_angle"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;

 private:
  double threshold_m_;
};

struct MppiPathAlignOptions {
  double threshold_m = 0.5;
  int offset_from_furthest = 20;
  double max_path_occupancy_ratio = 0.07;
  int trajectory_point_step = 4;
};
class MppiPathAlignCritic final : public MppiCritic {
 public:
  MppiPathAlignCritic(double weight, int power, const MppiPathAlignOptions& o) : MppiCritic(weight, power), o_(o) {}
  std::string_view name() const override { return "path_align"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;

 private:
  MppiPathAlignOptions o_;
};

class MppiPathFollowCritic final : public MppiCritic {
 public:
  MppiPathFollowCritic(double weight, int power, double threshold_m, int offset)
      : MppiCritic(weight, power), threshold_m_(threshold_m), offset_(offset) {}
  std::string_view name() const override { return "path_follow"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;

 private:
  double threshold_m_;
  int offset_;
};

class MppiPathAngleCritic final : public MppiCritic {
 public:
  MppiPathAngleCritic(double weight, int power, double threshold_m, int offset, double max_angle_rad, int mode)
      : MppiCritic(weight, power), threshold_m_(threshold_m), offset_(offset), max_angle_rad_(max_angle_rad), mode_(mode) {}
  std::string_view name() const override { return "path_angle"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;

 private:
  double threshold_m_;
  int offset_;
  double max_angle_rad_;
  int mode_;  // 0: forward preference, 1: no directional preference
};

class MppiPreferForwardCritic final : public MppiCritic {
 public:
  MppiPreferForwardCritic(double weight, int power, double threshold_m) : MppiCritic(weight, power), threshold_m_(threshold_m) {}
  std::string_view name() const override { return "prefer_forward"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;

 private:
  double threshold_m_;
};

struct MppiObstaclesOptions {
  double critical_weight = 20.0;
  double repulsion_weight = 1.5;
  int power = 1;
  bool consider_footprint = false;
  double collision_cost = 100000.0;
  double collision_margin_distance_m = 0.10;
  double near_goal_distance_m = 0.5;
  double inflation_radius_m = 0.55;
};
class MppiObstaclesCritic final : public MppiCritic {
 public:
  explicit MppiObstaclesCritic(const MppiObstaclesOptions& o) : MppiCritic(1.0, o.power), o_(o) {}
  std::string_view name() const override { return "obstacles"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;
  // Whether the robot at this pose collides, by the critic's rule (clearance: at its centre).
  bool collides(const MppiScene& scene, const Pose2& pose, float clearance) const;

 private:
  MppiObstaclesOptions o_;
};

class MppiTwirlingCritic final : public MppiCritic {
 public:
  using MppiCritic::MppiCritic;
  std::string_view name() const override { return "twirling"; }
  void score(const MppiScene& scene, MppiCosts& costs) const override;
};

// The shortest signed angle from b to a, elementwise, in (-pi, pi].
Eigen::ArrayXXf mppi_angle_difference(const Eigen::ArrayXXf& a, const Eigen::ArrayXXf& b);

}  // namespace starnav
