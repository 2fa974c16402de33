// The latching goal checker (the navigation's default), found by its name in the registry: with a
// goal heading the position latches once the robot is slow within the tolerance and then holds
// while the heading turns (Nav2's stateful checker); not stateful, the position must hold when the
// heading does (a car turning its heading by driving).
#include <gtest/gtest.h>

#include <optional>

#include "starnav/control/goal_checker.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {
namespace {

std::unique_ptr<GoalChecker> latching_checker(std::vector<ParamSetting> settings = {}) {
  return find_goal_checker("latching").make(GoalCheckerContext{"test.yaml"}, settings);
}

// The goal at (1, 0) facing +x, tolerances 0.1 m and 5 deg; the robot at (x, 0) with yaw `yaw`.
GoalCheckInput robot_at(double x, double vx, double yaw) {
  GoalCheckInput in;
  in.pose = Pose2(x, 0.0, yaw);
  in.velocity = BodyTwist{vx, 0.0, 0.0};
  in.goal = Vec2(1.0, 0.0);
  in.goal_yaw = 0.0;
  in.xy_tolerance_m = 0.1;
  in.yaw_tolerance_rad = deg_to_rad(5.0);
  return in;
}

TEST(LatchingGoalChecker, ThePositionLatchesWhenSlowAndHoldsWhileTheHeadingTurns) {
  auto g = latching_checker();
  EXPECT_FALSE(g->reached(robot_at(1.05, 0.2, 0.5)));  // within, too fast: not latched
  EXPECT_FALSE(g->position_reached());
  EXPECT_FALSE(g->reached(robot_at(1.05, 0.0, 0.5)));  // within and slow: latched, heading off
  EXPECT_TRUE(g->position_reached());
  EXPECT_TRUE(g->reached(robot_at(1.5, 0.0, 0.01)));  // far off, heading within: the latch holds (Nav2)
}

TEST(LatchingGoalChecker, NotStatefulThePositionMustHoldWithTheHeading) {
  auto g = latching_checker({{"stateful", "false", "test.yaml", 3, "navigation.latching_goal_checker.stateful"}});
  EXPECT_FALSE(g->reached(robot_at(1.05, 0.0, 0.5)));  // within and slow, heading off
  EXPECT_TRUE(g->position_reached());
  EXPECT_FALSE(g->reached(robot_at(1.11, 0.0, 0.01)));  // heading within, but 0.11 m off
  EXPECT_FALSE(g->position_reached());
  EXPECT_FALSE(g->reached(robot_at(1.08, 0.2, 0.01)));  // within, heading within, too fast
  EXPECT_TRUE(g->reached(robot_at(1.08, 0.0, 0.01)));   // within, slow, heading within
}

}  // namespace
}  // namespace starnav
