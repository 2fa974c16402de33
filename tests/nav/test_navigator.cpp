// The navigation loop without the simulator: synthetic scans (sensor origin + world points) fed
// to a Navigator in 2D mode, checked against independent recomputations on the map it built.
//   - a replan happens exactly when a cell of the remaining path is blocked, and not otherwise;
//   - every plan is collision-free on the map it was made on (escape prefix aside) and optimal
//     (equal to an A* search run here from the same cells);
//   - the start inside the band leaves it by escape_cell; no path is reported once, not looped on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/nav/navigator.hpp"
#include "starnav/plan/grid_planner.hpp"

namespace starnav {
namespace {

// 10 m x 6 m at 0.1 m, 2D mode (each return marks its cell), barrier 0.3 m.
NavigatorConfig config_2d(const std::string& planner = "astar") {
  NavigatorConfig c;
  c.geometry.width = 100;
  c.geometry.height = 60;
  c.geometry.resolution = 0.1;
  c.map.mode = NodeMapMode::Lidar2D;
  c.map.barrier_distance_m = 0.3;
  c.compare_astar = planner == "dstar_lite";
  return c;
}

// The registry's parts by name (the path follower, the latching goal checker, the simple progress
// checker, rotate then back up), as a scenario chooses them.
NavigatorParts parts(const std::string& planner = "astar", std::vector<ParamSetting> controller_settings = {},
                     const RobotConfig& robot = RobotConfig{}) {
  NavigationComponents c;
  c.planner = {planner, {}, "navigation.planner", 0, {}};
  c.controller = {"path_follower", std::move(controller_settings), "navigation.controller", 0, {}};
  c.goal_checker = {"latching", {}, "navigation.goal_checker", 0, {}};
  c.progress_checker = {"simple_progress", {}, "navigation.progress_checker", 0, {}};
  c.recoveries = {{"rotate", {}, "navigation.recoveries", 0, {}}, {"back_up", {}, "navigation.recoveries", 0, {}}};
  c.layers = {{"static_map", {}, "navigation.layers", 0, {}}, {"node_height", {}, "navigation.layers", 0, {}}};
  return make_navigator_parts(c, config_2d(planner), robot);
}

const Pose2 kStart(1.05, 3.05, 0.0);
const Vec2 kGoal(9.05, 3.05);

Vec3 origin_of(const Pose2& p) { return {p.x, p.y, 0.3}; }

// A* on the navigator's current map from `from` to the goal's cell (unknown free, 8-connected).
PlanResult reference_astar(const Navigator& nav, Cell from) {
  GridPlannerOptions o;
  o.unknown_is_free = true;
  const auto astar = make_grid_planner("astar", nav.map().occupancy(), o);
  return astar->plan(from, *nav.map().geometry().world_to_cell(nav.goal()));
}

// Is any cell of `plan` from `progress` on blocked on the navigator's map now (escape prefix: raw blocked)?
bool blocked_from(const Navigator& nav, const NavPlan& plan, std::size_t progress) {
  for (std::size_t i = progress; i < plan.cells.size(); ++i) {
    const Cell c = plan.cells[i];
    if (i < plan.escape_cells ? nav.map().raw_blocked(c.x, c.y) : nav.map().blocked(c.x, c.y)) return true;
  }
  return false;
}

TEST(Navigator, FirstCyclePlansStraightThroughUnknownSpace) {
  Navigator nav(config_2d(), RobotConfig{}, parts(), kGoal);
  EXPECT_EQ(nav.status(), NavStatus::Waiting);
  const NavCycle c = nav.on_points(origin_of(kStart), {}, kStart, 0.0);
  EXPECT_TRUE(c.planned);
  EXPECT_EQ(c.cause, "initial");
  ASSERT_EQ(nav.plans().size(), 1u);
  const NavPlan& p = nav.plans()[0];
  EXPECT_EQ(p.status, "found");
  EXPECT_NEAR(p.cost_m, 8.0, 1e-9);  // 80 straight cells
  ASSERT_EQ(p.points.size(), 2u);    // robot position, goal: no turning point on a straight path
  EXPECT_TRUE(p.points.front().isApprox(kStart.translation()));
  EXPECT_TRUE(p.points.back().isApprox(kGoal));
  EXPECT_EQ(nav.status(), NavStatus::Navigating);
}

TEST(Navigator, ObstacleOffThePathDoesNotReplanOnThePathDoes) {
  Navigator nav(config_2d(), RobotConfig{}, parts(), kGoal);
  nav.on_points(origin_of(kStart), {}, kStart, 0.0);
  // 1 m beside the path (band 0.3 m): no replan.
  std::vector<Vec3> off{{5.05, 4.05, 0.2}, {5.15, 4.05, 0.2}};
  NavCycle c = nav.on_points(origin_of(kStart), off, kStart, 0.1);
  EXPECT_GT(c.update.cells_hit, 0u);
  EXPECT_FALSE(c.planned);
  EXPECT_EQ(nav.plans().size(), 1u);
  // The band reaches the path from 0.25 m away: replan.
  std::vector<Vec3> near{{5.05, 3.3, 0.2}};
  c = nav.on_points(origin_of(kStart), near, kStart, 0.2);
  EXPECT_TRUE(c.planned);
  EXPECT_EQ(c.cause, "blocked");
  ASSERT_EQ(nav.plans().size(), 2u);
  const NavPlan& p = nav.plans()[1];
  EXPECT_EQ(p.status, "found");
  for (const Cell& cell : p.cells) EXPECT_FALSE(nav.map().blocked(cell.x, cell.y));
  EXPECT_GT(p.cost_m, 8.0);
  EXPECT_NEAR(p.cost_m, reference_astar(nav, p.cells.front()).cost, 1e-9);
}

// Random obstacles, cycle after cycle, robot moving along its path: the navigator replans
// exactly when the remaining path (from the progress it had) is blocked after the update.
void random_replan_property(const std::string& planner, std::uint64_t seed, int& replans, int& kept) {
  Navigator nav(config_2d(planner), RobotConfig{}, parts(planner), kGoal);
  Rng rng(seed);
  Pose2 pose = kStart;
  nav.on_points(origin_of(pose), {}, pose, 0.0);
  for (int k = 1; k <= 150 && nav.status() == NavStatus::Navigating; ++k) {
    // Walk the robot a little along its current path (a stand-in for the follower).
    const NavPlan before = nav.plans().back();
    const std::size_t progress_before = nav.progress();
    const std::size_t step_to = std::min(before.cells.size() - 1, progress_before + 1);
    const Vec2 at = nav.map().geometry().cell_center(before.cells[step_to]);
    pose = Pose2(at.x(), at.y(), 0.0);
    std::vector<Vec3> points;
    const int n = 1 + static_cast<int>(rng.uniform_int(0, 3));
    for (int i = 0; i < n; ++i) {
      const Vec3 p(rng.uniform(0.0, 10.0), rng.uniform(0.0, 6.0), 0.2);
      // Keep obstacles off the robot and the goal so both stay plannable.
      if ((p.head<2>() - pose.translation()).norm() < 0.8 || (p.head<2>() - kGoal).norm() < 0.8) continue;
      points.push_back(p);
    }
    const NavCycle c = nav.on_points(origin_of(pose), points, pose, 0.1 * k);
    // Independent: the old plan from the progress the robot reached (the nearest of its cells in
    // a window ahead of the previous progress), recomputed here.
    bool expected = false;
    {
      std::size_t best_i = progress_before;
      double best = 1e300;
      for (std::size_t i = progress_before; i < std::min(before.cells.size(), progress_before + 64); ++i) {
        const double d = (nav.map().geometry().cell_center(before.cells[i]) - pose.translation()).squaredNorm();
        if (d < best) best = d, best_i = i;
      }
      expected = blocked_from(nav, before, best_i);
    }
    ASSERT_EQ(c.planned, expected) << "cycle " << k << " seed " << seed;
    if (c.planned) {
      ++replans;
      const NavPlan& p = nav.plans().back();
      if (p.status != "found") {
        EXPECT_EQ(nav.status(), NavStatus::NoPath);
        break;
      }
      for (std::size_t i = p.escape_cells; i < p.cells.size(); ++i)
        ASSERT_FALSE(nav.map().blocked(p.cells[i].x, p.cells[i].y)) << "plan " << p.id << " cell " << i;
      const PlanResult ref = reference_astar(nav, p.cells[p.escape_cells]);
      ASSERT_TRUE(ref.found());
      ASSERT_NEAR(p.cost_m, ref.cost, 1e-9) << "plan " << p.id;
      if (p.compared) {
        ASSERT_NEAR(p.astar_cost_m, ref.cost, 1e-9);
        // The grid's moves are symmetric, so the search from the goal to the robot costs the same.
        ASSERT_EQ(p.astar_backward_status, "found");
        ASSERT_NEAR(p.astar_backward_cost_m, ref.cost, 1e-9);
        ASSERT_GT(p.astar_backward_expanded, 0u);
      }
    } else {
      ++kept;
    }
  }
}

TEST(Navigator, ReplansExactlyWhenTheRemainingPathIsBlockedAStar) {
  int replans = 0, kept = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) random_replan_property("astar", seed, replans, kept);
  EXPECT_GT(replans, 30);  // both branches exercised many times
  EXPECT_GT(kept, 30);
}

TEST(Navigator, ReplansExactlyWhenTheRemainingPathIsBlockedDStarLiteEqualsAStar) {
  int replans = 0, kept = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) random_replan_property("dstar_lite", seed, replans, kept);
  EXPECT_GT(replans, 30);
  EXPECT_GT(kept, 30);
}

TEST(Navigator, StartInsideTheBandEscapesInsteadOfReportingABlockedStart) {
  Navigator nav(config_2d(), RobotConfig{}, parts(), kGoal);
  // A wall 0.2 m below the robot: its cell lies inside the 0.3 m band.
  std::vector<Vec3> wall;
  for (double x = 0.55; x <= 1.6; x += 0.1) wall.emplace_back(x, 2.85, 0.2);
  const NavCycle c = nav.on_points(origin_of(kStart), wall, kStart, 0.0);
  ASSERT_TRUE(c.planned);
  ASSERT_TRUE(nav.map().blocked(10, 30));
  const NavPlan& p = nav.plans()[0];
  EXPECT_EQ(p.status, "found");
  EXPECT_GT(p.escape_cells, 0u);
  EXPECT_EQ(p.cells.front(), (Cell{10, 30}));
  // The escape prefix is exactly NodeHeightMap::escape_cell's path; the rest is free.
  std::vector<Cell> escape;
  const auto e = nav.map().escape_cell({10, 30}, &escape);
  ASSERT_TRUE(e.has_value());
  ASSERT_EQ(escape.size(), p.escape_cells + 1);
  for (std::size_t i = 0; i < escape.size(); ++i) EXPECT_EQ(p.cells[i], escape[i]);
  for (std::size_t i = p.escape_cells; i < p.cells.size(); ++i) EXPECT_FALSE(nav.map().blocked(p.cells[i].x, p.cells[i].y));
  // The next cycle with the same scan keeps the plan: the band around the robot is expected.
  EXPECT_FALSE(nav.on_points(origin_of(kStart), wall, kStart, 0.1).planned);
}

TEST(Navigator, EnclosedGoalIsReportedOnceAndNotLoopedOn) {
  Navigator nav(config_2d(), RobotConfig{}, parts(), kGoal);
  nav.on_points(origin_of(kStart), {}, kStart, 0.0);
  // A closed square ring around the goal, 0.6 m out.
  std::vector<Vec3> ring;
  for (double a = -0.6; a <= 0.6 + 1e-9; a += 0.05) {
    ring.emplace_back(kGoal.x() + a, kGoal.y() - 0.6, 0.2);
    ring.emplace_back(kGoal.x() + a, kGoal.y() + 0.6, 0.2);
    ring.emplace_back(kGoal.x() - 0.6, kGoal.y() + a, 0.2);
    ring.emplace_back(kGoal.x() + 0.6, kGoal.y() + a, 0.2);
  }
  // The ring is seen from inside its own cells (sensor at the goal side) so no beam clears it.
  NavCycle c = nav.on_points(Vec3(kGoal.x(), kGoal.y(), 0.3), ring, kStart, 0.1);
  EXPECT_TRUE(c.planned);
  EXPECT_EQ(nav.status(), NavStatus::NoPath);
  EXPECT_EQ(nav.plans().back().status, "no_path");
  EXPECT_FALSE(nav.no_path_reason().empty());
  const std::size_t plans = nav.plans().size();
  // Further cycles and commands neither plan again nor move the robot.
  for (int k = 0; k < 5; ++k) {
    c = nav.on_points(origin_of(kStart), {}, kStart, 0.2 + 0.1 * k);
    EXPECT_FALSE(c.planned);
    const BodyTwist t = nav.command(kStart, 0.2 + 0.1 * k);
    EXPECT_EQ(t.vx, 0.0);
    EXPECT_EQ(t.vy, 0.0);
    EXPECT_EQ(t.wz, 0.0);
  }
  EXPECT_EQ(nav.plans().size(), plans);
}

TEST(Navigator, ArrivesWithinGoalTolerance) {
  NavigatorConfig c = config_2d();
  c.goal_tolerance_m = 0.2;
  Navigator nav(c, RobotConfig{}, parts(), kGoal);
  nav.on_points(origin_of(kStart), {}, kStart, 0.0);
  const BodyTwist far = nav.command(kStart, 0.0);
  EXPECT_GT(std::abs(far.vx) + std::abs(far.wz), 0.0);
  const Pose2 near(kGoal.x() - 0.19, kGoal.y(), 0.0);
  const BodyTwist t = nav.command(near, 5.0);
  EXPECT_EQ(nav.status(), NavStatus::Arrived);
  EXPECT_DOUBLE_EQ(nav.arrival_time_s(), 5.0);
  EXPECT_EQ(t.vx, 0.0);
}

TEST(Navigator, RejectsBadConfigurations) {
  NavigatorConfig c = config_2d();
  EXPECT_THROW(Navigator(c, RobotConfig{}, parts(), Vec2(20.0, 3.0)), Error);  // goal outside the map
  c.goal_tolerance_m = 0.0;
  EXPECT_THROW(Navigator(c, RobotConfig{}, parts(), kGoal), Error);
  c = config_2d();
  RobotConfig diff;
  diff.drive = DriveKind::Differential;
  try {
    Navigator nav(c, diff, parts("astar", {{"motion_mode", "holonomic", "", 0, "motion_mode"}}, diff), kGoal);
    FAIL() << "holonomic on a differential robot accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "motion_mode");
  }
  // Any occupancy planner of the registry navigates; an elevation planner or an unknown name does not.
  EXPECT_EQ(Navigator(c, RobotConfig{}, parts("dijkstra"), kGoal).planner().name(), "dijkstra");
  try {
    Navigator nav(c, RobotConfig{}, parts("ia"), kGoal);
    FAIL() << "an elevation planner navigated";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "navigation.planner");
  }
  try {
    parts("nonesuch");
    FAIL() << "unknown planner accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "navigation.planner");
    EXPECT_NE(std::string(e.what()).find("dstar_lite"), std::string::npos) << e.what();
  }
  // The old spelling still builds the planner (the scenario's reader warns about it).
  EXPECT_EQ(Navigator(c, RobotConfig{}, parts("dstarlite"), kGoal).planner().name(), "dstar_lite");
  // A navigator without one of its parts is refused.
  NavigatorParts missing = parts();
  missing.goal_checker.reset();
  EXPECT_THROW(Navigator(c, RobotConfig{}, std::move(missing), kGoal), Error);
}

// The navigator knows its parts by their roles only: a planner and a controller written here,
// never registered, plan and drive it; the goal checker and progress checker come the same way.
class StraightLinePlanner final : public GlobalPlanner {
 public:
  std::string_view name() const override { return "fake_planner"; }
  PlanResult plan(const PlanningLayers& layers, Cell start, Cell goal, std::span<const CellChange>) override {
    ++calls;
    PlanResult r;
    r.status = PlanStatus::Found;
    // Along x, then along y: enough for an open map.
    Cell c = start;
    r.path_cells.push_back(c);
    while (c.x != goal.x) {
      c.x += goal.x > c.x ? 1 : -1;
      r.path_cells.push_back(c);
    }
    while (c.y != goal.y) {
      c.y += goal.y > c.y ? 1 : -1;
      r.path_cells.push_back(c);
    }
    for (const Cell& p : r.path_cells) r.path_world.push_back(layers.occupancy->geometry().cell_center(p));
    r.cost = static_cast<double>(r.path_cells.size() - 1) * layers.occupancy->geometry().resolution;
    r.length = r.cost;
    return r;
  }
  int calls = 0;
};

class ConstantController final : public LocalController {
 public:
  std::string_view name() const override { return "fake_controller"; }
  void set_path(std::span<const Vec2> points) override { path_.assign(points.begin(), points.end()); }
  void clear() override { path_.clear(); }
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return path_; }
  ControlOutput compute(const ControlInput& in) override {
    last_goal = in.goal;
    return {{0.25, 0.0, 0.0}, ControlStatus::Tracking};
  }
  std::vector<Vec2> path_;
  Vec2 last_goal = Vec2::Zero();
};

class NeverReached final : public GoalChecker {
 public:
  std::string_view name() const override { return "never"; }
  void reset() override {}
  bool reached(const GoalCheckInput&) override { return false; }
  bool position_reached() const override { return false; }
};

class AlwaysProgressing final : public ProgressChecker {
 public:
  std::string_view name() const override { return "always"; }
  void reset() override {}
  void restart_clock(double) override {}
  bool check(const Pose2&, double) override { return true; }
};

TEST(Navigator, TakesAPlannerAndAControllerItWasGivenWithoutTheRegistry) {
  NavigatorParts p;
  auto planner = std::make_unique<StraightLinePlanner>();
  auto controller = std::make_unique<ConstantController>();
  StraightLinePlanner* planner_seen = planner.get();
  ConstantController* controller_seen = controller.get();
  p.planner = std::move(planner);
  p.controller = std::move(controller);
  p.goal_checker = std::make_unique<NeverReached>();
  p.progress_checker = std::make_unique<AlwaysProgressing>();
  Navigator nav(config_2d(), RobotConfig{}, std::move(p), kGoal);
  nav.on_points(origin_of(kStart), {}, kStart, 0.0);
  ASSERT_EQ(nav.status(), NavStatus::Navigating);
  EXPECT_EQ(planner_seen->calls, 1);
  EXPECT_EQ(nav.planner().name(), "fake_planner");
  // The controller got the path (from the robot to the goal) and drives with its own twist.
  ASSERT_EQ(controller_seen->path_.size(), 2u);
  EXPECT_EQ(controller_seen->path_.front(), kStart.translation());
  EXPECT_EQ(controller_seen->path_.back(), kGoal);
  const BodyTwist t = nav.command(kStart, 0.1);
  EXPECT_DOUBLE_EQ(t.vx, 0.25);
  EXPECT_EQ(controller_seen->last_goal, kGoal);
  // Near the goal the fake goal checker still says no: the navigator asks it, not a rule of its own.
  nav.command(Pose2(kGoal.x(), kGoal.y(), 0.0), 0.2);
  EXPECT_EQ(nav.status(), NavStatus::Navigating);
}

// A band of limited speed across the map, 4 m <= x <= 5 m: what a speed-limit layer answers, in
// the simplest form (the area meets the band when its x extent does).
class SlowBand final : public CostmapLayer {
 public:
  std::string_view name() const override { return "slow_band"; }
  void contribute(const CellRect&, std::span<std::uint8_t>, std::span<std::uint8_t>) const override {}
  std::optional<double> speed_limit_mps(std::span<const Vec2> area) const override {
    double lo = 1e300, hi = -1e300;
    for (const Vec2& p : area) lo = std::min(lo, p.x()), hi = std::max(hi, p.x());
    if (hi >= 4.0 && lo <= 5.0) return 0.1;
    return std::nullopt;
  }
};

class RecordingController final : public LocalController {
 public:
  std::string_view name() const override { return "recording"; }
  void set_path(std::span<const Vec2> points) override { path_.assign(points.begin(), points.end()); }
  void clear() override { path_.clear(); }
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return path_; }
  ControlOutput compute(const ControlInput& in) override {
    limits = in.limits;
    return {{std::min(0.4, in.limits.max_vx_mps), 0.0, 0.0}, ControlStatus::Tracking};
  }
  std::vector<Vec2> path_;
  VelocityLimits limits;
};

TEST(Navigator, ASpeedLimitLayerLowersTheControllersLimitsWhereTheFootprintMeetsIt) {
  const RobotConfig robot;  // 0.55 m long: the body meets the band from x = 4 - 0.275
  NavigatorParts p;
  p.planner = std::make_unique<StraightLinePlanner>();
  auto controller = std::make_unique<RecordingController>();
  RecordingController* seen = controller.get();
  p.controller = std::move(controller);
  p.goal_checker = std::make_unique<NeverReached>();
  p.progress_checker = std::make_unique<AlwaysProgressing>();
  p.layers.push_back(std::make_unique<SlowBand>());
  Navigator nav(config_2d(), robot, std::move(p), kGoal);
  nav.on_points(origin_of(kStart), {}, kStart, 0.0);
  const VelocityLimits own = velocity_limits_of(robot);
  ASSERT_GT(own.max_vx_mps, 0.3);
  ASSERT_GT(own.max_vy_mps, 0.3);  // mecanum: the lateral limit is lowered too
  double t = 0.0;
  for (const double x : {2.0, 3.70, 3.73, 4.5, 5.2, 5.3, 6.0}) {
    SCOPED_TRACE(x);
    const BodyTwist twist = nav.command(Pose2(x, 3.05, 0.0), t += 0.1);
    const bool meets = x + 0.275 >= 4.0 && x - 0.275 <= 5.0;
    EXPECT_EQ(nav.speed_limit_at(Pose2(x, 3.05, 0.0)).has_value(), meets);
    ASSERT_EQ(nav.speed_limit().has_value(), meets);
    EXPECT_EQ(seen->limits.max_vx_mps, meets ? 0.1 : own.max_vx_mps);
    EXPECT_EQ(seen->limits.max_vy_mps, meets ? 0.1 : own.max_vy_mps);
    EXPECT_EQ(seen->limits.max_speed_mps, meets ? 0.1 : own.max_speed_mps);
    EXPECT_EQ(seen->limits.max_yaw_rate_radps, own.max_yaw_rate_radps);  // turning is not limited
    EXPECT_DOUBLE_EQ(twist.vx, meets ? 0.1 : 0.4);
  }
  // Turned across the band's edge, the body's corners count, not its centre.
  EXPECT_FALSE(nav.speed_limit_at(Pose2(3.70, 3.05, 0.0)));
  EXPECT_TRUE(nav.speed_limit_at(Pose2(3.70, 3.05, 0.7)));
  // Each change of the limit is an event: entering, leaving.
  std::vector<std::string> changes;
  for (const NavEvent& e : nav.events())
    if (e.kind == "speed_limit") changes.push_back(e.detail);
  EXPECT_EQ(changes, (std::vector<std::string>{"0.1", "none"}));
}

// The registry's controllers keep their commands within a lowered limit: the navigator's step in
// the band commands no more than the band's speed, outside it more.
TEST(Navigator, EveryRegisteredControllerKeepsToTheLoweredLimit) {
  for (const char* name : {"path_follower", "dwa", "regulated_pure_pursuit", "straight_to_goal"}) {
    SCOPED_TRACE(name);
    NavigationComponents c;
    c.planner = {"astar", {}, "navigation.planner", 0, {}};
    std::vector<ParamSetting> fast;
    if (std::string(name) == "path_follower") fast = {{"cruise_speed_mps", "0.5", "", 0, "cruise_speed_mps"}};
    if (std::string(name) == "straight_to_goal") fast = {{"speed_mps", "0.5", "", 0, "speed_mps"}};
    if (std::string(name) == "regulated_pure_pursuit") fast = {{"desired_linear_vel_mps", "0.5", "", 0, "desired_linear_vel_mps"}};
    c.controller = {name, fast, "navigation.controller", 0, {}};
    c.goal_checker = {"latching", {}, "navigation.goal_checker", 0, {}};
    c.progress_checker = {"simple_progress", {}, "navigation.progress_checker", 0, {}};
    c.layers = {{"static_map", {}, "navigation.layers", 0, {}}};
    NavigatorParts p = make_navigator_parts(c, config_2d(), RobotConfig{});
    p.layers.push_back(std::make_unique<SlowBand>());
    Navigator nav(config_2d(), RobotConfig{}, std::move(p), kGoal);
    // Moving at 0.3 m/s along the path, in the band and before it.
    const Pose2 in_band(4.5, 3.05, 0.0), before(2.0, 3.05, 0.0);
    nav.on_points(origin_of(before), {}, before, 0.0);
    double fastest_before = 0.0;
    for (int k = 0; k < 5; ++k) {
      const BodyTwist b = nav.command(before, 0.2 * k, {0.3, 0.0, 0.0});
      fastest_before = std::max(fastest_before, std::hypot(b.vx, b.vy));
    }
    nav.hold(1.0);
    for (int k = 0; k < 5; ++k) {
      const BodyTwist b = nav.command(in_band, 1.2 + 0.2 * k, {0.3, 0.0, 0.0});
      EXPECT_LE(std::hypot(b.vx, b.vy), 0.1 + 1e-12) << k;
      EXPECT_LE(std::abs(b.vx), 0.1 + 1e-12) << k;
    }
    EXPECT_GT(fastest_before, 0.1 + 1e-3) << "outside the band it drives faster than the band allows";
  }
}

}  // namespace
}  // namespace starnav
