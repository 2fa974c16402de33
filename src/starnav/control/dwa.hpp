#pragma once
// The Dynamic Window Approach (Fox, Burgard and Thrun 1997) for differential and holonomic bases,
// with Nav2 DWB's critics (docs/local_planning.md; docs/papers/ren2022.md).
//
// Per control step:
//   1. the dynamic window: per axis (vx, vy, wz) the velocities reachable from the current one
//      within one control period under the acceleration limits, inside the controller's and the
//      robot's limits; vx_samples x vy_samples x wz_samples velocities spread over it (zero
//      exactly where the window holds it), those beyond the wheels' speed limit dropped;
//   2. each sample rolled out at constant body velocity (the exact arc) for sim_time_s in steps of
//      sim_step_s, and tested against the local obstacle map with the robot's footprint out to
//      the time it needs to stop (one more control period, the actuator lag and braking at the
//      acceleration limits, on the same arc): a sample whose swept footprint touches an obstacle
//      is dropped, so every command the controller gives leaves room to stop;
//   3. the rest scored by named critics (dwa_critics.hpp), each a cost times its weight; the
//      cheapest is commanded. No valid sample: zero twist and status Blocked (the navigator
//      recovers). Near the goal (within the navigator's goal tolerance, ControlInput) it only
//      turns, to the goal's yaw when one is given, and reports Arrived when the yaw is within
//      its tolerance too.
// A Mecanum robot gets real sideways velocity: vy is sampled and scored like vx. Its alignment
// critics follow the direction of motion, and the path_angle critic turns its body along the path
// (its LiDAR sees ahead; a rectangular body passes doors straight), and within
// holonomic_approach_m of a goal with a heading toward that heading instead, so that it reaches
// such a goal by translating, already turned.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "starnav/map/footprint_checker.hpp"
#include "starnav/control/local_controller.hpp"
#include "starnav/core/params.hpp"
#include "starnav/robot/robot_model.hpp"

namespace starnav {

struct DwaConfig {
  int vx_samples = 15;
  int vy_samples = 9;  // a robot that cannot move sideways samples vy = 0 only
  int wz_samples = 15;
  double sim_time_s = 1.7;
  double sim_step_s = 0.05;
  double control_period_s = 0.05;
  double max_vx_mps = 0.5;
  double min_vx_mps = 0.0;  // < 0 allows driving backwards
  double max_vy_mps = 0.3;
  double max_speed_xy_mps = 0.5;
  double max_yaw_rate_radps = 1.0;
  double acc_x_mps2 = 1.0;
  double acc_y_mps2 = 1.0;
  double acc_yaw_radps2 = 2.0;
  std::string footprint = "rectangle";  // rectangle: the robot's body; circle: footprint_radius_m
  double footprint_radius_m = 0.0;      // circle; 0: the body's circumscribed radius
  double safety_margin_m = 0.02;
  double forward_point_m = 0.325;
  std::string align = "auto";  // heading | motion | auto (motion for a holonomic robot, heading otherwise)
  double holonomic_approach_m = 1.5;  // path_angle: within this of a goal with a heading, aim at that heading
  double window_m = 0.0;       // side of the local window; 0: what the rollouts need
  double inflation_radius_m = 0.55;
  double cost_scaling_per_m = 3.0;
  double oscillation_reset_m = 0.05;
  double oscillation_reset_rad = 0.2;
  // Critic weights (0 switches a critic off).
  double path_align_weight = 32.0;
  double path_dist_weight = 32.0;
  double goal_align_weight = 24.0;
  double goal_dist_weight = 24.0;
  double obstacle_weight = 1.0;
  double velocity_weight = 1.0;
  double twirling_weight = 1.0;
  double path_angle_weight = 8.0;
  double prefer_forward_weight = 5.0;
  double oscillation_weight = 100.0;
  double rotate_to_goal_weight = 32.0;
  // Throws Error naming the field.
  void validate() const;
};

const ParamTable<DwaConfig>& dwa_params();

// The velocities reachable within one control period, per axis [lo, hi].
struct DynamicWindow {
  double vx_lo = 0.0, vx_hi = 0.0;
  double vy_lo = 0.0, vy_hi = 0.0;
  double wz_lo = 0.0, wz_hi = 0.0;
};

// The axis limits DWA samples inside: the configuration's, cut to the robot's.
struct DwaLimits {
  double min_vx = 0.0, max_vx = 0.0, max_vy = 0.0, max_wz = 0.0, max_speed_xy = 0.0;
  double acc_x = 0.0, acc_y = 0.0, acc_yaw = 0.0;
};
DwaLimits dwa_limits(const DwaConfig& config, const VelocityLimits& robot, bool holonomic);

// Each axis: [v0 - a T, v0 + a T] clamped to the limits (a current velocity beyond a limit
// gives the limit itself).
DynamicWindow dynamic_window(const BodyTwist& current, const DwaLimits& limits, double period_s);

// `n` values spread evenly over [lo, hi] (ends included; one value: the one nearest zero), the
// one nearest zero replaced by zero when the interval holds it.
std::vector<double> window_samples(double lo, double hi, int n);

// Time over which a command must be collision-free: the scored horizon, or one control period
// plus the actuator lag plus half the braking time at the acceleration limits (the distance
// braking covers on the same arc), whichever is longer.
double dwa_check_time(const BodyTwist& twist, const DwaLimits& limits, double sim_time_s, double period_s, double lag_s);

// The poses of a constant body twist from `start` every `step_s`, n of them (the first one step
// after the start): the exact arc, composed step by step. With `headings`, also each pose's
// (cos yaw, sin yaw), turned step by step without trigonometry.
void dwa_rollout(const Pose2& start, const BodyTwist& twist, double step_s, int n, std::vector<Pose2>& out,
                 std::vector<Vec2>* headings = nullptr);

// What every critic sees in one control step.
struct DwaScene {
  const ClearanceWindow* map = nullptr;
  Pose2 pose;                       // the robot (map frame)
  BodyTwist velocity;               // its current body twist
  std::vector<Vec2> local_path;     // the path from the robot's projection on it to the local goal
  Vec2 local_goal = Vec2::Zero();   // where the path leaves the window (or the goal)
  bool local_goal_is_goal = false;
  // What the alignment critics measure against: the local path, and when it ends at the goal, the
  // path carried on past it by the forward point's distance along its last direction (a forward
  // point past the goal is where an aligned robot's would be), and that path's end.
  std::vector<Vec2> align_path;
  Vec2 align_goal = Vec2::Zero();
  Vec2 goal = Vec2::Zero();         // the path's end
  std::optional<double> goal_yaw;   // rad, when the goal has a heading
  double distance_to_goal_m = 0.0;
  bool in_goal_window = false;      // within the xy goal tolerance: only turning
  bool align_by_motion = false;     // alignment critics look along the motion, not the heading
  std::optional<double> path_heading;  // the heading path_angle aims at (rad), none: off
  std::vector<double> goal_distance;  // per window cell: wavefront distance to the local goal (m)
  std::vector<double> obstacle_cost;  // per window cell: proximity cost in [0, 1]
  DwaLimits limits;
  double period_s = 0.05;
  double pass_clearance_m = 0.0;    // the wavefront's passability
};

// One rolled-out sample as the critics score it.
struct DwaRollout {
  BodyTwist twist;
  std::span<const Pose2> poses;  // at sim_step_s, 2 sim_step_s, ..., sim_time_s
};

// One sample of the last control step (for pictures and tests).
struct DwaSample {
  BodyTwist twist;
  bool valid = false;     // collision-free and accepted by every critic
  bool collides = false;  // its swept footprint touches an obstacle before it could stop
  double cost = 0.0;      // weighted sum of the critics (valid samples)
  Pose2 end;              // the rollout's pose at sim_time_s
};

}  // namespace starnav
