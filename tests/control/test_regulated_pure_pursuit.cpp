// Regulated Pure Pursuit, found by its name in the registry, against the closed forms of its rules:
// the arc through the carrot (curvature 2 y / L^2), the speed scaled by the turning radius, by the
// nearest obstacle's distance and by the remaining path, rotation in place within the angular
// acceleration, a stop before an arc that would collide; then whole runs (E3, the indoor world of
// the Ren stack) and its diagnostics drawn by the generic picture writer.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "starnav/control/local_controller.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/local_planning_pictures.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/map/obstacle_distance_field.hpp"
#include "starnav/registry/components.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

std::unique_ptr<LocalController> rpp(std::vector<ParamSetting> settings = {}) {
  RobotConfig robot;
  robot.drive = DriveKind::Differential;
  return find_local_controller("regulated_pure_pursuit").make(LocalControllerContext{robot, "test.yaml", 0.05}, settings);
}

ParamSetting set(const std::string& key, const std::string& value) { return {key, value, "test.yaml", 1, "navigation.rpp." + key}; }

// A 20 m x 10 m map at 5 cm, obstacles where `blocked` says, and its distance field.
struct World {
  GridGeometry g{400, 200, 0.05, Pose2(-5.0, -5.0, 0.0)};
  std::vector<std::uint8_t> mask = std::vector<std::uint8_t>(g.cell_count(), 0);
  std::unique_ptr<ObstacleDistanceField> field;
  void block(double x0, double y0, double x1, double y1) {
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        const Vec2 c = g.cell_center({x, y});
        if (c.x() >= x0 && c.x() <= x1 && c.y() >= y0 && c.y() <= y1) mask[g.index(x, y)] = 1;
      }
  }
  const ObstacleDistanceField* distances() {
    field = std::make_unique<ObstacleDistanceField>(g, &mask, 2.0);
    return field.get();
  }
};

ControlInput input(const Pose2& pose, const Vec2& goal, const ObstacleDistanceField* clearance, double vx = 0.5, double wz = 0.0) {
  ControlInput in;
  in.pose = pose;
  in.velocity = {vx, 0.0, wz};
  in.clearance = clearance;
  in.footprint = {0.4, 0.3};
  in.limits = {1.0, 0.0, 2.0};
  in.goal = goal;
  in.goal_tolerance_m = 0.1;
  return in;
}

std::vector<Vec2> straight(double x0, double x1) {
  std::vector<Vec2> p;
  const int n = static_cast<int>(std::lround((x1 - x0) / 0.05));
  for (int i = 0; i <= n; ++i) p.emplace_back(x0 + (x1 - x0) * i / n, 0.0);
  return p;
}

TEST(RegulatedPurePursuit, FollowsTheArcThroughTheCarrot) {
  World w;
  auto c = rpp({set("use_cost_regulated_linear_velocity_scaling", "false")});
  c->set_path(straight(0.0, 10.0));
  // 0.2 m to the right of the path, heading along it: the carrot at 0.6 m lies at y = +0.2 in
  // base_link, x = sqrt(0.6^2 - 0.2^2); curvature 2 * 0.2 / 0.36.
  const ControlOutput out = c->compute(input(Pose2(2.0, -0.2, 0.0), {10.0, 0.0}, w.distances()));
  EXPECT_EQ(out.status, ControlStatus::Tracking);
  const double kappa = 2.0 * 0.2 / 0.36;
  // Radius 0.9 m: exactly the regulation's threshold, so the cruise speed.
  EXPECT_NEAR(out.twist.vx, 0.5, 1e-9);
  EXPECT_NEAR(out.twist.wz, 0.5 * kappa, 1e-9);
}

// A loop whose last leg runs back 1 cm beside its first: the robot's place is searched along the
// path only as far as max_robot_pose_search_dist_m, so it stays at the loop's start (cruise
// speed); with a search over the whole path it jumps to the last leg, 2 m from the end, and the
// approach slows it.
TEST(RegulatedPurePursuit, SearchesItsPlaceOnlyAsFarAlongThePathAsItsBound) {
  World w;
  const std::vector<Vec2> loop = {{0.0, 0.0}, {8.0, 0.0}, {8.0, 4.0}, {0.0, 4.0}, {0.0, 0.08}, {3.0, 0.08}};
  const auto speed = [&](std::vector<ParamSetting> settings) {
    settings.push_back(set("use_cost_regulated_linear_velocity_scaling", "false"));
    settings.push_back(set("approach_velocity_scaling_dist_m", "3"));
    auto c = rpp(settings);
    c->set_path(loop);
    return c->compute(input(Pose2(1.0, 0.07, 0.0), {3.0, 0.08}, w.distances())).twist.vx;
  };
  EXPECT_NEAR(speed({}), 0.5, 1e-3);
  EXPECT_LT(speed({set("max_robot_pose_search_dist_m", "100")}), 0.4);
}

TEST(RegulatedPurePursuit, SlowsOnTightCurvatureNearObstaclesAndOnTheApproach) {
  World w;
  w.block(2.0, 0.45, 12.0, 0.6);  // a wall 0.45 m to the left of the path
  auto c = rpp({set("lookahead_dist_m", "0.6"), set("regulated_linear_scaling_min_speed_mps", "0.01")});
  c->set_path(straight(0.0, 10.0));
  // On the path: curvature 0; from the robot's cell (centre y = 0.025) the wall's nearest cell
  // centre (y = 0.475) is 0.45 m away -> 0.5 x 0.45 / 0.6.
  const ControlOutput near_wall = c->compute(input(Pose2(5.0, 0.0, 0.0), {10.0, 0.0}, w.distances()));
  EXPECT_NEAR(near_wall.twist.vx, 0.5 * 0.45 / 0.6, 1e-6);
  // Tight curvature: 0.3 m off the path, no wall: radius L^2 / 2y = 0.6 -> 0.5 x 0.6 / 0.9.
  World open;
  auto c2 = rpp({set("use_cost_regulated_linear_velocity_scaling", "false")});
  c2->set_path(straight(0.0, 10.0));
  const ControlOutput tight = c2->compute(input(Pose2(2.0, -0.3, 0.0), {10.0, 0.0}, open.distances()));
  EXPECT_NEAR(tight.twist.vx, 0.5 * 0.6 / 0.9, 1e-9);
  // The approach: 0.3 m of path left, 0.6 m scaling distance -> half the speed.
  auto c3 = rpp({set("use_cost_regulated_linear_velocity_scaling", "false")});
  c3->set_path(straight(0.0, 10.0));
  const ControlOutput approach = c3->compute(input(Pose2(9.7, 0.0, 0.0), {10.0, 0.0}, open.distances()));
  EXPECT_NEAR(approach.twist.vx, 0.25, 1e-9);
}

TEST(RegulatedPurePursuit, RotatesInPlaceWithinItsAccelerationAndTurnsToTheGoalHeading) {
  World w;
  auto c = rpp();
  c->set_path(straight(0.0, 10.0));
  // Facing back along the path: rotate, from rest by at most 3.2 rad/s^2 x 0.05 s.
  const ControlOutput turn = c->compute(input(Pose2(2.0, 0.0, kPi), {10.0, 0.0}, w.distances(), 0.0, 0.0));
  EXPECT_EQ(turn.twist.vx, 0.0);
  EXPECT_NEAR(std::abs(turn.twist.wz), 3.2 * 0.05, 1e-9);
  // At the goal with a heading 90 deg off: rotate toward it (positive), then arrived when within.
  ControlInput at_goal = input(Pose2(10.0, 0.0, 0.0), {10.0, 0.0}, w.distances(), 0.0, 1.8);
  at_goal.goal_yaw = kPi / 2.0;
  at_goal.goal_yaw_tolerance_rad = deg_to_rad(5.0);
  EXPECT_NEAR(c->compute(at_goal).twist.wz, 1.8, 1e-9);
  at_goal.pose.yaw = kPi / 2.0 - deg_to_rad(2.0);
  EXPECT_EQ(c->compute(at_goal).status, ControlStatus::Arrived);
}

TEST(RegulatedPurePursuit, StopsBeforeAnArcThatWouldCollide) {
  World w;
  w.block(2.3, -1.0, 2.5, 1.0);  // a wall across the path, 0.3 m ahead of the robot's front (0.4 m long)
  auto c = rpp({set("regulated_linear_scaling_min_speed_mps", "0.5"), set("use_cost_regulated_linear_velocity_scaling", "false")});
  c->set_path(straight(0.0, 10.0));
  c->keep_diagnostics(true);
  const ControlOutput out = c->compute(input(Pose2(1.8, 0.0, 0.0), {10.0, 0.0}, w.distances()));
  EXPECT_EQ(out.status, ControlStatus::Blocked);
  EXPECT_EQ(out.twist.vx, 0.0);
  const std::optional<ControlDiagnostics> d = c->diagnostics();
  ASSERT_TRUE(d.has_value());
  ASSERT_EQ(d->candidates.size(), 1u);
  EXPECT_EQ(d->candidates[0].status, CandidateStatus::Collides);
  // Without the check it would drive on.
  auto blind = rpp({set("use_collision_detection", "false"), set("use_cost_regulated_linear_velocity_scaling", "false")});
  blind->set_path(straight(0.0, 10.0));
  EXPECT_GT(blind->compute(input(Pose2(1.8, 0.0, 0.0), {10.0, 0.0}, w.distances())).twist.vx, 0.0);
}

TEST(RegulatedPurePursuit, ParametersAreCheckedWithTheirField) {
  try {
    rpp({set("min_lookahead_dist_m", "2.0")});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "min_lookahead_dist_m") << e.what();
  }
  RobotConfig car;
  car.drive = DriveKind::Ackermann;
  EXPECT_THROW(find_local_controller("regulated_pure_pursuit").make(LocalControllerContext{car, "t.yaml", 0.05}, {}), Error);
}

// Whole runs: the E3 obstacles, and the indoor world of the Ren stack (AMCL on its map), reached
// without a collision; a step drawn by the generic controller picture.
TEST(RegulatedPurePursuit, NavigatesE3AndTheIndoorWorld) {
  for (const char* scenario : {"e3_three_obstacles.yaml", "ren_table4.yaml"}) {
    SCOPED_TRACE(scenario);
    std::vector<ScenarioOverride> overrides;
    if (std::string(scenario) == "ren_table4.yaml") overrides.push_back({"navigation.laps", "1"});
    NavigationOptions o;
    o.controller = "regulated_pure_pursuit";  // as --controller: the scenario's controller section stays unused
    o.record_steps = false;
    o.controller_snapshot_times_s = {3.0};
    NavigationRun run(load_scenario(test::scenario_path(scenario), overrides), o);
    run.run();
    const NavigationMetrics m = run.metrics();
    EXPECT_TRUE(m.success) << m.outcome << " " << m.reason;
    EXPECT_EQ(m.collisions, 0);
    EXPECT_EQ(m.controller, "regulated_pure_pursuit");
    ASSERT_EQ(run.controller_snapshots().size(), 1u);
    const std::string svg = controller_step_picture(run.controller_snapshots()[0], "rpp").svg_string();
    EXPECT_NE(svg.find("carrot"), std::string::npos);
  }
}

}  // namespace
}  // namespace starnav
