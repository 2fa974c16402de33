// Ou et al. 2022 (docs/papers/ou2022.md), hand-built cases: the move-direction table and every steering angle
// difference, the turn cost along paths and in the search, the adaptive weight, each path
// metric, the inflation rule and its cost band, LOS smoothing on a drawn map, and which planner
// accepts which feature.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "plan/plan_test_maps.hpp"
#include "starnav/core/error.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/ou2022.hpp"
#include "starnav/plan/ou2022_policies.hpp"
#include "starnav/plan/path_metrics.hpp"
#include "starnav/plan/path_smoothing.hpp"

namespace starnav {
namespace {

using plantest::Map;
constexpr double kS2 = std::numbers::sqrt2;

Map empty_map(int w, int h) { return Map{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h, 0)}; }

// ---- Directions and steering angles ------------------------------------------------------------

TEST(Ou2022Steering, DirectionsFollowTable1) {
  // Paper Table 1 (with 270 and 315 for its typos 275 and 360).
  const int table[8][3] = {{1, 0, 0},     {1, 1, 45},    {0, 1, 90},   {-1, 1, 135},
                           {-1, 0, 180},  {-1, -1, 225}, {0, -1, 270}, {1, -1, 315}};
  for (const auto& row : table) {
    const int dir = move_direction(row[0], row[1]);
    ASSERT_GE(dir, 0);
    EXPECT_EQ(direction_angle_deg(dir), row[2]);
    EXPECT_EQ(direction_dx(dir), row[0]);
    EXPECT_EQ(direction_dy(dir), row[1]);
  }
  EXPECT_EQ(move_direction(0, 0), -1);
  EXPECT_EQ(move_direction(2, 0), -1);
}

TEST(Ou2022Steering, EveryAngleDifference) {
  // alpha -> beta in degrees, and the expected steering angle (the smaller angle between them).
  const int cases[][3] = {{0, 0, 0},     {0, 45, 45},    {0, 90, 90},    {0, 135, 135},  {0, 180, 180},
                          {0, 225, 135}, {0, 270, 90},   {0, 315, 45},   {315, 0, 45},   {270, 45, 135},
                          {225, 45, 180}, {90, 270, 180}, {135, 315, 180}, {45, 315, 90}, {180, 0, 180},
                          {315, 135, 180}, {315, 90, 135}};
  for (const auto& c : cases) {
    const int a = c[0] / 45, b = c[1] / 45;
    EXPECT_EQ(steering_angle_deg(a, b), c[2]) << c[0] << " -> " << c[1];
    EXPECT_EQ(steering_angle_deg(b, a), c[2]);
  }
  // turn_w = k * delta / 45: 0, k, 2k, 3k, 4k for 0, 45, 90, 135, 180 degrees.
  for (int d = 0; d <= 4; ++d) EXPECT_DOUBLE_EQ(turn_cost_cells(2.5, 0, d), 2.5 * d);
  EXPECT_DOUBLE_EQ(turn_cost_cells(1.0, 7, 1), 2.0);  // 315 -> 45 wraps through 0: 90 degrees
  // From a heading: the smaller angle to the move's direction.
  EXPECT_NEAR(heading_to_direction_rad(0.0, 4), std::numbers::pi, 1e-12);
  EXPECT_NEAR(heading_to_direction_rad(-std::numbers::pi / 2, 0), std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(heading_to_direction_rad(0.1, 7), std::numbers::pi / 4 + 0.1, 1e-12);
}

TEST(Ou2022Steering, TurnCostAlongAPath) {
  // Resolution 0.5, k_turn = 2: every case is one move east, then the move that turns by delta.
  const Map m = empty_map(5, 5);
  GridPlannerOptions o;
  o.ou2022.turn_cost = 2.0;
  const ImprovedAStarPlanner p(m.grid(0.5), o, false);
  const double r = 0.5, k = 2.0;
  EXPECT_NEAR(p.path_cost(std::vector<Cell>{{1, 1}, {2, 1}, {3, 1}}), r * (2), 1e-12);                 // 0
  EXPECT_NEAR(p.path_cost(std::vector<Cell>{{1, 1}, {2, 1}, {3, 2}}), r * (1 + kS2 + 1 * k), 1e-12);   // 45
  EXPECT_NEAR(p.path_cost(std::vector<Cell>{{1, 1}, {2, 1}, {2, 2}}), r * (2 + 2 * k), 1e-12);         // 90
  EXPECT_NEAR(p.path_cost(std::vector<Cell>{{1, 1}, {2, 1}, {1, 2}}), r * (1 + kS2 + 3 * k), 1e-12);   // 135
  EXPECT_NEAR(p.path_cost(std::vector<Cell>{{1, 1}, {2, 1}, {1, 1}}), r * (2 + 4 * k), 1e-12);         // 180
  EXPECT_NEAR(p.path_cost(std::vector<Cell>{{1, 1}, {2, 1}, {3, 0}}), r * (1 + kS2 + 1 * k), 1e-12);   // -45
  // Turns accumulate: east, north-east, north, north-west = three 45-degree turns.
  EXPECT_NEAR(p.path_cost(std::vector<Cell>{{0, 0}, {1, 0}, {2, 1}, {2, 2}, {1, 3}}), r * (2 + 2 * kS2 + 3 * k),
              1e-12);
}

TEST(Ou2022Steering, SearchChargesTheTurns) {
  // An L-shaped corridor, 4-connected: 6 moves east, a 90-degree turn, 4 moves north.
  //   y=4  ......@   (row 4 and column 6 free, the rest blocked)
  Map m = empty_map(7, 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) m.set(x, y, !(y == 0 || x == 6));
  for (bool exact : {false, true}) {
    GridPlannerOptions o;
    o.connectivity = 4;
    o.ou2022.turn_cost = 1.5;
    o.ou2022.turn_exact = exact;
    ImprovedAStarPlanner p(m.grid(0.2), o, false);
    const PlanResult r = p.plan({0, 0}, {6, 4});
    ASSERT_TRUE(r.found());
    EXPECT_NEAR(r.cost, 0.2 * (10 + 2 * 1.5), 1e-12);
    EXPECT_NEAR(r.length, 0.2 * 10, 1e-12);
    EXPECT_EQ(p.admissible(), exact);  // octile on 4-connected grids never overestimates
  }
  // An initial heading west makes the first move (east) a 180-degree turn.
  GridPlannerOptions o;
  o.connectivity = 4;
  o.ou2022.turn_cost = 1.0;
  o.ou2022.start_heading_rad = std::numbers::pi;
  ImprovedAStarPlanner p(m.grid(1.0), o, false);
  EXPECT_NEAR(p.plan({0, 0}, {6, 4}).cost, 10 + 2 + 4, 1e-9);
  o.ou2022.start_heading_rad = 0.0;
  ImprovedAStarPlanner q(m.grid(1.0), o, false);
  EXPECT_NEAR(q.plan({0, 0}, {6, 4}).cost, 10 + 2, 1e-9);
}

TEST(Ou2022Steering, TurnCostsPreferFewerTurns) {
  // Open 8-connected grid from (0,0) to (6,2): every shortest path has 2 diagonal and 4 straight
  // moves; with (exact) turn costs the search takes one whose diagonal moves come together, with
  // a single 45-degree turn (cost k).
  const Map m = empty_map(8, 4);
  GridPlannerOptions o;
  o.ou2022.turn_cost = 1.0;
  o.ou2022.turn_exact = true;
  ImprovedAStarPlanner p(m.grid(), o, false);
  const PlanResult r = p.plan({0, 0}, {6, 2});
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.cost, 4 + 2 * kS2 + 1.0, 1e-9);
  EXPECT_NEAR(r.length, 4 + 2 * kS2, 1e-9);
  const PathMetrics metrics = compute_path_metrics(r.path_world);
  EXPECT_EQ(metrics.turning_points, 1u);
}

// ---- Adaptive weight ---------------------------------------------------------------------------

TEST(Ou2022AdaptiveWeight, FallsFromTwoToOne) {
  const Map m = empty_map(10, 10);
  const GridSearchMap map(m.w, m.h, m.blocked);
  using C = std::int64_t;
  const C card = UniformGridCost::kCardinal, diag = UniformGridCost::kDiagonal;
  // Start (0,0), goal (3,4): D = 5.
  AdaptiveWeightHeuristic<ManhattanHeuristic<C>> h(ManhattanHeuristic<C>(map, card, diag), map, map.state(0, 0));
  h.set_goal(map.state(3, 4));
  EXPECT_DOUBLE_EQ(h.weight(map.state(0, 0)), 2.0);
  EXPECT_DOUBLE_EQ(h.weight(map.state(3, 4)), 1.0);
  EXPECT_DOUBLE_EQ(h.weight(map.state(3, 0)), 1.8);  // d = 4
  EXPECT_DOUBLE_EQ(h.weight(map.state(0, 4)), 1.6);  // d = 3
  // f's heuristic term: (1 + d/D) * Manhattan, in cells.
  EXPECT_NEAR(UniformGridCost::to_cells(h(map.state(3, 0))), 1.8 * 4, 1e-9);
  EXPECT_NEAR(UniformGridCost::to_cells(h(map.state(0, 0))), 2.0 * 7, 1e-9);
  EXPECT_EQ(h(map.state(3, 4)), 0);
  // Octile inner: at (0,4), dx = 3, dy = 0 -> 3 cells, weight 1.6.
  AdaptiveWeightHeuristic<OctileHeuristic<C>> o(OctileHeuristic<C>(map, card, diag), map, map.state(0, 0));
  o.set_goal(map.state(3, 4));
  EXPECT_NEAR(UniformGridCost::to_cells(o(map.state(0, 4))), 1.6 * 3, 1e-9);
  EXPECT_NEAR(UniformGridCost::to_cells(o(map.state(0, 0))), 2.0 * (1 + 3 * kS2), 1e-9);
}

TEST(Ou2022AdaptiveWeight, PlannerFlagsAndDefaults) {
  const OccupancyGrid grid = empty_map(6, 6).grid();
  ImprovedAStarPlanner paper(grid, {}, true);
  EXPECT_EQ(paper.name(), "ou2022");
  EXPECT_FALSE(paper.admissible());
  EXPECT_EQ(paper.settings().heuristic, GridHeuristicKind::Manhattan);
  EXPECT_TRUE(paper.settings().adaptive_weight);
  EXPECT_EQ(paper.settings().turn_cost, 1.0);
  EXPECT_EQ(paper.settings().smoothing, PathSmoothing::LineOfSight);
  GridPlannerOptions o;
  o.ou2022.adaptive_weight = true;
  auto astar = make_grid_planner("astar", grid, o);
  EXPECT_EQ(astar->name(), "astar");
  EXPECT_FALSE(astar->admissible());  // weighted: labelled inadmissible
  o.ou2022.adaptive_weight = false;
  o.ou2022.inflation.radius_m = 1.0;
  EXPECT_TRUE(make_grid_planner("astar", grid, o)->admissible());
  o.heuristic = "manhattan";
  EXPECT_FALSE(make_grid_planner("astar", grid, o)->admissible());
  // Start equal to goal: the trivial path, no search (D = 0).
  const PlanResult same = paper.plan({2, 2}, {2, 2});
  ASSERT_TRUE(same.found());
  EXPECT_EQ(same.path_cells.size(), 1u);
  EXPECT_EQ(same.expanded, 0u);
  EXPECT_EQ(same.cost, 0.0);
}

// ---- Path metrics ------------------------------------------------------------------------------

TEST(Ou2022PathMetrics, Turns) {
  // Three sides of a square: two 90-degree turns.
  const std::vector<Vec2> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  PathMetrics m = compute_path_metrics(square);
  EXPECT_DOUBLE_EQ(m.length, 6.0);
  EXPECT_EQ(m.vertices, 4u);
  EXPECT_EQ(m.turning_points, 2u);
  EXPECT_NEAR(m.turn_total_rad, std::numbers::pi, 1e-12);
  EXPECT_NEAR(m.turn_max_rad, std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(m.smoothness, 2 * (std::numbers::pi / 2) * (std::numbers::pi / 2) / 6.0, 1e-12);
  EXPECT_TRUE(std::isnan(m.clearance_min));
  EXPECT_TRUE(std::isnan(m.clearance_mean));
  // A collinear vertex and a repeated point are not turns; one 45-degree turn at the end.
  m = compute_path_metrics(std::vector<Vec2>{{0, 0}, {1, 0}, {1, 0}, {2, 0}, {3, 1}});
  EXPECT_EQ(m.vertices, 5u);
  EXPECT_EQ(m.turning_points, 1u);
  EXPECT_NEAR(m.turn_total_rad, std::numbers::pi / 4, 1e-12);
  EXPECT_NEAR(m.length, 2 + kS2, 1e-12);
  EXPECT_NEAR(m.smoothness, (std::numbers::pi / 4) * (std::numbers::pi / 4) / (2 + kS2), 1e-12);
  // A reversal is a turn of pi; turns to either side count by their absolute value.
  m = compute_path_metrics(std::vector<Vec2>{{0, 0}, {1, 0}, {0, 0}});
  EXPECT_NEAR(m.turn_max_rad, std::numbers::pi, 1e-12);
  m = compute_path_metrics(std::vector<Vec2>{{0, 0}, {1, 0}, {2, 1}, {3, 0}});  // +45, -90
  EXPECT_EQ(m.turning_points, 2u);
  EXPECT_NEAR(m.turn_total_rad, 3 * std::numbers::pi / 4, 1e-12);
  EXPECT_NEAR(m.turn_max_rad, std::numbers::pi / 2, 1e-12);
  // Degenerate paths.
  m = compute_path_metrics(std::vector<Vec2>{{1, 1}});
  EXPECT_EQ(m.vertices, 1u);
  EXPECT_EQ(m.length, 0.0);
  EXPECT_EQ(m.smoothness, 0.0);
  EXPECT_EQ(compute_path_metrics(std::vector<Vec2>{}).vertices, 0u);
}

TEST(Ou2022PathMetrics, Clearance) {
  // 7 x 5 cells of 0.5 m, an obstacle column at x = 0: a cell's clearance is 0.5 * x.
  Map m = empty_map(7, 5);
  for (int y = 0; y < 5; ++y) m.set(0, y, true);
  const OccupancyGrid grid = m.grid(0.5);
  const ClearanceField field = ClearanceField::of_grid(grid);
  EXPECT_DOUBLE_EQ(field.at(Cell{3, 2}), 1.5);
  EXPECT_DOUBLE_EQ(field.at(Vec2(2.6, 1.2)), 2.5);
  EXPECT_TRUE(std::isnan(field.at(Vec2(-0.1, 1.0))));
  // From the centre of (1, 2) to the centre of (5, 2): x = 0.75 .. 2.75 m, samples every
  // 0.125 m plus the end: 2 samples in cell 1, 4 each in cells 2, 3, 4, and 3 in cell 5.
  const PathMetrics pm = compute_path_metrics(std::vector<Vec2>{{0.75, 1.25}, {2.75, 1.25}}, &field);
  EXPECT_DOUBLE_EQ(pm.clearance_min, 0.5);
  EXPECT_NEAR(pm.clearance_mean, (2 * 0.5 + 4 * 1.0 + 4 * 1.5 + 4 * 2.0 + 3 * 2.5) / 17.0, 1e-12);
  // Diagonal distances count: a single obstacle at (0, 0), path point in cell (3, 4): 5 cells.
  Map one = empty_map(6, 6);
  one.set(0, 0, true);
  const ClearanceField f1 = ClearanceField::of_grid(one.grid(0.1));
  EXPECT_NEAR(compute_path_metrics(std::vector<Vec2>{{0.35, 0.45}}, &f1).clearance_min, 0.5, 1e-12);
  // No obstacle at all: infinite clearance.
  const ClearanceField none = ClearanceField::of_grid(empty_map(4, 4).grid());
  const PathMetrics inf = compute_path_metrics(std::vector<Vec2>{{0.5, 0.5}, {3.5, 3.5}}, &none);
  EXPECT_TRUE(std::isinf(inf.clearance_min));
  EXPECT_TRUE(std::isinf(inf.clearance_mean));
}

// ---- Inflation ---------------------------------------------------------------------------------

TEST(Ou2022Inflation, HardRadiusIsADisc) {
  // One obstacle in the middle of 9 x 9 cells of 0.05 m; R = 0.1 m = 2 cells exactly (the
  // tolerance keeps the cells at distance exactly 2): the 12 cells with dx^2 + dy^2 <= 4.
  Map m = empty_map(9, 9);
  m.set(4, 4, true);
  InflationOptions o;
  o.radius_m = 0.1;
  const InflatedMap inf = inflate_obstacles(m.grid(0.05), {}, false, o);
  EXPECT_EQ(inf.obstacle_cells, 1u);
  EXPECT_EQ(inf.inflated_cells, 12u);
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 9; ++x) {
      const int d2 = (x - 4) * (x - 4) + (y - 4) * (y - 4);
      EXPECT_EQ(inf.blocked[static_cast<std::size_t>(y) * 9 + x] != 0, d2 <= 4) << x << "," << y;
      EXPECT_NEAR(inf.clearance_m[static_cast<std::size_t>(y) * 9 + x], 0.05 * std::sqrt(d2), 1e-12);
    }
  EXPECT_TRUE(inf.multiplier.empty());
  // Unknown cells are obstacles unless unknown_is_free.
  OccupancyGrid g = empty_map(5, 1).grid();
  g(0, 0) = kUnknownOccupancy;
  o.radius_m = 1.0;
  EXPECT_EQ(inflate_obstacles(g, {}, false, o).inflated_cells, 1u);
  EXPECT_EQ(inflate_obstacles(g, {}, true, o).inflated_cells, 0u);
}

TEST(Ou2022Inflation, CostBandDecaysExponentially) {
  InflationOptions o;
  o.radius_m = 0.2;
  o.cost_radius_m = 1.0;
  o.cost_scale = 10.0;
  o.cost_weight = 4.0;
  EXPECT_DOUBLE_EQ(inflation_cost_multiplier(0.3, o), 1 + 4 * std::exp(-1.0));
  EXPECT_DOUBLE_EQ(inflation_cost_multiplier(1.0, o), 1 + 4 * std::exp(-8.0));
  EXPECT_DOUBLE_EQ(inflation_cost_multiplier(1.01, o), 1.0);
  EXPECT_DOUBLE_EQ(inflation_cost_multiplier(0.2, o), 1.0);  // blocked there, not this function's business
  // On a map: a wall at x = 0, cells of 0.1 m: x = 1, 2 blocked; x = 3 .. 10 in the band.
  Map m = empty_map(14, 2);
  for (int y = 0; y < 2; ++y) m.set(0, y, true);
  const InflatedMap inf = inflate_obstacles(m.grid(0.1), {}, false, o);
  ASSERT_EQ(inf.multiplier.size(), 28u);
  for (int x = 1; x < 14; ++x) {
    const double d = 0.1 * x;
    EXPECT_EQ(inf.blocked[x] != 0, x <= 2);
    if (x > 2) {
      EXPECT_NEAR(inf.multiplier[x], d <= 1.0 + 1e-12 ? 1 + 4 * std::exp(-10 * (d - 0.2)) : 1.0, 1e-12) << x;
    }
  }
  // A planner pays the band: along row 0 from x = 3 to x = 13 (10 moves, each entering x = 4..13).
  GridPlannerOptions po;
  po.ou2022.inflation = o;
  ImprovedAStarPlanner p(m.grid(0.1), po, false);
  double expected = 0.0;
  for (int x = 4; x <= 13; ++x) expected += 0.1 * inflation_cost_multiplier(0.1 * x, o);
  const PlanResult r = p.plan({3, 0}, {13, 0});
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.cost, expected, 1e-9);
  EXPECT_NEAR(r.length, 1.0, 1e-12);
  // Bad values name their field.
  o.cost_radius_m = 0.1;
  try {
    validate_inflation(o);
    ADD_FAILURE() << "accepted an outer radius inside the hard one";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "inflate_cost_radius");
  }
  InflationOptions neg;
  neg.radius_m = -1;
  EXPECT_THROW(validate_inflation(neg), Error);
}

// ---- Smoothing ---------------------------------------------------------------------------------

TEST(Ou2022Smoothing, RemovesRedundantNodes) {
  // Paper Fig. 5 in small: a staircase path in the open collapses to its ends; a wall keeps the
  // corner it forces.
  Map m = empty_map(8, 6);
  const GridSearchMap open(m.w, m.h, m.blocked);
  const std::vector<Cell> stairs = {{0, 0}, {1, 0}, {2, 1}, {3, 1}, {4, 2}, {5, 2}};
  EXPECT_EQ(remove_redundant_nodes(open, stairs), (std::vector<Cell>{{0, 0}, {5, 2}}));
  for (int y = 0; y < 5; ++y) m.set(3, y, true);  // a wall with a gap at the top
  const GridSearchMap walled(m.w, m.h, m.blocked);
  const std::vector<Cell> around = {{1, 1}, {2, 2}, {2, 3}, {2, 4}, {2, 5}, {3, 5},
                                    {4, 5}, {5, 4}, {6, 3}, {6, 2}, {6, 1}};
  for (std::size_t i = 1; i < around.size(); ++i) ASSERT_TRUE(plantest::segment_free(m, around[i - 1], around[i]));
  const std::vector<Cell> pruned = remove_redundant_nodes(walled, around);
  ASSERT_GE(pruned.size(), 3u);
  EXPECT_EQ(pruned.front(), (Cell{1, 1}));
  EXPECT_EQ(pruned.back(), (Cell{6, 1}));
  for (std::size_t i = 1; i < pruned.size(); ++i) EXPECT_TRUE(plantest::segment_free(m, pruned[i - 1], pruned[i]));
  // Two diagonal obstacles touching at a corner: a segment through that corner is refused (the
  // supercover rule), so the middle vertex stays.
  Map d = empty_map(3, 3);
  d.set(1, 0, true);
  d.set(0, 1, true);
  d.set(2, 1, true);
  const GridSearchMap diag(d.w, d.h, d.blocked);
  EXPECT_EQ(remove_redundant_nodes(diag, std::vector<Cell>{{0, 0}, {1, 1}, {2, 2}}).size(), 3u);
  EXPECT_TRUE(remove_redundant_nodes(open, std::vector<Cell>{}).empty());
  EXPECT_EQ(remove_redundant_nodes(open, std::vector<Cell>{{2, 2}}).size(), 1u);
}

// ---- Which planner takes which feature -----------------------------------------------------------

TEST(Ou2022Planners, JpsRefusesSearchFeatures) {
  const OccupancyGrid grid = empty_map(8, 8).grid();
  auto field_of = [&](const char* planner, GridPlannerOptions o) -> std::string {
    try {
      make_grid_planner(planner, grid, o);
    } catch (const Error& e) {
      return e.field();
    }
    return "accepted";
  };
  GridPlannerOptions turn;
  turn.ou2022.turn_cost = 1.0;
  GridPlannerOptions graded;
  graded.ou2022.inflation.cost_radius_m = 2.0;
  GridPlannerOptions exact;
  exact.ou2022.turn_exact = true;
  GridPlannerOptions weighted;
  weighted.ou2022.adaptive_weight = true;
  GridPlannerOptions hard_smooth;
  hard_smooth.ou2022.inflation.radius_m = 1.0;
  hard_smooth.ou2022.smoothing = PathSmoothing::LineOfSight;
  for (const char* planner : {"jps", "jpsplus", "dijkstra", "thetastar"}) {
    SCOPED_TRACE(planner);
    EXPECT_EQ(field_of(planner, turn), "turn_cost");
    EXPECT_EQ(field_of(planner, graded), "inflate_cost_radius");
    EXPECT_EQ(field_of(planner, exact), "turn_exact");
    EXPECT_EQ(field_of(planner, weighted), "adaptive_weight");
    EXPECT_EQ(field_of(planner, hard_smooth), "accepted");
  }
  for (const char* planner : {"astar", "ou2022"}) {
    EXPECT_EQ(field_of(planner, turn), "accepted");
    EXPECT_EQ(field_of(planner, graded), "accepted");
    EXPECT_EQ(field_of(planner, exact), "accepted");
    EXPECT_EQ(field_of(planner, weighted), "accepted");
  }
  GridPlannerOptions bad;
  bad.ou2022.turn_cost = -1.0;
  EXPECT_EQ(field_of("astar", bad), "turn_cost");
  bad.ou2022.turn_cost = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(field_of("ou2022", bad), "turn_cost");
}

TEST(Ou2022Planners, JpsWithInflationAndSmoothing) {
  // A wall with a gap: JPS on the inflated map keeps R away from the wall, and smoothing leaves
  // few vertices; the unsmoothed grid path is kept.
  Map m = empty_map(20, 12);
  for (int y = 0; y < 12; ++y)
    if (y < 4 || y > 7) m.set(10, y, true);
  GridPlannerOptions o;
  o.ou2022.inflation.radius_m = 1.0;
  o.ou2022.smoothing = PathSmoothing::LineOfSight;
  auto jps = make_grid_planner("jps", m.grid(), o);
  EXPECT_EQ(jps->name(), "jps");
  const PlanResult r = jps->plan({2, 1}, {17, 10});
  ASSERT_TRUE(r.found());
  const std::vector<Cell>& raw = jps->unsmoothed_path();
  ASSERT_GT(raw.size(), r.path_cells.size());
  EXPECT_LE(r.length, compute_path_metrics(cell_centres(raw, m.grid().geometry())).length + 1e-9);
  const InflatedMap inf = inflate_obstacles(m.grid(), {}, false, o.ou2022.inflation);
  Map inflated{m.w, m.h, inf.blocked};
  for (const Cell& c : raw) EXPECT_TRUE(inflated.free(c.x, c.y));
  for (std::size_t i = 1; i < r.path_cells.size(); ++i)
    EXPECT_TRUE(plantest::segment_free(inflated, r.path_cells[i - 1], r.path_cells[i]));
  // The same query without smoothing returns the grid path itself.
  o.ou2022.smoothing = PathSmoothing::None;
  const PlanResult plain = make_grid_planner("jps", m.grid(), o)->plan({2, 1}, {17, 10});
  EXPECT_EQ(plain.path_cells, raw);
  EXPECT_NEAR(plain.cost, r.cost, 1e-9);
}

}  // namespace
}  // namespace starnav
