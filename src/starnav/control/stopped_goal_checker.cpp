// Nav2's StoppedGoalChecker: the goal is reached when the robot is within the navigation's
// tolerances (the position latches, as in Nav2's stateful SimpleGoalChecker, so a robot turning to
// the goal heading may drift out a little) and it has stopped: its translational speed and its yaw
// rate at or below their limits. A robot that coasts through the goal has not reached it.
#include <cmath>

#include "starnav/control/goal_checker.hpp"
#include "starnav/core/angle.hpp"

namespace starnav {

namespace {

struct StoppedGoalCheckerConfig {
  double trans_stopped_velocity_mps = 0.25;  // Nav2's defaults
  double rot_stopped_velocity_radps = 0.25;
};

const ParamTable<StoppedGoalCheckerConfig>& stopped_goal_checker_params() {
  static const ParamTable<StoppedGoalCheckerConfig> table = [] {
    using C = StoppedGoalCheckerConfig;
    ParamTable<C> t;
    t.real("trans_stopped_velocity_mps", &C::trans_stopped_velocity_mps, non_negative(), "m/s",
           "the goal counts as reached only at or below this speed (|(vx, vy)|)");
    t.real("rot_stopped_velocity_degps", &C::rot_stopped_velocity_radps, non_negative(), "deg/s",
           "... and at or below this yaw rate", kPi / 180.0);
    return t;
  }();
  return table;
}

class StoppedGoalChecker final : public GoalChecker {
 public:
  explicit StoppedGoalChecker(const StoppedGoalCheckerConfig& c) : c_(c) {}
  std::string_view name() const override { return "stopped"; }
  void reset() override { position_reached_ = false; }
  bool reached(const GoalCheckInput& in) override {
    if ((in.pose.translation() - in.goal).norm() <= in.xy_tolerance_m) position_reached_ = true;
    if (!position_reached_) return false;
    if (in.goal_yaw && std::abs(wrap_angle(*in.goal_yaw - in.pose.yaw)) > in.yaw_tolerance_rad) return false;
    return std::hypot(in.velocity.vx, in.velocity.vy) <= c_.trans_stopped_velocity_mps &&
           std::abs(in.velocity.wz) <= c_.rot_stopped_velocity_radps;
  }
  bool position_reached() const override { return position_reached_; }

 private:
  StoppedGoalCheckerConfig c_;
  bool position_reached_ = false;
};

}  // namespace

GoalCheckerDef stopped_goal_checker() {
  GoalCheckerDef d;
  d.info.role = Role::GoalChecker;
  d.info.name = "stopped";
  d.info.section = "stopped_goal_checker";
  d.info.summary = "Nav2's StoppedGoalChecker: within the tolerances (the position latches) and stopped (speed and yaw rate limits)";
  d.info.nav2_counterpart = "nav2_controller::StoppedGoalChecker";
  d.info.params = stopped_goal_checker_params().specs();
  d.make = [](const GoalCheckerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<GoalChecker> {
    return std::make_unique<StoppedGoalChecker>(configured(stopped_goal_checker_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
