// The toy controller straight_to_goal, chosen by name from a scenario: the worked example of
// adding a component (one file in src/starnav/control/, one line in the registry).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/registry/components.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

const std::string kOpenField = R"(
name: open_field
world:
  terrain:
    generate: {kind: flat, size_m: [8.0, 6.0], resolution_m: 0.05}
robot:
  drive: mecanum
  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 90.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 60.0}
navigation:
  goal: {x_m: 6.0, y_m: 4.0}
  controller: straight_to_goal
  straight_to_goal: {speed_mps: 0.3, tolerance_m: 0.1}
)";

TEST(StraightToGoal, ChosenByNameFromAScenarioItDrivesStraightToTheGoal) {
  const ScenarioSpec spec = parse_scenario(kOpenField, "open_field.yaml");
  NavigationRun run(spec);
  EXPECT_EQ(run.navigator().controller().name(), "straight_to_goal");
  run.run();
  const NavigationMetrics m = run.metrics();
  EXPECT_TRUE(m.success) << m.outcome << " " << m.reason;
  EXPECT_EQ(m.controller, "straight_to_goal");
  EXPECT_EQ(m.motion_mode, "none");
  // Closed form: it turns in place first (no distance), then drives the straight line, so the
  // distance driven is the start-goal distance less what the goal tolerance spares.
  const double straight = std::hypot(5.0, 3.0);
  EXPECT_NEAR(m.distance_m, straight, 0.15);
  EXPECT_LE(m.goal_distance_m, 0.15 + 1e-9);
  EXPECT_NE(navigation_metrics_json(run).find("\"controller\": \"straight_to_goal\""), std::string::npos);
}

TEST(StraightToGoal, ItsParametersAreValidatedWithFileLineAndKey) {
  std::string bad = kOpenField;
  bad.replace(bad.find("speed_mps: 0.3"), 14, "speed_mps: 0.0");
  try {
    NavigationRun run(parse_scenario(bad, "open_field.yaml"));
    FAIL() << "speed 0 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "open_field.yaml");
    EXPECT_EQ(e.field(), "navigation.straight_to_goal.speed_mps");
    EXPECT_EQ(e.line(), 15);
  }
  // motion_mode belongs to the path follower.
  std::string mode = kOpenField + "motion_mode: holonomic\n";
  EXPECT_EQ(test::error_of([&] { NavigationRun run(parse_scenario(mode, "open_field.yaml")); }).find("open_field.yaml:16: motion_mode"),
            0u);
}

TEST(StraightToGoal, ComputeTurnsFirstThenDrivesWithinTheLimits) {
  const auto c = find_local_controller("straight_to_goal").make({}, {});
  const Vec2 path[] = {Vec2(0.0, 0.0), Vec2(0.0, 2.0)};
  c->set_path(path);
  ControlInput in;
  in.goal = Vec2(0.0, 2.0);
  in.limits.max_yaw_rate_radps = 0.5;
  in.pose = Pose2(0.0, 0.0, 0.0);  // goal 90 degrees to the left: turn only
  ControlOutput out = c->compute(in);
  EXPECT_EQ(out.status, ControlStatus::Tracking);
  EXPECT_EQ(out.twist.vx, 0.0);
  EXPECT_DOUBLE_EQ(out.twist.wz, 0.5);  // clamped to the limit
  in.pose = Pose2(0.0, 0.0, kPi / 2 - 0.1);  // nearly facing it: drive
  out = c->compute(in);
  EXPECT_DOUBLE_EQ(out.twist.vx, 0.2);
  EXPECT_NEAR(out.twist.wz, 0.2, 1e-12);  // yaw_gain 2 x 0.1 rad
  in.pose = Pose2(0.0, 1.95, kPi / 2);
  EXPECT_EQ(c->compute(in).status, ControlStatus::Arrived);
}

}  // namespace
}  // namespace starnav
