// `starnav plan`'s query as declared parameters (experiment/plan_query.hpp): settings applied and
// attributed to the field that gave them, the checks the CLI and the Python bindings share, the
// endpoints, and many queries on one planner per thread against the same queries one by one.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/plan_query.hpp"
#include "starnav/plan/grid_planner.hpp"

namespace starnav {
namespace {

// 20 x 12 free cells with a wall at x = 10 from y = 0 to 8: paths go round its top.
OccupancyGrid walled() {
  OccupancyGrid g(GridGeometry{20, 12, 0.5, {1.0, -2.0, 0.0}});
  for (int y = 0; y <= 8; ++y) g.set(10, y, kOccupiedOccupancy);
  return g;
}

ParamSetting set(const std::string& key, const std::string& value, const std::string& field = {}) {
  return {key, value, {}, 0, field};
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

PlanRequest request(const std::string& planner, const std::vector<ParamSetting>& settings) {
  const OccupancyGrid g = walled();
  return occupancy_plan_request(planner, settings, g.geometry(), false, {}, "walled.yaml");
}

TEST(PlanQuery, SettingsReachTheRequestAsTheCliFlagsDid) {
  const PlanRequest rq = request("wastar", {set("connectivity", "4"), set("weight", "2.5"), set("unknown", "free"),
                                            set("inflate", "0.5"), set("cost_radius_m", "2"), set("turn_cost", "1.5"),
                                            set("start_heading_deg", "90"), set("max_expansions", "7"),
                                            set("smooth", "los")});
  EXPECT_EQ(rq.planner, "wastar");
  EXPECT_EQ(rq.options.connectivity, 4);
  EXPECT_EQ(rq.options.weight, 2.5);
  EXPECT_TRUE(rq.options.unknown_is_free);
  EXPECT_EQ(rq.options.ou2022.inflation.radius_m, 0.5);
  EXPECT_EQ(rq.options.ou2022.inflation.cost_radius_m, 2.0);
  EXPECT_EQ(*rq.options.ou2022.turn_cost, 1.5);
  EXPECT_DOUBLE_EQ(*rq.options.ou2022.start_heading_rad, kPi / 2);
  EXPECT_EQ(rq.limits.max_expansions, 7u);
  EXPECT_EQ(rq.smoothing, PlanSmoothing::LineOfSight);
  // Unset options keep the planner's defaults (ou2022 turns them on itself).
  const PlanRequest plain = request("ou2022", {});
  EXPECT_FALSE(plain.options.ou2022.turn_cost.has_value());
  EXPECT_FALSE(plain.options.ou2022.adaptive_weight.has_value());
  EXPECT_EQ(plain.smoothing, PlanSmoothing::PlannerDefault);
}

TEST(PlanQuery, ErrorsNameTheSettingsField) {
  EXPECT_EQ(error_of([] { request("astar", {set("weight", "2", "--weight")}); }),
            "--weight: 'astar' takes no weight (planners that do: wastar)");
  EXPECT_EQ(error_of([] { request("astar", {set("weight", "2")}); }), "weight: 'astar' takes no weight (planners that do: wastar)");
  EXPECT_EQ(error_of([] { request("astar", {set("connectivity", "6")}); }), "connectivity: must be 4 or 8, got 6");
  EXPECT_EQ(error_of([] { request("astar", {set("smooth_clearance", "1")}); }), "smooth_clearance: only with --smooth gradient");
  EXPECT_EQ(error_of([] { request("astar", {set("cost_radius_m", "11")}); }), "cost_radius_m: must be in [0, 10], found '11'");
  EXPECT_EQ(error_of([] { request("ia", {}); }), "planner: 'ia' plans on elevation maps; walled.yaml is an occupancy map");
  EXPECT_EQ(error_of([] { request("astar", {set("bogus", "1")}); }).substr(0, 33), "bogus: unknown key 'bogus' (known");
  // A check deeper in the library (the planner's own) is attributed to the setting by its declared name.
  const OccupancyGrid g = walled();
  const std::vector<ParamSetting> band = {set("cost_radius_m", "2", "--inflate-cost-radius")};
  const PlanRequest rq = occupancy_plan_request("jps", band, g.geometry(), false, {}, "walled.yaml");
  EXPECT_EQ(error_of([&] { plan_query_on_grid(g, {0, 0}, {19, 0}, rq, band); }).substr(0, 42),
            "--inflate-cost-radius: jps cannot use a gr");
  EXPECT_EQ(plan_query_flag("cost_radius_m"), "--inflate-cost-radius");
  EXPECT_EQ(plan_query_flag("turn_cost"), "--turn-cost");
  EXPECT_EQ(plan_query_flag("w2"), "--weights");
}

TEST(PlanQuery, TerrainSettingsApplyToThePlannersThatUseThem) {
  const RoughTerrainPlannerKind ia[] = {RoughTerrainPlannerKind::IA}, oa[] = {RoughTerrainPlannerKind::OA};
  const TerrainPlanQuery q = terrain_plan_query(std::vector<ParamSetting>{set("h_y", "0.1"), set("admissible", "true")}, ia);
  EXPECT_EQ(q.options.cost.h_y, 0.1);
  EXPECT_EQ(q.options.heuristic, LiuHeuristic::Admissible);
  EXPECT_EQ(terrain_plan_query({}, ia).options.heuristic, LiuHeuristic::Paper);  // `starnav plan`'s default
  EXPECT_EQ(error_of([&] { terrain_plan_query(std::vector<ParamSetting>{set("h_y", "0.1", "--hy-m")}, oa); }),
            "--hy-m: applies to --planner aoea and ia only");
  EXPECT_EQ(error_of([&] { terrain_plan_query(std::vector<ParamSetting>{set("robot_radius_m", "1")}, ia); }),
            "robot_radius_m: applies to --planner aoea only");
  EXPECT_EQ(error_of([&] { terrain_plan_query(std::vector<ParamSetting>{set("w_s", "0.5"), set("w_e", "0.5")}, ia); }),
            "w_e: w_s + w_e + w_r must be 1, got 1.34");
  EXPECT_EQ(error_of([] { terrain_plan_planner("jps"); }).substr(0, 43), "planner: 'jps' plans on occupancy maps; on ");
}

TEST(PlanQuery, EndpointsInCellsOrMetres) {
  const GridGeometry g = walled().geometry();  // 0.5 m cells, origin (1, -2)
  EXPECT_EQ(plan_endpoint_cell({1.2, -1.9}, false, g, "start", ""), (Cell{0, 0}));
  EXPECT_EQ(plan_endpoint_cell({3.6, 0.1}, false, g, "start", ""), (Cell{5, 4}));
  EXPECT_EQ(plan_endpoint_cell({0.9, -2.0}, false, g, "start", ""), (Cell{-1, 0}));  // outside: a result later
  EXPECT_EQ(plan_endpoint_cell({3, 4}, true, g, "start", "3,4"), (Cell{3, 4}));
  EXPECT_EQ(error_of([&] { plan_endpoint_cell({3.5, 4}, true, g, "--start", "3.5,4"); }),
            "--start: expected cell indices X,Y (two integers), got '3.5,4'");
}

TEST(PlanQuery, ManyQueriesEqualTheQueriesOneByOneOnAnyNumberOfThreads) {
  const OccupancyGrid g = walled();
  std::vector<PlanEndpoints> queries;
  for (int i = 0; i < 30; ++i) queries.push_back({{i % 9, (i * 5) % 12}, {11 + i % 9, (i * 7) % 12}});
  queries.push_back({{10, 0}, {0, 0}});  // starts in the wall: a result, not an error
  for (const char* planner : {"astar", "jps", "jpsplus", "thetastar"}) {
    const PlanRequest rq = occupancy_plan_request(planner, {}, g.geometry(), false, {}, "walled");
    const std::vector<PlanResult> one = plan_many_on_grid(g, queries, rq, {}, 1), two = plan_many_on_grid(g, queries, rq, {}, 2);
    ASSERT_EQ(one.size(), queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const PlanResult single = make_grid_planner(planner, g, rq.options)->plan(queries[i].start, queries[i].goal);
      EXPECT_EQ(one[i].status, single.status) << planner << " " << i;
      EXPECT_EQ(one[i].cost, single.cost) << planner << " " << i;
      EXPECT_EQ(one[i].path_cells, single.path_cells) << planner << " " << i;
      EXPECT_EQ(two[i].path_cells, one[i].path_cells) << planner << " " << i;
      EXPECT_EQ(two[i].expanded, one[i].expanded) << planner << " " << i;
    }
    EXPECT_EQ(one.back().status, PlanStatus::StartBlocked);
  }
  const std::vector<ParamSetting> gradient = {set("smooth", "gradient")};
  EXPECT_EQ(error_of([&] {
              plan_many_on_grid(g, queries, occupancy_plan_request("astar", gradient, g.geometry(), false, {}, "w"), gradient);
            }),
            "smooth: gradient smoothing is per query: plan the queries one by one");
  const std::vector<ParamSetting> turn = {set("turn_cost", "1")};
  EXPECT_EQ(error_of([&] {
              plan_many_on_grid(g, queries, occupancy_plan_request("jps", turn, g.geometry(), false, {}, "w"), turn);
            }).substr(0, 35),
            "turn_cost: jps cannot use turn cost");
}

}  // namespace
}  // namespace starnav
