// The goal checker the navigation loop has always had: the position is reached within the xy
// tolerance (with a goal heading, only once the robot is slow there: passing through is not
// reaching) and then, as Nav2's stateful checker, stays reached while the robot turns (unless
// `stateful` is false); the goal is reached when the heading, if any, is within its tolerance too.
#include <cmath>

#include "starnav/control/goal_checker.hpp"
#include "starnav/core/angle.hpp"

namespace starnav {

namespace {

struct LatchingGoalCheckerConfig {
  double latch_speed_mps = 0.05;
  bool stateful = true;
};

const ParamTable<LatchingGoalCheckerConfig>& latching_goal_checker_params() {
  static const ParamTable<LatchingGoalCheckerConfig> table = [] {
    using C = LatchingGoalCheckerConfig;
    ParamTable<C> t;
    t.real("latch_speed_mps", &C::latch_speed_mps, non_negative(), "m/s",
           "with a goal heading, the position counts as reached only at or below this speed");
    t.boolean("stateful", &C::stateful,
              "the reached position stays reached while the robot turns to the goal heading (Nav2's); false: the "
              "position must hold when the heading does (a car turns its heading by driving, and may leave it)");
    return t;
  }();
  return table;
}

class LatchingGoalChecker final : public GoalChecker {
 public:
  explicit LatchingGoalChecker(const LatchingGoalCheckerConfig& c) : c_(c) {}
  std::string_view name() const override { return "latching"; }
  void reset() override { position_reached_ = false; }
  bool reached(const GoalCheckInput& in) override {
    const bool heading_ok = !in.goal_yaw || std::abs(wrap_angle(*in.goal_yaw - in.pose.yaw)) <= in.yaw_tolerance_rad;
    const bool within = (in.pose.translation() - in.goal).norm() <= in.xy_tolerance_m;
    if (!c_.stateful) position_reached_ = false;
    if (within && (!in.goal_yaw || std::hypot(in.velocity.vx, in.velocity.vy) <= c_.latch_speed_mps)) position_reached_ = true;
    return position_reached_ && heading_ok;
  }
  bool position_reached() const override { return position_reached_; }

 private:
  LatchingGoalCheckerConfig c_;
  bool position_reached_ = false;
};

}  // namespace

GoalCheckerDef latching_goal_checker() {
  GoalCheckerDef d;
  d.info.role = Role::GoalChecker;
  d.info.name = "latching";
  d.info.section = "latching_goal_checker";
  d.info.summary = "Reached within the navigation's tolerances; with a heading, the position latches once the robot is slow there";
  d.info.nav2_counterpart = "nav2_controller::SimpleGoalChecker";
  d.info.params = latching_goal_checker_params().specs();
  d.make = [](const GoalCheckerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<GoalChecker> {
    return std::make_unique<LatchingGoalChecker>(configured(latching_goal_checker_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
