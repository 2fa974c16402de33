// Dijkstra, A*, weighted A* and Theta* (and the search core under them) against the reference
// Dijkstra of plan_test_maps.hpp on thousands of random small maps; edge cases; limits; the two
// open lists; per-cell cost multipliers; no allocation inside a query after warm-up.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "plan/plan_test_maps.hpp"
#include "starnav/core/error.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/grid_planners.hpp"
#include "starnav/plan/line_of_sight.hpp"
#include "starnav/plan/search_core.hpp"

#include "plan/allocation_counter.hpp"

namespace starnav {
namespace {

using plantest::Map;

using test::long_tests;
using test::scaled;

bool adjacent_move_ok(const Map& m, int connectivity, Cell a, Cell b) {
  const int dx = b.x - a.x, dy = b.y - a.y;
  if (std::abs(dx) > 1 || std::abs(dy) > 1 || (dx == 0 && dy == 0)) return false;
  if (!m.free(b.x, b.y)) return false;
  if (dx != 0 && dy != 0) return connectivity == 8 && m.free(a.x + dx, a.y) && m.free(a.x, a.y + dy);
  return true;
}

// A grid path: starts and ends right, every step a legal move, cost = sum of the steps.
testing::AssertionResult valid_grid_path(const Map& m, int connectivity, const PlanResult& r, Cell s, Cell g,
                                         double resolution = 1.0) {
  if (r.path_cells.empty()) return testing::AssertionFailure() << "empty path";
  if (!(r.path_cells.front() == s) || !(r.path_cells.back() == g)) return testing::AssertionFailure() << "wrong ends";
  if (r.path_world.size() != r.path_cells.size()) return testing::AssertionFailure() << "world/cell sizes differ";
  double sum = 0.0;
  for (std::size_t i = 1; i < r.path_cells.size(); ++i) {
    const Cell a = r.path_cells[i - 1], b = r.path_cells[i];
    if (!adjacent_move_ok(m, connectivity, a, b))
      return testing::AssertionFailure() << "illegal move (" << a.x << "," << a.y << ")->(" << b.x << "," << b.y << ")";
    sum += (a.x != b.x && a.y != b.y) ? std::sqrt(2.0) : 1.0;
  }
  if (std::abs(sum * resolution - r.cost) > 1e-9 * std::max(1.0, r.cost))
    return testing::AssertionFailure() << "cost " << r.cost << " != sum of steps " << sum * resolution;
  return testing::AssertionSuccess();
}

bool close(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b)); }

struct Query {
  Cell start, goal;
};

std::vector<Query> queries_for(Rng& rng, const Map& m, int n) {
  std::vector<Query> q;
  for (int i = 0; i < n; ++i) q.push_back({plantest::random_free_cell(rng, m), plantest::random_free_cell(rng, m)});
  return q;
}

TEST(GridPlanners, DijkstraAStarAndWeightedAStarMatchReferenceOnRandomMaps) {
  Rng rng(20240601);
  const int maps = scaled(1200);
  int found = 0, unreachable = 0;
  for (int i = 0; i < maps; ++i) {
    const Map m = plantest::any_map(rng, i, 6 + static_cast<int>(rng.uniform_int(0, 24)));
    const int connectivity = (i % 2) ? 8 : 4;
    const OccupancyGrid grid = m.grid();
    GridPlannerOptions opt;
    opt.connectivity = connectivity;
    auto dijkstra = make_grid_planner("dijkstra", grid, opt);
    auto astar = make_grid_planner("astar", grid, opt);
    GridPlannerOptions wopt = opt;
    wopt.weight = 1.0 + static_cast<double>(rng.uniform_int(1, 8)) * 0.5;
    auto wastar = make_grid_planner("wastar", grid, wopt);
    ASSERT_TRUE(dijkstra->admissible() && astar->admissible());
    ASSERT_FALSE(wastar->admissible());
    for (const Query& q : queries_for(rng, m, 4)) {
      if (q.start.x < 0) continue;
      const auto ref = plantest::reference_dijkstra(m, connectivity, q.start.x, q.start.y);
      const double optimal = ref[m.index(q.goal.x, q.goal.y)];
      for (GridPlanner* p : {dijkstra.get(), astar.get(), wastar.get()}) {
        const PlanResult r = p->plan(q.start, q.goal);
        SCOPED_TRACE(std::string(p->name()) + " map " + std::to_string(i));
        if (std::isinf(optimal)) {
          ASSERT_EQ(r.status, PlanStatus::NoPath);
          ASSERT_TRUE(r.path_cells.empty());
          continue;
        }
        ASSERT_EQ(r.status, PlanStatus::Found);
        ASSERT_TRUE(valid_grid_path(m, connectivity, r, q.start, q.goal));
        ASSERT_TRUE(close(r.length, r.cost));
        if (p == wastar.get()) ASSERT_LE(r.cost, wopt.weight * optimal + 1e-9);
        else ASSERT_TRUE(close(r.cost, optimal)) << r.cost << " vs " << optimal;
        ASSERT_GE(r.expanded, 1u);
        ASSERT_GE(r.generated, r.expanded);
      }
      std::isinf(optimal) ? ++unreachable : ++found;
    }
  }
  EXPECT_GT(found, maps);        // the maps are not all walls
  EXPECT_GT(unreachable, maps / 50);  // and unreachable goals do occur
}

TEST(GridPlanners, OtherHeuristicsKeepTheirPromises) {
  Rng rng(77);
  for (int i = 0; i < scaled(300); ++i) {
    const Map m = plantest::any_map(rng, i, 8 + static_cast<int>(rng.uniform_int(0, 16)));
    const OccupancyGrid grid = m.grid();
    for (const char* h : {"zero", "octile", "manhattan", "euclidean"}) {
      for (int connectivity : {4, 8}) {
        GridPlannerOptions opt;
        opt.connectivity = connectivity;
        opt.heuristic = h;
        auto astar = make_grid_planner("astar", grid, opt);
        const bool admissible = !(std::string(h) == "manhattan" && connectivity == 8);
        ASSERT_EQ(astar->admissible(), admissible) << h << " " << connectivity;
        for (const Query& q : queries_for(rng, m, 2)) {
          if (q.start.x < 0) continue;
          const double optimal = plantest::reference_dijkstra(m, connectivity, q.start.x, q.start.y)[m.index(q.goal.x, q.goal.y)];
          const PlanResult r = astar->plan(q.start, q.goal);
          if (std::isinf(optimal)) {
            ASSERT_EQ(r.status, PlanStatus::NoPath);
            continue;
          }
          ASSERT_TRUE(valid_grid_path(m, connectivity, r, q.start, q.goal));
          // Manhattan on 8-connected grids overestimates by at most sqrt(2) per step: cost <= sqrt(2) * optimal.
          if (admissible) ASSERT_TRUE(close(r.cost, optimal)) << h << " " << r.cost << " vs " << optimal;
          else ASSERT_LE(r.cost, std::sqrt(2.0) * optimal + 1e-9);
        }
      }
    }
  }
}

TEST(GridPlanners, ThetaStarIsNoLongerThanAStarAndEverySegmentIsFree) {
  Rng rng(4242);
  const int maps = scaled(800);
  int shorter = 0;
  for (int i = 0; i < maps; ++i) {
    const Map m = plantest::any_map(rng, i, 6 + static_cast<int>(rng.uniform_int(0, 24)));
    const OccupancyGrid grid = m.grid();
    const int connectivity = (i % 3 == 0) ? 4 : 8;
    GridPlannerOptions opt;
    opt.connectivity = connectivity;
    auto theta = make_grid_planner("thetastar", grid, opt);
    auto astar = make_grid_planner("astar", grid, opt);
    for (const Query& q : queries_for(rng, m, 4)) {
      if (q.start.x < 0) continue;
      const PlanResult a = astar->plan(q.start, q.goal);
      const PlanResult t = theta->plan(q.start, q.goal);
      ASSERT_EQ(a.status, t.status);
      if (!t.found()) continue;
      ASSERT_TRUE(t.path_cells.front() == q.start && t.path_cells.back() == q.goal);
      ASSERT_LE(t.cost, a.cost + 1e-9) << "map " << i;
      double sum = 0.0;
      for (std::size_t k = 1; k < t.path_cells.size(); ++k) {
        const Cell p = t.path_cells[k - 1], c = t.path_cells[k];
        ASSERT_TRUE(plantest::segment_free(m, p, c))
            << "map " << i << " segment (" << p.x << "," << p.y << ")->(" << c.x << "," << c.y << ")";
        sum += std::hypot(c.x - p.x, c.y - p.y);
      }
      ASSERT_NEAR(sum, t.cost, 1e-9 * std::max(1.0, sum));
      if (t.cost < a.cost - 1e-9) ++shorter;
    }
  }
  EXPECT_GT(shorter, maps / 4);  // any-angle paths are usually strictly shorter
}

TEST(LineOfSight, AgreesWithTheExactSupercoverRule) {
  Rng rng(99);
  for (int i = 0; i < scaled(300); ++i) {
    const Map m = plantest::random_obstacles(rng, 12 + static_cast<int>(rng.uniform_int(0, 8)), 12, 0.2);
    const GridSearchMap sm(m.w, m.h, m.blocked);
    for (int k = 0; k < 50; ++k) {
      const Cell a{static_cast<int>(rng.uniform_int(0, m.w - 1)), static_cast<int>(rng.uniform_int(0, m.h - 1))};
      const Cell b{static_cast<int>(rng.uniform_int(0, m.w - 1)), static_cast<int>(rng.uniform_int(0, m.h - 1))};
      ASSERT_EQ(line_of_sight(sm, a.x, a.y, b.x, b.y), plantest::segment_free(m, a, b))
          << "(" << a.x << "," << a.y << ")->(" << b.x << "," << b.y << ")";
      ASSERT_EQ(line_of_sight(sm, a.x, a.y, b.x, b.y), line_of_sight(sm, b.x, b.y, a.x, a.y));
    }
  }
}

TEST(LineOfSight, CornerRules) {
  // . @     A segment through the shared corner of two blocked cells, or grazing one blocked
  // @ .     corner, is not free; the same as a diagonal move without corner cutting.
  Map m{3, 3, std::vector<std::uint8_t>(9, 0)};
  m.set(1, 0, true);
  const GridSearchMap one(m.w, m.h, m.blocked);
  EXPECT_FALSE(line_of_sight(one, 0, 0, 1, 1));  // grazes the corner of (1, 0)
  EXPECT_FALSE(line_of_sight(one, 0, 0, 2, 2));  // passes the corner (1, 1) of (1, 0)
  EXPECT_TRUE(line_of_sight(one, 0, 1, 2, 1));
  EXPECT_FALSE(line_of_sight(one, 0, 2, 2, 0));  // passes the grid corner (2, 1), a corner of (1, 0)
  m.set(1, 0, false);
  const GridSearchMap none(m.w, m.h, m.blocked);
  EXPECT_TRUE(line_of_sight(none, 0, 0, 2, 2));
  EXPECT_TRUE(line_of_sight(none, 0, 0, 2, 1));
}

TEST(GridPlanners, EdgeCasesForEveryPlanner) {
  // ..@.
  // ..@.
  // ..@.
  Map m{4, 3, std::vector<std::uint8_t>(12, 0)};
  for (int y = 0; y < 3; ++y) m.set(2, y, true);
  const OccupancyGrid grid = m.grid(0.5);
  for (const std::string& name : grid_planner_names()) {
    SCOPED_TRACE(name);
    auto p = make_grid_planner(name, grid);
    EXPECT_EQ(p->plan({-1, 0}, {0, 0}).status, PlanStatus::StartOutsideMap);
    EXPECT_EQ(p->plan({0, 0}, {4, 0}).status, PlanStatus::GoalOutsideMap);
    EXPECT_EQ(p->plan({0, 0}, {0, 3}).status, PlanStatus::GoalOutsideMap);
    EXPECT_EQ(p->plan({2, 1}, {0, 0}).status, PlanStatus::StartBlocked);
    EXPECT_EQ(p->plan({0, 0}, {2, 2}).status, PlanStatus::GoalBlocked);
    const PlanResult none = p->plan({0, 0}, {3, 2});
    EXPECT_EQ(none.status, PlanStatus::NoPath);
    EXPECT_TRUE(none.path_cells.empty());
    const PlanResult same = p->plan({1, 1}, {1, 1});
    ASSERT_EQ(same.status, PlanStatus::Found);
    ASSERT_EQ(same.path_cells.size(), 1u);
    EXPECT_EQ(same.cost, 0.0);
    EXPECT_EQ(same.length, 0.0);
    const PlanResult r = p->plan({0, 0}, {1, 2});
    ASSERT_EQ(r.status, PlanStatus::Found);
    // ou2022's objective adds its steering cost: one 45-degree turn, k_turn * resolution = 0.5.
    EXPECT_NEAR(r.cost,
                name == "thetastar" ? 0.5 * std::sqrt(5.0)
                : name == "ou2022"  ? 0.5 * (1 + std::sqrt(2.0)) + 0.5
                                    : 0.5 * (1 + std::sqrt(2.0)),
                1e-12);
    // World points are cell centres of the metric map (resolution 0.5, origin 0).
    EXPECT_NEAR(r.path_world.back().x(), 0.75, 1e-12);
    EXPECT_NEAR(r.path_world.back().y(), 1.25, 1e-12);
  }
  EXPECT_THROW(make_grid_planner("nosuch", grid), Error);
}

TEST(GridPlanners, OptionsAreChecked) {
  const OccupancyGrid grid = Map{3, 3, std::vector<std::uint8_t>(9, 0)}.grid();
  GridPlannerOptions bad;
  bad.connectivity = 6;
  EXPECT_THROW(make_grid_planner("astar", grid, bad), Error);
  GridPlannerOptions w;
  w.weight = 0.5;
  EXPECT_THROW(make_grid_planner("wastar", grid, w), Error);
  w.weight = 2.0;
  EXPECT_THROW(make_grid_planner("astar", grid, w), Error);
  GridPlannerOptions h;
  h.heuristic = "chebyshev";
  EXPECT_THROW(make_grid_planner("astar", grid, h), Error);
  h.heuristic = "octile";
  EXPECT_THROW(make_grid_planner("dijkstra", grid, h), Error);
  try {
    make_grid_planner("astar", grid, bad);
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "connectivity");
  }
}

TEST(GridPlanners, UnknownCellsFollowTheOption) {
  Map m{5, 1, std::vector<std::uint8_t>(5, 0)};
  OccupancyGrid grid = m.grid();
  grid(2, 0) = kUnknownOccupancy;
  GridPlannerOptions opt;
  EXPECT_EQ(make_grid_planner("astar", grid, opt)->plan({0, 0}, {4, 0}).status, PlanStatus::NoPath);
  opt.unknown_is_free = true;
  EXPECT_EQ(make_grid_planner("astar", grid, opt)->plan({0, 0}, {4, 0}).status, PlanStatus::Found);
  grid(2, 0) = 40;  // between the thresholds: occupied unless between_is_free
  opt.unknown_is_free = false;
  EXPECT_EQ(make_grid_planner("astar", grid, opt)->plan({0, 0}, {4, 0}).status, PlanStatus::NoPath);
  opt.thresholds.between_is_free = true;
  EXPECT_EQ(make_grid_planner("astar", grid, opt)->plan({0, 0}, {4, 0}).status, PlanStatus::Found);
}

TEST(GridPlanners, LimitsStopTheSearch) {
  // A cluttered map, so that no planner (not even JPS) reaches a far goal in one expansion.
  Rng rng(12);
  const Map m = plantest::random_obstacles(rng, 100, 100, 0.3);
  const OccupancyGrid grid = m.grid();
  const Cell start = plantest::random_free_cell(rng, m);
  const auto dist = plantest::reference_dijkstra(m, 8, start.x, start.y);
  Cell goal = start;
  for (int y = 0; y < m.h; ++y)
    for (int x = 0; x < m.w; ++x)
      if (std::isfinite(dist[m.index(x, y)]) && dist[m.index(x, y)] > dist[m.index(goal.x, goal.y)]) goal = {x, y};
  ASSERT_GT(dist[m.index(goal.x, goal.y)], 50.0);
  for (const std::string& name : grid_planner_names()) {
    SCOPED_TRACE(name);
    auto p = make_grid_planner(name, grid);
    SearchLimits limits;
    limits.max_expansions = 1;
    const PlanResult r = p->plan(start, goal, limits);
    EXPECT_EQ(r.status, PlanStatus::ExpansionLimit);
    EXPECT_LE(r.expanded, 1u);
    EXPECT_TRUE(r.path_cells.empty());
    std::atomic<bool> cancel{true};
    SearchLimits cancelled;
    cancelled.cancel = &cancel;
    EXPECT_EQ(p->plan(start, goal, cancelled).status, PlanStatus::Cancelled);
    cancel = false;
    EXPECT_EQ(p->plan(start, goal, cancelled).status, PlanStatus::Found);
  }
  const Map open{200, 200, std::vector<std::uint8_t>(200 * 200, 0)};
  const OccupancyGrid open_grid = open.grid();
  // A time budget is checked every 1024 expansions: a tiny budget stops Dijkstra on a big map.
  SearchLimits tiny;
  tiny.time_budget_s = 1e-9;
  EXPECT_EQ(make_grid_planner("dijkstra", open_grid)->plan({0, 0}, {199, 199}, tiny).status, PlanStatus::TimeLimit);
}

TEST(GridPlanners, TraceListsExpandedCells) {
  const Map m{20, 10, std::vector<std::uint8_t>(200, 0)};
  GridPlannerOptions opt;
  opt.record_trace = true;
  for (const char* name : {"dijkstra", "astar", "thetastar", "dstarlite"}) {
    auto p = make_grid_planner(name, m.grid(), opt);
    const PlanResult r = p->plan({0, 0}, {19, 9});
    ASSERT_TRUE(r.found());
    EXPECT_EQ(p->trace().size(), r.expanded) << name;
  }
}

// ---- The search core directly -------------------------------------------------------------------

template <class OpenList>
std::vector<std::uint64_t> run_queries(const GridSearchMap& sm, Rng rng, const Map& m, std::vector<double>& costs) {
  BestFirstSearch<std::int64_t, OpenList> search(sm.state_count());
  GridGraph<8> graph(sm);
  OctileHeuristic<std::int64_t> h(sm, UniformGridCost::kCardinal, UniformGridCost::kDiagonal);
  std::vector<std::uint64_t> stats;
  std::vector<std::uint32_t> path;
  for (int k = 0; k < 20; ++k) {
    const Cell s = plantest::random_free_cell(rng, m), g = plantest::random_free_cell(rng, m);
    h.set_goal(sm.state(g));
    const SearchOutcome o = search.run(graph, h, sm.state(s), SingleGoal{sm.state(g)});
    stats.push_back(search.stats().expanded);
    stats.push_back(search.stats().generated);
    if (o == SearchOutcome::Found) {
      search.path_to(sm.state(g), path);
      stats.insert(stats.end(), path.begin(), path.end());
      costs.push_back(UniformGridCost::to_cells(search.g(sm.state(g))));
    }
  }
  return stats;
}

TEST(SearchCore, OpenListVariantsExpandTheSameStatesInTheSameOrder) {
  Rng rng(5);
  for (int i = 0; i < scaled(60); ++i) {
    const Map m = plantest::any_map(rng, i, 30);
    const GridSearchMap sm(m.w, m.h, m.blocked);
    std::vector<double> c1, c2, c3, c4;
    const auto a = run_queries<DecreaseKeyOpenList<std::int64_t, 4>>(sm, Rng(i), m, c1);
    using Binary = DecreaseKeyOpenList<std::int64_t, 2>;
    using Lazy4 = LazyOpenList<std::int64_t, 4>;
    using Lazy2 = LazyOpenList<std::int64_t, 2>;
    EXPECT_EQ(a, run_queries<Binary>(sm, Rng(i), m, c2));
    EXPECT_EQ(a, run_queries<Lazy4>(sm, Rng(i), m, c3));
    EXPECT_EQ(a, run_queries<Lazy2>(sm, Rng(i), m, c4));
    EXPECT_EQ(c1, c3);
  }
}

TEST(SearchCore, PerCellCostMultipliersMatchReference) {
  Rng rng(8);
  for (int i = 0; i < scaled(200); ++i) {
    const Map m = plantest::any_map(rng, i, 8 + static_cast<int>(rng.uniform_int(0, 16)));
    const GridSearchMap sm(m.w, m.h, m.blocked);
    std::vector<double> mult(sm.state_count(), 1.0), plain(static_cast<std::size_t>(m.w) * m.h);
    for (int y = 0; y < m.h; ++y)
      for (int x = 0; x < m.w; ++x) plain[m.index(x, y)] = mult[sm.state(x, y)] = 1.0 + rng.uniform() * 4.0;
    CellCostMultipliers costs{mult.data(), 1.0};
    GridGraph<8, CellCostMultipliers> graph(sm, costs);
    OctileHeuristic<double> h(sm, costs.min_cardinal(), costs.min_diagonal());
    BestFirstSearch<double> search(sm.state_count());
    for (int k = 0; k < 4; ++k) {
      const Cell s = plantest::random_free_cell(rng, m), g = plantest::random_free_cell(rng, m);
      if (s.x < 0) continue;
      const auto ref = plantest::reference_dijkstra(m, 8, s.x, s.y, [&](int to, double len) { return len * plain[to]; });
      h.set_goal(sm.state(g));
      const SearchOutcome o = search.run(graph, h, sm.state(s), SingleGoal{sm.state(g)});
      const double expected = ref[m.index(g.x, g.y)];
      if (std::isinf(expected)) {
        EXPECT_EQ(o, SearchOutcome::Exhausted);
      } else {
        ASSERT_EQ(o, SearchOutcome::Found);
        EXPECT_NEAR(search.g(sm.state(g)), expected, 1e-9 * expected);
      }
    }
  }
}

TEST(SearchCore, StateIsAtMost32BytesAndWarmQueriesDoNotAllocate) {
  Rng rng(3);
  const Map m = plantest::random_obstacles(rng, 120, 100, 0.25);
  const GridSearchMap sm(m.w, m.h, m.blocked);
  BestFirstSearch<std::int64_t> search(sm.state_count());
  EXPECT_LE(search.memory().bytes_per_state(), 32u);
  GridGraph<8> graph(sm);
  OctileHeuristic<std::int64_t> h(sm, UniformGridCost::kCardinal, UniformGridCost::kDiagonal);
  std::vector<std::pair<Cell, Cell>> queries;
  for (int k = 0; k < 40; ++k) queries.push_back({plantest::random_free_cell(rng, m), plantest::random_free_cell(rng, m)});
  auto run_all = [&] {
    for (const auto& [s, g] : queries) {
      h.set_goal(sm.state(g));
      search.run(graph, h, sm.state(s), SingleGoal{sm.state(g)});
    }
  };
  run_all();  // warm-up: the open list reaches its largest size
  const long long before = test::allocation_count();
  run_all();
  EXPECT_EQ(test::allocation_count(), before);
}

TEST(SearchCore, FastDividerIsExact) {
  Rng rng(1);
  for (std::uint32_t d : {1u, 2u, 3u, 7u, 10u, 258u, 514u, 1026u, 65537u, 1000003u}) {
    const FastDivider div(d);
    for (int k = 0; k < 20000; ++k) {
      const std::uint32_t n = static_cast<std::uint32_t>(rng.uniform_int(0, 0x7FFFFFFE));
      ASSERT_EQ(div.divide(n), n / d) << n << " / " << d;
    }
    ASSERT_EQ(div.divide(0x7FFFFFFFu), 0x7FFFFFFFu / d);
  }
}

}  // namespace
}  // namespace starnav
