// The indoor robot's whole stack (scenarios/ren_table4.yaml, shortened to one cycle): AMCL on EKF
// odometry, A* on the prior map with the sensed obstacles, DWA with the rectangular footprint;
// both arrivals within the Table 4 bounds, no collision; the scan placed by the estimate; the
// navigation section's new fields (goals, laps, goal headings, manual commands, the prior map)
// refused with the file, line and field when wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"
#include "harness/scenario_errors.hpp"

namespace starnav {
namespace {

const std::string kRenScenarios = std::string(STARNAV_SOURCE_DIR) + "/scenarios/";

TEST(RenStack, OneCycleBetweenTheTwoGoalPosesArrivesWithinTheTableFourBounds) {
  const std::vector<ScenarioOverride> o{parse_scenario_override("navigation.laps=1")};
  const ScenarioSpec spec = load_scenario(kRenScenarios + "ren_table4.yaml", o);
  NavigationRun run(spec);
  run.run();
  const NavigationMetrics m = run.metrics();
  EXPECT_TRUE(m.success) << m.outcome << " " << m.reason;
  EXPECT_EQ(m.controller, "dwa");
  EXPECT_EQ(m.collisions, 0);
  ASSERT_EQ(run.arrivals().size(), 2u);
  for (const NavArrival& a : run.arrivals()) {
    EXPECT_TRUE(a.has_yaw);
    EXPECT_LE(std::abs(a.error_x_m()), 0.08);
    EXPECT_LE(std::abs(a.error_y_m()), 0.08);
    EXPECT_LE(std::abs(rad_to_deg(a.error_yaw_rad())), 6.0);
    EXPECT_GE(a.settled_t_s, a.t_s);
  }
  EXPECT_EQ(run.arrivals()[0].goal, 0);
  EXPECT_EQ(run.arrivals()[1].goal, 1);
  // The planner saw the prior map: its first plan went round the room's walls, through the door.
  ASSERT_FALSE(run.navigator().plans().empty());
  EXPECT_GT(run.navigator().plans().front().cost_m, 8.0);
}

// A robot at 0.5 m/s with a wall 0.175 m ahead of its front: every DWA sample would touch the wall
// before the robot could stop, so the controller says blocked and the command is zero; the
// navigator asks for a new plan at once and, blocked for blocked_patience_s, starts a recovery
// whose first motion (turning in place) is clear.
TEST(RenStack, NoValidSampleGivesBlockedAZeroCommandAndARecovery) {
  RobotConfig robot;
  robot.actuator_lag_s = 0.05;
  NavigatorConfig c;
  c.geometry.resolution = 0.05;
  c.geometry.width = 200;
  c.geometry.height = 60;
  c.map.mode = NodeMapMode::Lidar2D;
  c.map.barrier_distance_m = 0.25;
  c.prior_obstacles.assign(c.geometry.cell_count(), 0);
  for (int y = 0; y < 48; ++y)  // a wall at x = 3.75-3.85 m from y = 0 to 2.4 m; open above
    for (int x = 75; x < 77; ++x) c.prior_obstacles[c.geometry.index(x, y)] = 1;
  NavigationComponents components;
  components.planner = {"astar", {}, "navigation.planner", 0, {}};
  components.controller = {"dwa", {}, "navigation.controller", 0, {}};
  components.goal_checker = {"latching", {}, "navigation.goal_checker", 0, {}};
  components.progress_checker = {"simple_progress", {}, "navigation.progress_checker", 0, {}};
  components.recoveries = {{"rotate", {}, "navigation.recoveries", 0, {}}, {"back_up", {}, "navigation.recoveries", 0, {}}};
  components.layers = {{"static_map", {}, "navigation.layers", 0, {}}, {"node_height", {}, "navigation.layers", 0, {}}};
  Navigator nav(c, robot, make_navigator_parts(components, c, robot), {9.0, 1.5});
  const Pose2 pose(3.3, 1.5, 0.0);
  nav.on_points(Vec3(3.4, 1.5, 0.4), {}, pose, 0.0);
  ASSERT_EQ(nav.status(), NavStatus::Navigating);
  bool recovered = false;
  for (int k = 0; k <= 150 && !recovered; ++k) {
    const double t = 0.01 * k;
    const BodyTwist cmd = nav.command(pose, t, {0.5, 0.0, 0.0});
    for (const NavEvent& e : nav.events()) recovered = recovered || (e.kind == "recovery" && e.detail == "controller_blocked");
    if (!recovered) {
      EXPECT_EQ(nav.control_status(), ControlStatus::Blocked) << t;
      EXPECT_EQ(cmd.vx, 0.0) << t;
      EXPECT_EQ(cmd.wz, 0.0) << t;
    } else {
      EXPECT_EQ(cmd.vx, 0.0);  // the recovery turns in place first
      EXPECT_NE(cmd.wz, 0.0);
    }
  }
  EXPECT_TRUE(recovered);
  // The next cycle plans again, asked for by the blocked controller.
  nav.on_points(Vec3(3.4, 1.5, 0.4), {}, pose, 1.6);
  bool replanned = false;
  for (const NavPlan& p : nav.plans()) replanned = replanned || p.cause == "controller_blocked";
  EXPECT_TRUE(replanned);
}

TEST(RenStack, ScansArePlacedWithThePoseTheRobotBelieves) {
  LidarScan scan;
  scan.sensor_pose.position = Vec3(1.1, 2.0, 0.4);
  scan.points_world = {Vec3(3.0, 2.0, 0.4), Vec3(1.0, 4.0, 0.2)};
  const Pose2 truth(1.0, 2.0, 0.0), estimate(1.5, 1.0, kPi / 2.0);
  const LidarScan placed = scan_placed_at(scan, truth, estimate);
  // A point 2 m ahead of the true pose is 2 m ahead of the estimate (which faces +y).
  EXPECT_NEAR(placed.points_world[0].x(), 1.5, 1e-12);
  EXPECT_NEAR(placed.points_world[0].y(), 3.0, 1e-12);
  EXPECT_NEAR(placed.points_world[0].z(), 0.4, 1e-12);
  // 2 m to the left of the truth is 2 m to the left of the estimate (-x).
  EXPECT_NEAR(placed.points_world[1].x(), -0.5, 1e-12);
  EXPECT_NEAR(placed.points_world[1].y(), 1.0, 1e-12);
  EXPECT_NEAR(placed.sensor_pose.position.x(), 1.5, 1e-12);
  EXPECT_NEAR(placed.sensor_pose.position.y(), 1.1, 1e-12);
  const Vec3 forward = placed.sensor_pose.orientation * Vec3::UnitX();
  EXPECT_NEAR(forward.y(), 1.0, 1e-12);
}

TEST(RenStack, NavigationGoalsAndManualCommandsAreCheckedWithTheirField) {
  const std::string head = R"(
world:
  terrain:
    generate: {kind: flat, size_m: [8.0, 5.0], resolution_m: 0.05}
robot:
  drive: mecanum
  start: {x_m: 1.0, y_m: 2.4, yaw_deg: 0.0}
sensors:
  lidar: {preset: hokuyo_utm30lx}
sim: {dt_s: 0.01, duration_s: 30.0}
navigation:
)";
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  goals: [{x_m: 6.0, y_m: 2.4}]\n", "navigation.goals");
  test::expect_scenario_error(head + "  goals: []\n", "navigation.goals");
  test::expect_scenario_error(head + "  goals: [{x_m: 6.0, y_m: 2.4, heading: 3}]\n", "navigation.goals[0].heading");
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  laps: 0\n", "navigation.laps");
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  manual: [{t_s: 1, duration_s: 2}, {t_s: 2, duration_s: 1}]\n",
               "navigation.manual[1]");
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  manual: [{t_s: 1, duration_s: 0}]\n", "navigation.manual[0].duration_s");
  // A heading the path follower cannot turn to; a prior map the scenario does not have.
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4, yaw_deg: 90}\n", "navigation.goal.yaw_deg", true);
  test::expect_scenario_error(head + "  goals: [{x_m: 6.0, y_m: 2.4}, {x_m: 2.0, y_m: 2.4, yaw_deg: 90}]\n", "navigation.goals[1].yaw_deg", true);
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  map: {prior: world}\n", "navigation.map.prior", true);
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  map: {prior: nonesuch.yaml}\n", "navigation.map.prior", true);
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  controller: dwa\n  dwa: {sim_step_s: 5}\n", "navigation.dwa.sim_step_s", true);
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  astar: {cost_radius_m: -1}\n", "navigation.astar.cost_radius_m", true);
  test::expect_scenario_error(head + "  goal: {x_m: 6.0, y_m: 2.4}\n  planner: jps\n  jps: {cost_radius_m: 1}\n", "navigation.jps.cost_radius_m", true);
}

}  // namespace
}  // namespace starnav
