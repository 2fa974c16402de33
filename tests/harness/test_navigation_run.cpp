// Navigation scenarios end to end (simulator + navigator): the paper's E3 in both motion modes
// and E4 reach the goal without a collision; at every plan of a D* Lite run its cost equals an A*
// search run here on the same map; E4 leaves its dead end; an enclosed goal ends the run with
// no_path before the timeout; same seed, same bytes; the navigation section's errors name the
// file, line and field; a controller given in the options drives instead of the named one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/sim/scenario.hpp"
#include "harness/scenario_errors.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

const std::string kScenarios = std::string(STARNAV_SOURCE_DIR) + "/scenarios/";

// Checks every plan against A* run here on the navigator's map from the plan's start cell.
void check_plans_against_astar(NavigationRun& run, int& checked) {
  run.navigator().on_plan = [&checked](const Navigator& nav, const NavPlan& p) {
    if (p.status != "found") return;
    GridPlannerOptions o;
    o.unknown_is_free = true;
    const auto astar = make_grid_planner("astar", nav.map().occupancy(), o);
    const PlanResult ref = astar->plan(p.cells[p.escape_cells], *nav.map().geometry().world_to_cell(nav.goal()));
    ASSERT_TRUE(ref.found()) << "plan " << p.id;
    EXPECT_NEAR(p.cost_m, ref.cost, 1e-9) << "plan " << p.id;
    ++checked;
  };
}

TEST(NavigationRun, E3BothMotionModesReachTheGoalAndDStarLiteMatchesAStarAtEveryPlan) {
  const ScenarioSpec spec = load_scenario(kScenarios + "e3_three_obstacles.yaml");
  for (const char* mode : {"turn_then_drive", "holonomic"}) {
    NavigationOptions o;
    o.motion_mode = mode;
    o.planner = "dstar_lite";
    o.compare_astar = true;
    o.record_steps = false;
    NavigationRun run(spec, o);
    int checked = 0;
    check_plans_against_astar(run, checked);
    run.run();
    const NavigationMetrics m = run.metrics();
    EXPECT_TRUE(m.success) << mode << ": " << m.outcome;
    EXPECT_EQ(m.collisions, 0) << mode;
    EXPECT_EQ(m.motion_mode, mode);
    EXPECT_TRUE(m.costs_match) << mode;
    EXPECT_GE(m.replans, 1) << mode;
    EXPECT_EQ(checked, m.plans) << mode;
    EXPECT_LE(m.goal_distance_m, run.navigator().config().goal_tolerance_m + 1e-9);
    // Both modes track their paths closely on flat ground (docs/navigation.md).
    EXPECT_LT(m.deviation_max_m, 0.1) << mode;
  }
}

TEST(NavigationRun, E4LeavesTheDeadEndAndReachesTheGoal) {
  const ScenarioSpec spec = load_scenario(kScenarios + "e4_dynamic_dead_end.yaml");
  NavigationOptions o;
  o.record_steps = false;
  NavigationRun run(spec, o);
  run.run();
  const NavigationMetrics m = run.metrics();
  EXPECT_TRUE(m.success) << m.outcome;
  EXPECT_EQ(m.collisions, 0);
  EXPECT_GE(m.replans, 3);
  // In the pocket (between SO2 and SO3, x > 7.5 m), later back out west of it (x < 7 m), then at the goal.
  bool inside = false, left = false;
  for (const TrajectorySample& s : run.simulation().trajectory()) {
    const double x = s.position.x(), y = s.position.y();
    if (!inside && x > 7.5 && x < 12.0 && y > 8.4 && y < 11.6) inside = true;
    if (inside && x < 7.0) left = true;
  }
  EXPECT_TRUE(inside);
  EXPECT_TRUE(left);
}

// Every drive on the same small scene: Ackermann follows the line-of-sight-smoothed path with
// pure pursuit (it can neither turn in place nor take grid corners), differential turns then drives.
TEST(NavigationRun, AckermannAndDifferentialRobotsReachTheGoal) {
  for (const char* drive : {"ackermann", "differential"}) {
    const std::string yaml = std::string(R"(
name: drives
world:
  terrain:
    generate: {kind: flat, size_m: [12.0, 8.0], resolution_m: 0.05}
  obstacles:
    - {name: box, kind: box, position_m: [6.0, 4.3], size_m: [1.0, 1.5, 0.5]}
robot:
  drive: )") + drive + R"(
  start: {x_m: 1.0, y_m: 4.0, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 120.0, seed: 1}
navigation:
  goal: {x_m: 11.0, y_m: 4.0}
)";
    NavigationRun run(parse_scenario(yaml, "drives.yaml"));
    run.run();
    const NavigationMetrics m = run.metrics();
    EXPECT_TRUE(m.success) << drive << ": " << m.outcome;
    EXPECT_EQ(m.collisions, 0) << drive;
    EXPECT_EQ(m.motion_mode, std::string(drive) == "ackermann" ? "pure_pursuit" : "turn_then_drive");
    ASSERT_GE(m.plans, 2) << drive;  // the box is seen and planned round
    if (std::string(drive) == "ackermann") {
      // Line-of-sight smoothed: a few vertices per plan round one box, not the grid's corners.
      for (const NavPlan& p : run.navigator().plans()) EXPECT_LE(p.points.size(), 4u) << "plan " << p.id;
    }
  }
}

// A controller handed in by whoever runs the scenario (what the Python bindings do): straight at
// the goal, counting its calls.
class GivenController final : public LocalController {
 public:
  explicit GivenController(int* calls) : calls_(calls) {}
  std::string_view name() const override { return "given"; }
  void set_path(std::span<const Vec2> points) override { path_.assign(points.begin(), points.end()); }
  void clear() override { path_.clear(); }
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return path_; }
  double control_period_s() const override { return 0.1; }
  ControlOutput compute(const ControlInput& in) override {
    ++*calls_;
    const Vec2 to = in.goal - in.pose.translation();
    const double bearing = std::atan2(std::sin(std::atan2(to.y(), to.x()) - in.pose.yaw), std::cos(std::atan2(to.y(), to.x()) - in.pose.yaw));
    return {{std::abs(bearing) < 0.3 ? 0.3 : 0.0, 0.0, std::clamp(2.0 * bearing, -1.0, 1.0)}, ControlStatus::Tracking};
  }

 private:
  int* calls_;
  std::vector<Vec2> path_;
};

TEST(NavigationRun, AControllerGivenInTheOptionsDrivesInsteadOfTheNamedOne) {
  const char* yaml = R"(
name: given
world:
  terrain:
    generate: {kind: flat, size_m: [6.0, 4.0], resolution_m: 0.05}
robot:
  drive: differential
  start: {x_m: 1.0, y_m: 2.0, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.02, duration_s: 30.0, seed: 1}
navigation:
  goal: {x_m: 4.0, y_m: 3.0}
)";
  int calls = 0;
  NavigationOptions o;
  o.record_steps = false;
  o.make_controller = [&calls](const LocalControllerContext& ctx) -> std::unique_ptr<LocalController> {
    EXPECT_EQ(ctx.file, "given.yaml");
    EXPECT_EQ(ctx.map_resolution_m, 0.1);
    return std::make_unique<GivenController>(&calls);
  };
  NavigationRun run(parse_scenario(yaml, "given.yaml"), o);
  EXPECT_EQ(run.navigator().controller().name(), "given");
  run.run();
  const NavigationMetrics m = run.metrics();
  EXPECT_TRUE(m.success) << m.outcome;
  EXPECT_EQ(m.controller, "given");
  // Asked once per its control period (0.1 s: every fifth step) while it navigated.
  const double steps = m.duration_s / 0.02;
  EXPECT_GT(calls, 20);
  EXPECT_NEAR(calls, steps / 5.0, 2.0);
  // A goal heading needs a controller that declares it can turn to one.
  const std::string with_heading = std::string(yaml).replace(std::string(yaml).find("y_m: 3.0}"), 9, "y_m: 3.0, yaw_deg: 90.0}");
  try {
    NavigationRun refused(parse_scenario(with_heading, "given.yaml"), o);
    FAIL() << "a goal heading was accepted for a controller that cannot turn to one";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "given.yaml") << e.what();
    EXPECT_GT(e.line(), 0) << e.what();
    EXPECT_NE(std::string(e.what()).find("the given controller cannot turn to a goal heading"), std::string::npos) << e.what();
  }
  o.controller_capabilities = Capabilities{Capability::GoalHeading};
  NavigationRun accepted(parse_scenario(with_heading, "given.yaml"), o);
  EXPECT_EQ(accepted.navigator().controller().name(), "given");
}

const char* kEnclosedGoal = R"(
name: enclosed_goal
world:
  terrain:
    generate: {kind: flat, size_m: [8.0, 5.0], resolution_m: 0.05}
  obstacles:
    - {name: south, kind: box, position_m: [6.0, 1.4], size_m: [1.6, 0.2, 0.5]}
    - {name: north, kind: box, position_m: [6.0, 3.4], size_m: [1.6, 0.2, 0.5]}
    - {name: west, kind: box, position_m: [5.3, 2.4], size_m: [0.2, 1.8, 0.5]}
    - {name: east, kind: box, position_m: [6.7, 2.4], size_m: [0.2, 1.8, 0.5]}
robot:
  start: {x_m: 1.0, y_m: 2.4, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 300.0, seed: 3}
navigation:
  goal: {x_m: 6.0, y_m: 2.4}
  map: {resolution_m: 0.1}
)";

TEST(NavigationRun, EnclosedGoalEndsWithNoPathBeforeTheTimeout) {
  const ScenarioSpec spec = parse_scenario(kEnclosedGoal, "enclosed_goal.yaml");
  NavigationRun run(spec);
  run.run();
  const NavigationMetrics m = run.metrics();
  EXPECT_FALSE(m.success);
  EXPECT_EQ(m.outcome, "no_path");
  EXPECT_FALSE(m.reason.empty());
  EXPECT_LT(m.duration_s, 300.0);  // stopped when it knew, not at the timeout
  EXPECT_EQ(m.collisions, 0);
  const auto& plans = run.navigator().plans();
  ASSERT_FALSE(plans.empty());
  EXPECT_NE(plans.back().status, "found");
  for (std::size_t i = 0; i + 1 < plans.size(); ++i) EXPECT_EQ(plans[i].status, "found");
}

TEST(NavigationRun, SameSeedSameBytes) {
  ScenarioSpec spec = parse_scenario(kEnclosedGoal, "enclosed_goal.yaml");
  spec.duration_s = 20.0;
  std::string first;
  for (int k = 0; k < 2; ++k) {
    NavigationRun run(spec);
    run.run();
    const std::string all = paths_csv(run) + trajectory_csv(run.simulation()) + navigation_metrics_json(run);
    if (k == 0) first = all;
    else EXPECT_EQ(all, first);
  }
}

using test::expect_scenario_error;

TEST(NavigationRun, NavigationSectionErrorsNameTheField) {
  const std::string head = R"(
world:
  terrain:
    generate: {kind: flat, size_m: [8.0, 5.0], resolution_m: 0.05}
robot:
  drive: differential
  start: {x_m: 1.0, y_m: 2.4, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 30.0}
)";
  expect_scenario_error(head + "navigation:\n  goal_tolerance_m: 0.2\n", "navigation.goal");
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0}\n", "navigation.goal.y_m");
  // The components' declared parameters judge the rest when the run is set up (a list is a
  // value: polygons are lists of lists of numbers).
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  map: [1, 2]\n", "navigation.map", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  map: [{a: 1}]\n", "navigation.map");
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  planner: nonesuch\n", "navigation.planner", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  map: {resolution_m: -1}\n",
                        "navigation.map.resolution_m", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  speed: 3\n", "navigation.speed", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  follower: {cruise_speed_mps: 0}\n",
                        "navigation.follower.cruise_speed_mps", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  follower: {min_speed_mps: 0.5}\n",
                        "navigation.follower.min_speed_mps", true);  // above cruise_speed_mps: a cross-check
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  controller: straight_to_goal\n"
                               "  follower: {look_ahead_m: 0.4}\n",
                        "navigation.follower.look_ahead_m", true);  // the follower's section, another controller
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  map: {hit_gain: 1.5}\n",
                        "navigation.map.hit_gain", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n  map: {max_slope_deg: 90}\n",
                        "navigation.map.max_slope_deg", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\nlocalization: {localizer: amcl9}\n",
                        "localization.localizer", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 6.0, y_m: 2.4}\nlocalization: {ground_truth: {sigma_xy_m: -1}}\n",
                        "localization.ground_truth.sigma_xy_m", true);
  expect_scenario_error(head + "commands:\n  - {duration_s: 1, vx_mps: 0.1}\nnavigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n",
                        "commands");
  expect_scenario_error(head + "motion_mode: sideways\nnavigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n", "motion_mode");
  // Parsed, refused when the run is set up: the drive cannot do it, the goal is off the map.
  expect_scenario_error(head + "motion_mode: holonomic\nnavigation:\n  goal: {x_m: 6.0, y_m: 2.4}\n", "motion_mode", true);
  expect_scenario_error(head + "navigation:\n  goal: {x_m: 60.0, y_m: 2.4}\n", "navigation.goal", true);
}


// A controller (or planner) chosen on the command line outranks the scenario file: the file's
// section of the component it swapped out is dropped and said, not an error; a --set of that
// section is still refused, and so is the same section when the file itself chose another.
TEST(NavigationRun, AComponentSwappedOnTheCommandLineDropsTheFilesSectionOfTheOldOne) {
  const std::string yaml = R"(
world:
  terrain:
    generate: {kind: flat, size_m: [8.0, 5.0], resolution_m: 0.05}
robot:
  drive: differential
  start: {x_m: 1.0, y_m: 2.4, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 30.0}
navigation:
  goal: {x_m: 6.0, y_m: 2.4}
  follower: {cruise_speed_mps: 0.3}
  astar: {cost_weight: 2.0}
)";
  const ScenarioSpec spec = parse_scenario(yaml, "swap.yaml");
  NavigationOptions options;
  options.controller = "dwa";
  options.planner = "dijkstra";
  NavigationRun run(spec, options);
  const std::vector<std::string>& w = run.navigator().warnings();
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0].find("navigation.follower: ignored"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("--controller chose dwa"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("navigation.astar: ignored"), std::string::npos) << w[1];
  EXPECT_NE(w[1].find("--planner chose dijkstra"), std::string::npos) << w[1];

  // The same swap with a --set of the old controller's section: the user's own words, refused.
  const ScenarioOverride set = parse_scenario_override("navigation.follower.look_ahead_m=0.5");
  const ScenarioSpec with_set = parse_scenario(yaml, "swap.yaml", std::span<const ScenarioOverride>(&set, 1));
  try {
    NavigationRun refused(with_set, options);
    FAIL() << "a --set of the swapped-out controller was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "navigation.follower.look_ahead_m (--set)") << e.what();
    EXPECT_NE(std::string(e.what()).find("but navigation.controller is dwa"), std::string::npos) << e.what();
  }
}


// A navigation scenario on a SLAM-built map: a map_server map whose origin is negative, goals
// spread over the building. The navigation map covers the world's map and every goal (it used to
// cover the start, the first goal and each obstacle's anchor only); a goal off a terrain's bounds is
// refused naming the extent and the setting that changes it.
TEST(NavigationRun, TheNavigationMapCoversTheWorldsMapAndEveryGoal) {
  test::ScratchDir dir;
  fs::copy_file(kScenarios + "maps/indoor_rooms.pgm", dir.file("rooms.pgm"));
  // 480 x 320 cells of 0.05 m: [-12.5, 11.5] x [-4, 12] m.
  test::write_text(dir.file("rooms.yaml"), "image: rooms.pgm\nresolution: 0.05\norigin: [-12.5, -4.0, 0.0]\nnegate: 0\n"
                                           "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n");
  const std::string yaml = R"(
world:
  occupancy_map: {file: rooms.yaml, wall_height_m: 2.0}
robot:
  drive: differential
  start: {x_m: -10.75, y_m: -2.25, yaw_deg: 0.0}
sensors:
  lidar: {preset: hokuyo_utm30lx}
sim: {dt_s: 0.01, duration_s: 30.0}
navigation:
  goals:
    - {x_m: -9.0, y_m: -2.25}
    - {x_m: 9.5, y_m: 10.0}
)";
  test::write_text(dir.file("nav.yaml"), yaml);
  NavigationRun run(load_scenario(dir.file("nav.yaml")));
  const GridGeometry& g = run.navigator().map().geometry();
  const Vec2 lo = g.origin.translation();
  EXPECT_LE(lo.x(), -12.5);
  EXPECT_LE(lo.y(), -4.0);
  EXPECT_GE(lo.x() + g.width_m(), 11.5);
  EXPECT_GE(lo.y() + g.height_m(), 12.0);

  // On a terrain, the terrain's bounds are the map: a goal beyond them says so.
  const std::string terrain = R"(
world:
  terrain:
    generate: {kind: flat, size_m: [8.0, 5.0], resolution_m: 0.05}
robot:
  drive: differential
  start: {x_m: 1.0, y_m: 2.4, yaw_deg: 0.0}
sensors:
  lidar: {}
sim: {dt_s: 0.01, duration_s: 30.0}
navigation:
  goal: {x_m: 60.0, y_m: 2.4}
)";
  try {
    NavigationRun refused(parse_scenario(terrain, "far.yaml"));
    FAIL() << "a goal off the terrain was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "navigation.goal") << e.what();
    EXPECT_NE(std::string(e.what()).find("[0.00, 8.00] x [0.00, 5.00] m (navigation.map.extent world"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace starnav
