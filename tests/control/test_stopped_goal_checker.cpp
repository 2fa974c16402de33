// The stopped goal checker (Nav2's StoppedGoalChecker), found by its name in the registry: reached
// only within the tolerances and stopped; the position latches; a robot coasting through the goal
// has not reached it. And in a navigation run: the run ends with the robot stopped at the goal.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/control/goal_checker.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/registry/components.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

std::unique_ptr<GoalChecker> stopped(std::vector<ParamSetting> settings = {}) {
  return find_goal_checker("stopped").make(GoalCheckerContext{"test.yaml"}, settings);
}

GoalCheckInput at(double x, double vx, double wz, std::optional<double> goal_yaw = std::nullopt, double yaw = 0.0) {
  GoalCheckInput in;
  in.pose = Pose2(x, 0.0, yaw);
  in.velocity = BodyTwist{vx, 0.0, wz};
  in.goal = Vec2(1.0, 0.0);
  in.goal_yaw = goal_yaw;
  in.xy_tolerance_m = 0.1;
  in.yaw_tolerance_rad = deg_to_rad(5.0);
  return in;
}

TEST(StoppedGoalChecker, ReachedOnlyWithinTheTolerancesAndStopped) {
  struct Case {
    GoalCheckInput in;
    bool reached;
    const char* why;
  };
  const Case cases[] = {
      {at(1.05, 0.1, 0.1), true, "within and slow (limits 0.25 m/s, 0.25 rad/s)"},
      {at(1.05, 0.3, 0.0), false, "within but too fast"},
      {at(1.05, 0.0, 0.3), false, "within but turning too fast"},
      {at(1.05, 0.25, 0.25), true, "at the limits"},
      {at(1.2, 0.0, 0.0), false, "stopped outside the tolerance"},
      {at(1.05, 0.0, 0.0, 0.5, 0.0), false, "stopped, heading off"},
      {at(1.05, 0.0, 0.0, 0.5, 0.49), true, "stopped, heading within"},
  };
  for (const Case& c : cases) {
    auto g = stopped();
    EXPECT_EQ(g->reached(c.in), c.reached) << c.why;
  }
}

TEST(StoppedGoalChecker, ThePositionLatchesUntilReset) {
  auto g = stopped();
  EXPECT_FALSE(g->reached(at(1.0, 1.0, 0.0)));  // coasting through: not reached
  EXPECT_TRUE(g->position_reached());
  EXPECT_TRUE(g->reached(at(1.3, 0.0, 0.0)));  // stopped just past it: the position latched
  g->reset();
  EXPECT_FALSE(g->reached(at(1.3, 0.0, 0.0)));
  EXPECT_FALSE(g->position_reached());
}

TEST(StoppedGoalChecker, ParametersAreDeclaredAndChecked) {
  auto strict = stopped({{"trans_stopped_velocity_mps", "0.05", "test.yaml", 3, "navigation.stopped_goal_checker.trans_stopped_velocity_mps"},
                         {"rot_stopped_velocity_degps", "2", "test.yaml", 4, "navigation.stopped_goal_checker.rot_stopped_velocity_degps"}});
  EXPECT_FALSE(strict->reached(at(1.0, 0.1, 0.0)));
  EXPECT_FALSE(strict->reached(at(1.0, 0.0, deg_to_rad(3.0))));
  EXPECT_TRUE(strict->reached(at(1.0, 0.04, deg_to_rad(1.0))));
  try {
    stopped({{"trans_stopped_velocity_mps", "-1", "test.yaml", 3, "navigation.stopped_goal_checker.trans_stopped_velocity_mps"}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "navigation.stopped_goal_checker.trans_stopped_velocity_mps");
  }
}

TEST(StoppedGoalChecker, ARunEndsWithTheRobotStoppedAtTheGoal) {
  ScenarioSpec spec = load_scenario(test::scenario_path("e3_three_obstacles.yaml"), std::vector<ScenarioOverride>{
      {"navigation.goal_checker", "stopped"}, {"navigation.stopped_goal_checker.trans_stopped_velocity_mps", "0.02"}});
  NavigationOptions o;
  o.record_steps = false;
  NavigationRun run(spec, o);
  run.run();
  const NavigationMetrics m = run.metrics();
  ASSERT_TRUE(m.success) << m.outcome;
  EXPECT_EQ(m.collisions, 0);
  const BodyTwist last = run.simulation().trajectory().back().twist;
  EXPECT_LE(std::hypot(last.vx, last.vy), 0.02 + 1e-9);
  EXPECT_LE(m.goal_distance_m, run.navigator().config().goal_tolerance_m + 0.05);
}

}  // namespace
}  // namespace starnav
