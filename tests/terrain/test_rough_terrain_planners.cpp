// OA*, AOEA* and IA*: optimality of IA* with the admissible H against an independent Dijkstra
// under the same move costs, thresholds never reached along IA* and AOEA* paths, statuses.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <queue>

#include "starnav/core/error.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"
#include "terrain_test_util.hpp"

namespace {

using namespace starnav;
using terrain_test::brute_ruggedness;
using terrain_test::geometry;
using terrain_test::random_terrain;

// The IA* move cost from the spec, written out independently: both ends observed (the tests use
// fully observed maps unless said otherwise).
struct ReferenceCosts {
  const ElevationMap* m;
  LiuCostParams p;
  std::vector<double> s;  // brute-force ruggedness

  ReferenceCosts(const ElevationMap& map, const LiuCostParams& params) : m(&map), p(params) {
    s.resize(map.cell_count());
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x) s[map.geometry().index(x, y)] = brute_ruggedness(map, x, y);
  }
  double straight_or_diagonal(int x, int y, int dx, int dy) const {
    const int i = x + dx, j = y + dy;
    if (!m->contains(i, j)) return INFINITY;
    const double res = m->resolution();
    const double d = std::sqrt(static_cast<double>(dx * dx + dy * dy)) * res;
    const double h = std::abs(m->height_at(i, j) - m->height_at(x, y));
    const double a = std::atan(h / d);
    const double sc = s[m->geometry().index(i, j)];
    if (a >= p.a_y || h >= p.h_y || sc >= p.s_y) return INFINITY;
    const double g = p.w_s * std::tan(std::numbers::pi * a / (2 * p.a_y)) +
                     p.w_e * std::tan(std::numbers::pi * h / (2 * p.h_y)) +
                     p.w_r * std::tan(std::numbers::pi * sc / (2 * p.s_y));
    return p.w1 * g * (p.cost_per_metre ? d / res : 1.0) + p.w2 * d;
  }
  double move(int x, int y, int dx, int dy) const {
    if (dx != 0 && dy != 0 &&
        (std::isinf(straight_or_diagonal(x, y, dx, 0)) || std::isinf(straight_or_diagonal(x, y, 0, dy))))
      return INFINITY;
    return straight_or_diagonal(x, y, dx, dy);
  }
};

double reference_dijkstra(const ReferenceCosts& rc, Cell start, Cell goal) {
  const int w = rc.m->width(), h = rc.m->height();
  std::vector<double> dist(static_cast<std::size_t>(w) * h, INFINITY);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> pq;
  dist[start.y * w + start.x] = 0;
  pq.push({0.0, start.y * w + start.x});
  while (!pq.empty()) {
    auto [d, id] = pq.top();
    pq.pop();
    if (d > dist[id]) continue;
    const int x = id % w, y = id / w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy) continue;
        const double c = rc.move(x, y, dx, dy);
        if (std::isinf(c)) continue;
        const int nid = (y + dy) * w + (x + dx);
        if (d + c < dist[nid]) {
          dist[nid] = d + c;
          pq.push({d + c, nid});
        }
      }
  }
  return dist[goal.y * w + goal.x];
}

// Every move of the path is an 8-neighbour move below all thresholds, diagonals with both
// straight moves beside them below the thresholds too.
void expect_path_within_thresholds(const ElevationMap& m, const std::vector<Cell>& path, const LiuCostParams& p) {
  const ReferenceCosts rc(m, p);
  for (std::size_t i = 1; i < path.size(); ++i) {
    const int dx = path[i].x - path[i - 1].x, dy = path[i].y - path[i - 1].y;
    ASSERT_TRUE(std::abs(dx) <= 1 && std::abs(dy) <= 1 && (dx || dy));
    EXPECT_TRUE(std::isfinite(rc.move(path[i - 1].x, path[i - 1].y, dx, dy))) << "move " << i;
    const double h = std::abs(m.height_at(path[i].x, path[i].y) - m.height_at(path[i - 1].x, path[i - 1].y));
    EXPECT_LT(h, p.h_y);
    EXPECT_LT(std::atan(h / (std::hypot(dx, dy) * m.resolution())), p.a_y);
    EXPECT_LT(rc.s[m.geometry().index(path[i].x, path[i].y)], p.s_y);
  }
}

LiuCostParams test_params(std::uint64_t seed) {
  LiuCostParams p;
  p.h_y = 0.045;
  p.s_y = 0.0005;
  p.cost_per_metre = seed % 2 == 0;
  if (seed % 3 == 0) {
    p.w_s = 0.2, p.w_e = 0.5, p.w_r = 0.3, p.w1 = 0.8, p.w2 = 0.2;
  }
  return p;
}

TEST(RoughTerrainPlanners, IaStarAdmissibleEqualsDijkstraOnRandomTerrains) {
  int found = 0, unreachable = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const int w = 12 + static_cast<int>(seed % 13), h = 10 + static_cast<int>(seed % 7);
    const ElevationMap m = random_terrain(seed, w, h, 0.1, 0.018);
    RoughTerrainPlannerOptions o;
    o.cost = test_params(seed);
    RoughTerrainPlanner ia(RoughTerrainPlannerKind::IA, m, o);
    EXPECT_TRUE(ia.admissible());
    Rng rng(seed * 7);
    for (int q = 0; q < 3; ++q) {
      const Cell s{static_cast<int>(rng.uniform_int(0, w - 1)), static_cast<int>(rng.uniform_int(0, h - 1))};
      const Cell g{static_cast<int>(rng.uniform_int(0, w - 1)), static_cast<int>(rng.uniform_int(0, h - 1))};
      const ReferenceCosts rc(m, o.cost);
      const double want = s == g ? 0.0 : reference_dijkstra(rc, s, g);
      const PlanResult r = ia.plan(s, g);
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " query " << q);
      if (std::isinf(want)) {
        EXPECT_FALSE(r.found());
        ++unreachable;
        continue;
      }
      ASSERT_TRUE(r.found()) << plan_status_reason(r.status);
      ++found;
      EXPECT_NEAR(r.cost, want, 1e-5 * (1.0 + want));
      EXPECT_EQ(r.path_cells.front(), s);
      EXPECT_EQ(r.path_cells.back(), g);
      expect_path_within_thresholds(m, r.path_cells, o.cost);
      // The reported cost is the path's cost under the reference.
      double again = 0.0;
      for (std::size_t i = 1; i < r.path_cells.size(); ++i)
        again += rc.move(r.path_cells[i - 1].x, r.path_cells[i - 1].y, r.path_cells[i].x - r.path_cells[i - 1].x,
                         r.path_cells[i].y - r.path_cells[i - 1].y);
      EXPECT_NEAR(r.cost, again, 1e-12 * (1.0 + again));
    }
  }
  EXPECT_GT(found, 60);   // the terrains are passable often enough to test something
  EXPECT_GT(unreachable, 0);  // and sometimes not
}

TEST(RoughTerrainPlanners, IaStarPaperHeuristicReopensAndIsNeverBelowOptimal) {
  std::uint64_t reopened = 0;
  for (std::uint64_t seed = 100; seed < 115; ++seed) {
    const ElevationMap m = random_terrain(seed, 30, 24, 0.1, 0.015);
    RoughTerrainPlannerOptions o;
    o.cost = test_params(seed);
    o.heuristic = LiuHeuristic::Paper;
    RoughTerrainPlanner paper(RoughTerrainPlannerKind::IA, m, o);
    EXPECT_FALSE(paper.admissible());
    o.heuristic = LiuHeuristic::Admissible;
    RoughTerrainPlanner exact(RoughTerrainPlannerKind::IA, m, o);
    const Cell s{1, 1}, g{28, 21};
    const PlanResult a = paper.plan(s, g);
    const PlanResult b = exact.plan(s, g);
    ASSERT_EQ(a.found(), b.found());
    if (!a.found()) continue;
    reopened += paper.reopened();
    EXPECT_GE(a.cost, b.cost - 1e-6);
    expect_path_within_thresholds(m, a.path_cells, o.cost);
    // Without reopening: weighted A* with w = 1 / w2, every state expanded at most once.
    o.heuristic = LiuHeuristic::Paper;
    o.reopen = false;
    RoughTerrainPlanner once(RoughTerrainPlannerKind::IA, m, o);
    const PlanResult c = once.plan(s, g);
    ASSERT_TRUE(c.found());
    EXPECT_EQ(once.reopened(), 0u);
    EXPECT_LE(c.expanded, 30u * 24u);
    EXPECT_GE(c.cost, b.cost - 1e-6);
    EXPECT_LE(c.cost, b.cost / o.cost.w2 + 1e-6);
    expect_path_within_thresholds(m, c.path_cells, o.cost);
  }
  EXPECT_GT(reopened, 0u);
}

TEST(RoughTerrainPlanners, AoeaStarPathsStayClearOfThresholdsAndObstacles) {
  int found = 0;
  for (std::uint64_t seed = 200; seed < 215; ++seed) {
    const ElevationMap m = random_terrain(seed, 40, 30, 0.1, 0.015);
    RoughTerrainPlannerOptions o;
    o.cost = test_params(seed);
    o.robot_radius_m = seed % 2 ? 0.1 : 0.0;
    RoughTerrainPlanner aoea(RoughTerrainPlannerKind::AOEA, m, o);
    const TerrainAnalysis& t = aoea.analysis();
    const auto raw = liu_obstacle_mask(t, o.cost);
    const auto expanded = inflate_mask(raw, 40, 30, o.robot_radius_m / 0.1);
    EXPECT_EQ(aoea.blocked_mask(), expanded);
    // A free cell far from the corners, if any, as start and goal.
    Cell s{-1, -1}, g{-1, -1};
    for (int i = 0; i < 40 * 30 && s.x < 0; ++i)
      if (!expanded[i]) s = t.geometry().cell_of_index(static_cast<std::size_t>(i));
    for (int i = 40 * 30 - 1; i >= 0 && g.x < 0; --i)
      if (!expanded[i]) g = t.geometry().cell_of_index(static_cast<std::size_t>(i));
    if (s.x < 0) continue;
    const PlanResult r = aoea.plan(s, g);
    if (!r.found()) continue;
    ++found;
    for (const Cell& c : r.path_cells) EXPECT_EQ(expanded[t.index(c.x, c.y)], 0);
    expect_path_within_thresholds(m, r.path_cells, o.cost);
    EXPECT_NEAR(r.cost, r.length, 1e-9);
  }
  EXPECT_GT(found, 3);
}

TEST(RoughTerrainPlanners, OaStarIgnoresTerrainAndFindsTheShortestPath) {
  const ElevationMap m = random_terrain(5, 30, 20, 0.1, 0.05);
  RoughTerrainPlanner oa(RoughTerrainPlannerKind::OA, m);
  const PlanResult r = oa.plan({0, 0}, {29, 12});
  ASSERT_TRUE(r.found());
  // Octile distance: 12 diagonal + 17 straight moves.
  EXPECT_NEAR(r.length, (17 + 12 * std::numbers::sqrt2) * 0.1, 1e-12);
  for (const auto v : oa.blocked_mask()) EXPECT_EQ(v, 0);
}

TEST(RoughTerrainPlanners, IaStarDetoursAroundAWall) {
  // Flat ground with a 0.1 m high wall across x = 10 except a gap at the top: IA* goes through
  // the gap; a move onto the wall would be a 0.1 m step.
  ElevationMap m(geometry(20, 12, 0.1));
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 20; ++x) m.set_height(x, y, (x == 10 && y < 9) ? 0.1 : 0.0);
  RoughTerrainPlannerOptions o;
  RoughTerrainPlanner ia(RoughTerrainPlannerKind::IA, m, o);
  const PlanResult r = ia.plan({2, 2}, {17, 2});
  ASSERT_TRUE(r.found());
  bool through_gap = false;
  for (const Cell& c : r.path_cells) {
    EXPECT_FALSE(c.x == 10 && c.y < 9);
    through_gap |= c.x == 10 && c.y >= 9;
  }
  EXPECT_TRUE(through_gap);
  // Close the gap: no path.
  for (int y = 9; y < 12; ++y) m.set_height(10, y, 0.1);
  RoughTerrainPlanner closed(RoughTerrainPlannerKind::IA, m, o);
  EXPECT_EQ(closed.plan({2, 2}, {17, 2}).status, PlanStatus::NoPath);
}

TEST(RoughTerrainPlanners, UnobservedPolicies) {
  // A band of unobserved cells across the map at x = 8..9.
  ElevationMap m(geometry(20, 10, 0.1));
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x)
      if (x < 8 || x > 9) m.set_height(x, y, 0.0);
  RoughTerrainPlannerOptions o;
  for (const auto kind : {RoughTerrainPlannerKind::OA, RoughTerrainPlannerKind::AOEA, RoughTerrainPlannerKind::IA}) {
    RoughTerrainPlanner blocked(kind, m, o);
    EXPECT_EQ(blocked.plan({2, 5}, {17, 5}).status, PlanStatus::NoPath) << rough_terrain_planner_name(kind);
    EXPECT_EQ(blocked.plan({8, 5}, {17, 5}).status, PlanStatus::StartBlocked) << rough_terrain_planner_name(kind);
    EXPECT_EQ(blocked.plan({2, 5}, {9, 5}).status, PlanStatus::GoalBlocked) << rough_terrain_planner_name(kind);
  }
  o.unobserved = UnobservedPolicy::FreeFlat;
  RoughTerrainPlanner flat(RoughTerrainPlannerKind::IA, m, o);
  PlanResult r = flat.plan({2, 5}, {17, 5});
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.cost, 15 * 0.5 * 0.1, 1e-12);  // flat everywhere: w2 * d only
  o.unobserved = UnobservedPolicy::UnknownCost;
  o.cost.unobserved_g = 2.0;
  RoughTerrainPlanner unknown(RoughTerrainPlannerKind::IA, m, o);
  r = unknown.plan({2, 5}, {17, 5});
  ASSERT_TRUE(r.found());
  // Moves 7->8, 8->9, 9->10 touch unobserved cells: 3 * w1 * 2.0 extra.
  EXPECT_NEAR(r.cost, 15 * 0.05 + 3 * 0.5 * 2.0, 1e-12);
}

TEST(RoughTerrainPlanners, StatusesAndNames) {
  const ElevationMap m = random_terrain(3, 10, 10, 0.1, 0.001);
  RoughTerrainPlanner ia(RoughTerrainPlannerKind::IA, m);
  EXPECT_EQ(ia.plan({-1, 0}, {5, 5}).status, PlanStatus::StartOutsideMap);
  EXPECT_EQ(ia.plan({0, 0}, {5, 10}).status, PlanStatus::GoalOutsideMap);
  const PlanResult same = ia.plan({4, 4}, {4, 4});
  ASSERT_TRUE(same.found());
  EXPECT_EQ(same.path_cells.size(), 1u);
  EXPECT_EQ(same.cost, 0.0);
  EXPECT_EQ(parse_rough_terrain_planner("aoea"), RoughTerrainPlannerKind::AOEA);
  EXPECT_EQ(parse_rough_terrain_planner("iastar"), RoughTerrainPlannerKind::IA);
  EXPECT_EQ(make_rough_terrain_planner("oa", m)->name(), "oa");
  try {
    parse_rough_terrain_planner("astar", "--planner");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--planner");
  }
  // A shared analysis must agree on unobserved cells.
  auto analysis = std::make_shared<const TerrainAnalysis>(m);
  RoughTerrainPlannerOptions o;
  o.unobserved = UnobservedPolicy::FreeFlat;
  EXPECT_THROW(RoughTerrainPlanner(RoughTerrainPlannerKind::IA, analysis, o), Error);
  o.unobserved = UnobservedPolicy::Blocked;
  RoughTerrainPlanner shared(RoughTerrainPlannerKind::AOEA, analysis, o);
  EXPECT_EQ(shared.blocked_mask(), analysis->expanded_obstacle_mask());
}

TEST(RoughTerrainPlanners, TraceRecordsExpansions) {
  const ElevationMap m = random_terrain(8, 20, 20, 0.1, 0.005);
  RoughTerrainPlannerOptions o;
  o.record_trace = true;
  RoughTerrainPlanner ia(RoughTerrainPlannerKind::IA, m, o);
  const PlanResult r = ia.plan({0, 0}, {19, 19});
  ASSERT_TRUE(r.found());
  EXPECT_EQ(ia.trace().size(), r.expanded);
  EXPECT_EQ(ia.trace().front(), (Cell{0, 0}));
  EXPECT_EQ(ia.trace().back(), (Cell{19, 19}));
}

TEST(RoughTerrainPlanners, TableMatchesMoveCostFunction) {
  const ElevationMap m = random_terrain(77, 15, 11, 0.1, 0.02, 0.1);
  for (const auto pol : {UnobservedPolicy::Blocked, UnobservedPolicy::FreeFlat, UnobservedPolicy::UnknownCost}) {
    TerrainAnalysisOptions ao;
    ao.unobserved = pol;
    const TerrainAnalysis t(m, ao);
    const LiuCostParams p;
    const MoveCostTable<double> table(t, p);
    for (int y = 0; y < 11; ++y)
      for (int x = 0; x < 15; ++x)
        for (int k = 0; k < kMoveCount; ++k)
          EXPECT_EQ(table.costs_of(static_cast<std::uint32_t>(t.index(x, y)))[k], ia_move_cost(t, x, y, k, p));
  }
}

}  // namespace
