// JPS and JPS+ against a plain Dijkstra written here, on thousands of random small maps; the bit
// grid scans and the JPS+ tables against naive definitions; edge cases and limits.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include "plan/allocation_counter.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/bit_grid.hpp"
#include "starnav/plan/jps.hpp"
#include "starnav/plan/jps_tables.hpp"

namespace starnav {
namespace {

constexpr double kRoot2 = 1.4142135623730950488;

// ---------------------------------------------------------------------------------------------
// Maps: blocked[y * w + x] = 1 for an obstacle.
struct TestMap {
  int w = 0, h = 0;
  std::vector<std::uint8_t> blocked;
  bool free(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h && !blocked[std::size_t(y) * w + x]; }
  OccupancyGrid grid() const {
    GridGeometry g;
    g.width = w;
    g.height = h;
    g.y_down = true;
    OccupancyGrid o(g);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) o(x, y) = blocked[std::size_t(y) * w + x] ? kOccupiedOccupancy : kFreeOccupancy;
    return o;
  }
};

TestMap random_map(Rng& rng, int w, int h, double density) {
  TestMap m{w, h, std::vector<std::uint8_t>(std::size_t(w) * h, 0)};
  for (auto& b : m.blocked) b = rng.bernoulli(density) ? 1 : 0;
  return m;
}

// Rectangular rooms separated by one-cell walls with a few doors, like the MovingAI room maps.
TestMap rooms_map(Rng& rng, int w, int h, int room) {
  TestMap m{w, h, std::vector<std::uint8_t>(std::size_t(w) * h, 0)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (x % room == room - 1 || y % room == room - 1) m.blocked[std::size_t(y) * w + x] = 1;
  // Doors: open random cells of each wall segment.
  for (int y0 = 0; y0 < h; y0 += room)
    for (int x0 = 0; x0 < w; x0 += room) {
      const int wx = x0 + room - 1, wy = y0 + room - 1;
      for (int k = 0; k < 2; ++k) {
        if (wx < w) {
          const int y = y0 + static_cast<int>(rng.uniform_int(0, room - 2));
          if (y < h && rng.bernoulli(0.7)) m.blocked[std::size_t(y) * w + wx] = 0;
        }
        if (wy < h) {
          const int x = x0 + static_cast<int>(rng.uniform_int(0, room - 2));
          if (x < w && rng.bernoulli(0.7)) m.blocked[std::size_t(wy) * w + x] = 0;
        }
      }
    }
  // Some clutter inside rooms.
  for (auto& b : m.blocked)
    if (!b && rng.bernoulli(0.03)) b = 1;
  return m;
}

// A perfect maze on a lattice of corridors `corridor` cells wide (recursive backtracker),
// sometimes with extra openings so paths are not unique.
TestMap maze_map(Rng& rng, int w, int h, int corridor) {
  TestMap m{w, h, std::vector<std::uint8_t>(std::size_t(w) * h, 1)};
  const int pitch = corridor + 1;
  const int cw = std::max(1, (w + 1) / pitch), ch = std::max(1, (h + 1) / pitch);
  auto open_block = [&](int x0, int y0, int bw, int bh) {
    for (int y = y0; y < y0 + bh && y < h; ++y)
      for (int x = x0; x < x0 + bw && x < w; ++x) m.blocked[std::size_t(y) * w + x] = 0;
  };
  std::vector<char> seen(std::size_t(cw) * ch, 0);
  std::vector<std::pair<int, int>> stack{{0, 0}};
  seen[0] = 1;
  open_block(0, 0, corridor, corridor);
  while (!stack.empty()) {
    auto [cx, cy] = stack.back();
    int opts[4][2];
    int n = 0;
    const int dxs[4] = {1, -1, 0, 0}, dys[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int nx = cx + dxs[k], ny = cy + dys[k];
      if (nx >= 0 && ny >= 0 && nx < cw && ny < ch && !seen[std::size_t(ny) * cw + nx]) {
        opts[n][0] = nx;
        opts[n][1] = ny;
        ++n;
      }
    }
    if (n == 0) {
      stack.pop_back();
      continue;
    }
    const int pick = static_cast<int>(rng.uniform_int(0, n - 1));
    const int nx = opts[pick][0], ny = opts[pick][1];
    seen[std::size_t(ny) * cw + nx] = 1;
    open_block(nx * pitch, ny * pitch, corridor, corridor);
    open_block(std::min(cx, nx) * pitch + (nx != cx ? corridor : 0), std::min(cy, ny) * pitch + (ny != cy ? corridor : 0),
               nx != cx ? 1 : corridor, ny != cy ? 1 : corridor);
    stack.push_back({nx, ny});
  }
  for (auto& b : m.blocked)
    if (b && rng.bernoulli(0.04)) b = 0;
  return m;
}

// ---------------------------------------------------------------------------------------------
// Independent reference: Dijkstra from one source over the whole map.
std::vector<double> dijkstra(const TestMap& m, int sx, int sy) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(std::size_t(m.w) * m.h, inf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> pq;
  dist[std::size_t(sy) * m.w + sx] = 0;
  pq.push({0.0, sy * m.w + sx});
  while (!pq.empty()) {
    auto [d, i] = pq.top();
    pq.pop();
    if (d > dist[i]) continue;
    const int x = i % m.w, y = i / m.w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy) continue;
        const int nx = x + dx, ny = y + dy;
        if (!m.free(nx, ny)) continue;
        if (dx && dy && (!m.free(x + dx, y) || !m.free(x, y + dy))) continue;
        const double nd = d + (dx && dy ? kRoot2 : 1.0);
        const int ni = ny * m.w + nx;
        if (nd < dist[ni] - 1e-12) {
          dist[ni] = nd;
          pq.push({nd, ni});
        }
      }
  }
  return dist;
}

// Checks that `r` is a valid path from s to g on m whose step costs add up to r.cost.
void expect_valid_path(const TestMap& m, const PlanResult& r, Cell s, Cell g, const std::string& what) {
  ASSERT_FALSE(r.path_cells.empty()) << what;
  EXPECT_EQ(r.path_cells.front(), s) << what;
  EXPECT_EQ(r.path_cells.back(), g) << what;
  ASSERT_EQ(r.path_world.size(), r.path_cells.size()) << what;
  double sum = 0;
  for (std::size_t k = 0; k < r.path_cells.size(); ++k) {
    const Cell c = r.path_cells[k];
    ASSERT_TRUE(m.free(c.x, c.y)) << what << ": path cell " << k << " (" << c.x << "," << c.y << ") not free";
    if (k == 0) continue;
    const Cell p = r.path_cells[k - 1];
    const int dx = c.x - p.x, dy = c.y - p.y;
    ASSERT_TRUE(std::abs(dx) <= 1 && std::abs(dy) <= 1 && (dx || dy)) << what << ": step " << k << " not a move";
    if (dx && dy) {
      ASSERT_TRUE(m.free(p.x + dx, p.y) && m.free(p.x, p.y + dy)) << what << ": step " << k << " cuts a corner";
      sum += kRoot2;
    } else {
      sum += 1.0;
    }
  }
  EXPECT_NEAR(sum, r.cost, 1e-9 * std::max(1.0, sum)) << what;
  EXPECT_NEAR(r.length, r.cost, 1e-9 * std::max(1.0, sum)) << what;
}

struct Counters {
  long queries = 0;
  long found = 0;
};

// Runs JPS and JPS+ for `starts` random sources and `goals` random targets each.
void check_map(const TestMap& m, Rng& rng, int starts, int goals, const std::string& label, Counters& counters) {
  const OccupancyGrid grid = m.grid();
  auto jps = make_jps_planner(grid, {}, false);
  auto plus = make_jps_planner(grid, {}, true);
  std::vector<int> free_cells;
  for (int i = 0; i < m.w * m.h; ++i)
    if (!m.blocked[i]) free_cells.push_back(i);
  if (free_cells.empty()) return;
  for (int s = 0; s < starts; ++s) {
    const int si = free_cells[rng.uniform_int(0, static_cast<std::int64_t>(free_cells.size()) - 1)];
    const Cell sc{si % m.w, si / m.w};
    const std::vector<double> dist = dijkstra(m, sc.x, sc.y);
    for (int q = 0; q < goals; ++q) {
      const int gi = free_cells[rng.uniform_int(0, static_cast<std::int64_t>(free_cells.size()) - 1)];
      const Cell gc{gi % m.w, gi / m.w};
      const std::string what = label + " " + std::to_string(m.w) + "x" + std::to_string(m.h) + " (" +
                               std::to_string(sc.x) + "," + std::to_string(sc.y) + ")->(" + std::to_string(gc.x) +
                               "," + std::to_string(gc.y) + ")";
      for (GridPlanner* p : {jps.get(), plus.get()}) {
        const PlanResult r = p->plan(sc, gc);
        ++counters.queries;
        if (std::isinf(dist[gi])) {
          EXPECT_EQ(r.status, PlanStatus::NoPath) << what << " " << p->name();
          EXPECT_TRUE(r.path_cells.empty()) << what;
        } else {
          ASSERT_EQ(r.status, PlanStatus::Found) << what << " " << p->name();
          ++counters.found;
          EXPECT_NEAR(r.cost, dist[gi], 1e-9 * std::max(1.0, dist[gi])) << what << " " << p->name();
          expect_valid_path(m, r, sc, gc, what + " " + std::string(p->name()));
          EXPECT_GE(r.expanded, 1u);
          EXPECT_GE(r.generated, r.expanded);
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
TEST(JpsProperty, RandomObstacleMapsMatchDijkstra) {
  Rng rng(11);
  Counters c;
  const double densities[] = {0.0, 0.05, 0.15, 0.25, 0.35, 0.45};
  for (int i = 0; i < 900; ++i) {
    const int w = static_cast<int>(rng.uniform_int(1, 70)), h = static_cast<int>(rng.uniform_int(1, 70));
    const TestMap m = random_map(rng, w, h, densities[i % 6]);
    check_map(m, rng, 2, 4, "random d=" + std::to_string(densities[i % 6]), c);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(c.found, c.queries / 3);
}

TEST(JpsProperty, WordBoundaryWidthsMatchDijkstra) {
  // Widths and heights around one and two 64-bit words, for the row and the transposed grid.
  Rng rng(12);
  Counters c;
  const int sizes[] = {62, 63, 64, 65, 66, 127, 128, 129, 130};
  for (int a : sizes)
    for (int k = 0; k < 4; ++k) {
      const int other = static_cast<int>(rng.uniform_int(2, 24));
      const double d = 0.05 + 0.1 * k;
      check_map(random_map(rng, a, other, d), rng, 2, 6, "wide", c);
      check_map(random_map(rng, other, a, d), rng, 2, 6, "tall", c);
      if (k == 0) check_map(random_map(rng, a, a, 0.2), rng, 2, 6, "square", c);
      if (HasFatalFailure()) return;
    }
  EXPECT_GT(c.found, c.queries / 3);
}

TEST(JpsProperty, RoomMapsMatchDijkstra) {
  Rng rng(13);
  Counters c;
  for (int i = 0; i < 200; ++i) {
    const int w = static_cast<int>(rng.uniform_int(8, 90)), h = static_cast<int>(rng.uniform_int(8, 90));
    const int room = static_cast<int>(rng.uniform_int(4, 12));
    check_map(rooms_map(rng, w, h, room), rng, 2, 4, "rooms", c);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(c.found, c.queries / 3);
}

TEST(JpsProperty, MazeMapsMatchDijkstra) {
  Rng rng(14);
  Counters c;
  for (int i = 0; i < 200; ++i) {
    const int w = static_cast<int>(rng.uniform_int(5, 80)), h = static_cast<int>(rng.uniform_int(5, 80));
    const int corridor = static_cast<int>(rng.uniform_int(1, 3));
    check_map(maze_map(rng, w, h, corridor), rng, 2, 4, "maze", c);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(c.found, c.queries / 3);
}

TEST(JpsProperty, ManyQueriesOnOneMapReuseMemory) {
  // Hundreds of queries on the same planners: generation stamps must isolate them.
  Rng rng(15);
  Counters c;
  const TestMap m = random_map(rng, 97, 61, 0.3);
  check_map(m, rng, 40, 25, "reuse", c);
  EXPECT_EQ(c.queries, 40 * 25 * 2);
}

TEST(Jps, DeterministicPaths) {
  Rng rng(16);
  const TestMap m = random_map(rng, 80, 80, 0.2);
  const OccupancyGrid grid = m.grid();
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(grid, {}, plus);
    auto q = make_jps_planner(grid, {}, plus);
    for (int k = 0; k < 50; ++k) {
      const Cell s{static_cast<int>(rng.uniform_int(0, 79)), static_cast<int>(rng.uniform_int(0, 79))};
      const Cell g{static_cast<int>(rng.uniform_int(0, 79)), static_cast<int>(rng.uniform_int(0, 79))};
      const PlanResult a = p->plan(s, g);
      const PlanResult b = p->plan(s, g);
      const PlanResult c = q->plan(s, g);
      EXPECT_EQ(a.status, b.status);
      EXPECT_EQ(a.path_cells, b.path_cells);
      EXPECT_EQ(a.path_cells, c.path_cells);
      EXPECT_EQ(a.expanded, c.expanded);
      EXPECT_EQ(a.generated, c.generated);
    }
  }
}

TEST(Jps, NoAllocationInsideAQueryAfterWarmUp) {
  // After one pass over the queries (open list, path buffers sized), a query allocates only the
  // two vectors of its PlanResult (cells and world points), and nothing when there is no path.
  Rng rng(24);
  const TestMap m = random_map(rng, 150, 130, 0.3);
  const OccupancyGrid grid = m.grid();
  std::vector<std::pair<Cell, Cell>> queries;
  for (int k = 0; k < 60; ++k)
    queries.push_back({{static_cast<int>(rng.uniform_int(0, 149)), static_cast<int>(rng.uniform_int(0, 129))},
                       {static_cast<int>(rng.uniform_int(0, 149)), static_cast<int>(rng.uniform_int(0, 129))}});
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(grid, {}, plus);
    for (const auto& [s, g] : queries) (void)p->plan(s, g);
    int found = 0;
    for (const auto& [s, g] : queries) {
      const long long before = test::allocation_count();
      const PlanResult r = p->plan(s, g);
      const long long allocations = test::allocation_count() - before;
      EXPECT_LE(allocations, r.found() ? 2 : 0) << plan_status_reason(r.status);
      found += r.found();
    }
    EXPECT_GT(found, 10);
  }
}

TEST(Jps, StartEqualsGoal) {
  Rng rng(17);
  const TestMap m = random_map(rng, 10, 10, 0.0);
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(m.grid(), {}, plus);
    const PlanResult r = p->plan({3, 4}, {3, 4});
    ASSERT_EQ(r.status, PlanStatus::Found);
    ASSERT_EQ(r.path_cells.size(), 1u);
    EXPECT_EQ(r.path_cells[0], (Cell{3, 4}));
    EXPECT_EQ(r.cost, 0.0);
    EXPECT_EQ(r.length, 0.0);
  }
}

TEST(Jps, BlockedOutsideAndUnreachable) {
  TestMap m{7, 5, std::vector<std::uint8_t>(35, 0)};
  for (int y = 0; y < 5; ++y) m.blocked[std::size_t(y) * 7 + 3] = 1;  // a wall splits the map
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(m.grid(), {}, plus);
    EXPECT_EQ(p->plan({-1, 0}, {0, 0}).status, PlanStatus::StartOutsideMap);
    EXPECT_EQ(p->plan({0, 5}, {0, 0}).status, PlanStatus::StartOutsideMap);
    EXPECT_EQ(p->plan({0, 0}, {7, 0}).status, PlanStatus::GoalOutsideMap);
    EXPECT_EQ(p->plan({0, 0}, {0, -3}).status, PlanStatus::GoalOutsideMap);
    EXPECT_EQ(p->plan({3, 2}, {0, 0}).status, PlanStatus::StartBlocked);
    EXPECT_EQ(p->plan({0, 0}, {3, 1}).status, PlanStatus::GoalBlocked);
    const PlanResult r = p->plan({0, 0}, {6, 4});
    EXPECT_EQ(r.status, PlanStatus::NoPath);
    EXPECT_FALSE(r.found());
    EXPECT_TRUE(r.path_cells.empty());
    EXPECT_GE(r.expanded, 1u);
    const PlanResult ok = p->plan({0, 0}, {2, 4});
    ASSERT_EQ(ok.status, PlanStatus::Found);
    EXPECT_NEAR(ok.cost, 2 * kRoot2 + 2, 1e-12);
  }
}

TEST(Jps, NoCornerCutting) {
  // . @
  // @ .   the diagonal between the free cells is not a move; no path.
  TestMap m{2, 2, {0, 1, 1, 0}};
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(m.grid(), {}, plus);
    EXPECT_EQ(p->plan({0, 0}, {1, 1}).status, PlanStatus::NoPath);
    EXPECT_EQ(p->plan({1, 1}, {0, 0}).status, PlanStatus::NoPath);
  }
  // . . .
  // . @ .   from (0,1) to (2,1): both diagonals next to the block cut its corner, so the way
  // . . .   around is four straight moves.
  TestMap b{3, 3, {0, 0, 0, 0, 1, 0, 0, 0, 0}};
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(b.grid(), {}, plus);
    const PlanResult r = p->plan({0, 1}, {2, 1});
    ASSERT_TRUE(r.found());
    EXPECT_NEAR(r.cost, 4.0, 1e-12);  // (0,1)->(0,0)->(1,0)->(2,0)->(2,1): corners are blocked
    expect_valid_path(b, r, {0, 1}, {2, 1}, "around");
  }
}

TEST(Jps, OptionsThatCannotBeHonouredThrow) {
  const TestMap m{4, 4, std::vector<std::uint8_t>(16, 0)};
  GridPlannerOptions o;
  o.connectivity = 4;
  EXPECT_THROW(make_jps_planner(m.grid(), o, false), Error);
  EXPECT_THROW(make_jps_planner(m.grid(), o, true), Error);
  o = {};
  o.weight = 2.0;
  EXPECT_THROW(make_jps_planner(m.grid(), o, false), Error);
  o = {};
  o.heuristic = "manhattan";
  EXPECT_THROW(make_jps_planner(m.grid(), o, true), Error);
  o = {};
  o.heuristic = "octile";
  EXPECT_NO_THROW(make_jps_planner(m.grid(), o, true));
  try {
    GridPlannerOptions c4;
    c4.connectivity = 4;
    make_jps_planner(m.grid(), c4, false);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "connectivity");
  }
}

TEST(Jps, UnknownCellsFollowTheOption) {
  GridGeometry g;
  g.width = 5;
  g.height = 1;
  OccupancyGrid grid(g);
  grid(2, 0) = kUnknownOccupancy;
  grid(4, 0) = 50;  // between the thresholds: occupied by default
  for (bool plus : {false, true}) {
    auto blocked = make_jps_planner(grid, {}, plus);
    EXPECT_EQ(blocked->plan({0, 0}, {3, 0}).status, PlanStatus::NoPath);
    GridPlannerOptions o;
    o.unknown_is_free = true;
    auto optimistic = make_jps_planner(grid, o, plus);
    const PlanResult r = optimistic->plan({0, 0}, {3, 0});
    ASSERT_TRUE(r.found());
    EXPECT_EQ(r.path_cells.size(), 4u);
    EXPECT_EQ(optimistic->plan({0, 0}, {4, 0}).status, PlanStatus::GoalBlocked);
    o.thresholds.between_is_free = true;
    auto lenient = make_jps_planner(grid, o, plus);
    EXPECT_TRUE(lenient->plan({0, 0}, {4, 0}).found());
  }
}

TEST(Jps, MetricResolutionScalesCost) {
  GridGeometry g;
  g.width = 6;
  g.height = 4;
  g.resolution = 0.05;
  g.origin = Pose2(1.0, -2.0, 0.0);
  const OccupancyGrid grid(g);
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(grid, {}, plus);
    const PlanResult r = p->plan({0, 0}, {5, 3});
    ASSERT_TRUE(r.found());
    EXPECT_NEAR(r.cost, (2 + 3 * kRoot2) * 0.05, 1e-12);
    EXPECT_NEAR(r.path_world.front().x(), 1.025, 1e-12);
    EXPECT_NEAR(r.path_world.back().y(), -2.0 + 3.5 * 0.05, 1e-12);
  }
}

TEST(Jps, LimitsStopTheSearch) {
  Rng rng(18);
  const TestMap m = random_map(rng, 120, 120, 0.3);
  // The corners may be blocked: clear a start and a goal.
  TestMap open = m;
  open.blocked[0] = 0;
  open.blocked.back() = 0;
  const OccupancyGrid grid = open.grid();
  for (bool plus : {false, true}) {
    auto p = make_jps_planner(grid, {}, plus);
    const PlanResult full = p->plan({0, 0}, {119, 119});
    if (!full.found() || full.expanded < 3) continue;
    SearchLimits lim;
    lim.max_expansions = 2;
    const PlanResult r = p->plan({0, 0}, {119, 119}, lim);
    EXPECT_EQ(r.status, PlanStatus::ExpansionLimit);
    EXPECT_EQ(r.expanded, 2u);
    EXPECT_TRUE(r.path_cells.empty());
    std::atomic<bool> cancel{true};
    SearchLimits lc;
    lc.cancel = &cancel;
    EXPECT_EQ(p->plan({0, 0}, {119, 119}, lc).status, PlanStatus::Cancelled);
    SearchLimits lt;
    lt.time_budget_s = 1e-12;
    const PlanResult t = p->plan({0, 0}, {119, 119}, lt);
    EXPECT_EQ(t.status, PlanStatus::TimeLimit);
    // And the planner still answers normally afterwards.
    const PlanResult again = p->plan({0, 0}, {119, 119});
    EXPECT_EQ(again.path_cells, full.path_cells);
  }
}

TEST(Jps, TraceRecordsExpandedJumpPoints) {
  Rng rng(19);
  const TestMap m = random_map(rng, 40, 40, 0.2);
  GridPlannerOptions o;
  o.record_trace = true;
  auto p = make_jps_planner(m.grid(), o, false);
  for (int k = 0; k < 10; ++k) {
    const Cell s{static_cast<int>(rng.uniform_int(0, 39)), static_cast<int>(rng.uniform_int(0, 39))};
    const Cell g{static_cast<int>(rng.uniform_int(0, 39)), static_cast<int>(rng.uniform_int(0, 39))};
    const PlanResult r = p->plan(s, g);
    if (r.status != PlanStatus::Found && r.status != PlanStatus::NoPath) continue;
    EXPECT_EQ(p->trace().size(), r.expanded);
    for (const Cell& c : p->trace()) EXPECT_TRUE(m.free(c.x, c.y));
  }
}

// ---------------------------------------------------------------------------------------------
// The bit grid's scans against a cell-by-cell definition.
std::uint32_t naive_scan(const TestMap& m, int x, int y, int dx, int dy, int tx, int ty) {
  // Steps from (x, y) along (dx, dy) to the first jump point or to the target, 0 at a wall.
  for (int k = 1;; ++k) {
    const int cx = x + k * dx, cy = y + k * dy;
    if (cx == tx && cy == ty) return static_cast<std::uint32_t>(k);
    if (!m.free(cx, cy)) return 0;
    const int px = dy, py = dx;
    const bool forced = (m.free(cx + px, cy + py) && !m.free(cx - dx + px, cy - dy + py)) ||
                        (m.free(cx - px, cy - py) && !m.free(cx - dx - px, cy - dy - py));
    if (forced) return static_cast<std::uint32_t>(k);
  }
}

TEST(BitGrid, ScansMatchNaiveDefinition) {
  Rng rng(20);
  const int widths[] = {1, 2, 5, 62, 63, 64, 65, 66, 126, 127, 128, 129, 190, 200};
  for (int w : widths)
    for (int rep = 0; rep < 6; ++rep) {
      const int h = static_cast<int>(rng.uniform_int(1, 7));
      const TestMap m = random_map(rng, w, h, 0.05 + 0.08 * rep);
      const BitGrid rows(m.blocked, w, h, false);
      const BitGrid cols(m.blocked, w, h, true);
      EXPECT_EQ(rows.stride() % 64, 0u);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          ASSERT_EQ(rows.free(x, y), m.free(x, y));
          ASSERT_EQ(cols.free(y, x), m.free(x, y));
          if (!m.free(x, y)) continue;
          // A random target somewhere on the map (often on the same row or column).
          const int tx = rng.bernoulli(0.5) ? static_cast<int>(rng.uniform_int(0, w - 1)) : x;
          const int ty = rng.bernoulli(0.5) ? y : static_cast<int>(rng.uniform_int(0, h - 1));
          const std::uint32_t tr = rows.index(tx, ty), tc = cols.index(ty, tx);
          ASSERT_EQ(rows.scan_forward(rows.index(x, y), tr), naive_scan(m, x, y, 1, 0, tx, ty)) << w << " " << x << "," << y;
          ASSERT_EQ(rows.scan_backward(rows.index(x, y), tr), naive_scan(m, x, y, -1, 0, tx, ty)) << w << " " << x << "," << y;
          ASSERT_EQ(cols.scan_forward(cols.index(y, x), tc), naive_scan(m, x, y, 0, 1, tx, ty)) << w << " " << x << "," << y;
          ASSERT_EQ(cols.scan_backward(cols.index(y, x), tc), naive_scan(m, x, y, 0, -1, tx, ty)) << w << " " << x << "," << y;
        }
    }
}

TEST(BitGrid, RejectsBadSizes) {
  std::vector<std::uint8_t> none;
  EXPECT_THROW(BitGrid(none, 0, 3, false), Error);
  std::vector<std::uint8_t> four(4, 0);
  EXPECT_THROW(BitGrid(four, 3, 3, false), Error);
}

// The JPS+ table against walking the definitions cell by cell.
int naive_straight(const TestMap& m, int x, int y, int dx, int dy) {
  for (int k = 1;; ++k) {
    const int cx = x + k * dx, cy = y + k * dy;
    if (!m.free(cx, cy)) return -(k - 1);
    const int px = dy, py = dx;
    const bool forced = (m.free(cx + px, cy + py) && !m.free(cx - dx + px, cy - dy + py)) ||
                        (m.free(cx - px, cy - py) && !m.free(cx - dx - px, cy - dy - py));
    if (forced) return k;
  }
}

// `straight[(y * w + x) * 4 + d]` holds naive_straight for the straight direction d (0..3).
int naive_diagonal(const TestMap& m, const std::vector<int>& straight, int x, int y, int dx, int dy) {
  const int hdir = dx > 0 ? kJpsEast : kJpsWest, vdir = dy > 0 ? kJpsSouth : kJpsNorth;
  for (int k = 1;; ++k) {
    const int px = x + (k - 1) * dx, py = y + (k - 1) * dy;
    if (!m.free(px + dx, py) || !m.free(px, py + dy) || !m.free(px + dx, py + dy)) return -(k - 1);
    const std::size_t c = static_cast<std::size_t>((py + dy) * m.w + px + dx) * 4;
    if (straight[c + static_cast<std::size_t>(hdir)] > 0 || straight[c + static_cast<std::size_t>(vdir)] > 0) return k;
  }
}

// The exact distance a table entry stands for, following hop entries.
int decode(const JumpTable& t, const TestMap& m, int x, int y, int dir) {
  int travelled = 0;
  for (;;) {
    const std::int8_t v = t.at(static_cast<std::uint32_t>(y * m.w + x), dir);
    if (v != kJumpHop) return v > 0 ? travelled + v : -(travelled - v);
    travelled += kJumpHopSteps;
    x += kJpsDx[dir] * kJumpHopSteps;
    y += kJpsDy[dir] * kJumpHopSteps;
  }
}

void expect_table_matches(const TestMap& m) {
  const BitGrid rows(m.blocked, m.w, m.h, false);
  const JumpTable table(rows);
  std::vector<int> straight(static_cast<std::size_t>(m.w) * m.h * 4, 0);
  for (int y = 0; y < m.h; ++y)
    for (int x = 0; x < m.w; ++x)
      if (m.free(x, y))
        for (int d = 0; d < 4; ++d)
          straight[static_cast<std::size_t>(y * m.w + x) * 4 + d] = naive_straight(m, x, y, kJpsDx[d], kJpsDy[d]);
  for (int y = 0; y < m.h; ++y)
    for (int x = 0; x < m.w; ++x) {
      if (!m.free(x, y)) continue;
      for (int d = 0; d < 8; ++d) {
        const int expect = d < 4 ? straight[static_cast<std::size_t>(y * m.w + x) * 4 + d]
                                 : naive_diagonal(m, straight, x, y, kJpsDx[d], kJpsDy[d]);
        ASSERT_EQ(decode(table, m, x, y, d), expect) << m.w << "x" << m.h << " cell " << x << "," << y << " dir " << d;
      }
    }
}

TEST(JumpTable, MatchesNaiveDefinition) {
  Rng rng(21);
  for (int rep = 0; rep < 40; ++rep) {
    const int w = static_cast<int>(rng.uniform_int(1, 70)), h = static_cast<int>(rng.uniform_int(1, 70));
    const TestMap m = rep % 3 == 0 ? rooms_map(rng, std::max(w, 8), std::max(h, 8), 5)
                                   : random_map(rng, w, h, 0.1 * (rep % 5));
    expect_table_matches(m);
    if (HasFatalFailure()) return;
  }
}

TEST(JumpTable, LongRunsUseHopEntries) {
  // Runs longer than one byte can hold: open maps and sparse obstacles, 300 cells across.
  Rng rng(22);
  for (const auto& [w, h] : {std::pair{300, 9}, std::pair{9, 300}, std::pair{260, 140}}) {
    for (double d : {0.0, 0.002, 0.01}) {
      expect_table_matches(random_map(rng, w, h, d));
      if (HasFatalFailure()) return;
    }
  }
}

TEST(JpsProperty, GoalsAtHopBoundaries) {
  // On an open map the answer is the octile distance; goals 126..128 and 253..255 cells away
  // sit just before, on and after the end of one or two hop entries of the JPS+ table.
  const TestMap m{300, 300, std::vector<std::uint8_t>(300 * 300, 0)};
  const OccupancyGrid grid = m.grid();
  auto plus = make_jps_planner(grid, {}, true);
  auto jps = make_jps_planner(grid, {}, false);
  auto octile = [](Cell a, Cell b) {
    const int dx = std::abs(a.x - b.x), dy = std::abs(a.y - b.y);
    return std::abs(dx - dy) + std::min(dx, dy) * kRoot2;
  };
  const Cell starts[] = {{0, 0}, {299, 299}, {0, 299}, {299, 0}, {3, 150}};
  for (const Cell s : starts)
    for (int k : {1, 126, 127, 128, 253, 254, 255, 296}) {
      const int sx = s.x < 150 ? 1 : -1, sy = s.y < 150 ? 1 : -1;
      const Cell goals[] = {{s.x + sx * k, s.y}, {s.x, s.y + sy * k}, {s.x + sx * k, s.y + sy * k},
                            {s.x + sx * k, s.y + sy * std::min(k, 3)}, {s.x + sx * std::min(k, 5), s.y + sy * k}};
      for (const Cell g : goals) {
        if (!m.free(g.x, g.y)) continue;
        for (GridPlanner* p : {plus.get(), jps.get()}) {
          const PlanResult r = p->plan(s, g);
          ASSERT_TRUE(r.found()) << p->name() << " " << s.x << "," << s.y << " -> " << g.x << "," << g.y;
          EXPECT_NEAR(r.cost, octile(s, g), 1e-9) << p->name() << " " << s.x << "," << s.y << " -> " << g.x << "," << g.y;
          expect_valid_path(m, r, s, g, "hop boundary");
        }
      }
    }
}

TEST(JpsProperty, LongOpenRunsMatchDijkstra) {
  // JPS+ hops over runs longer than 127 cells; the goal may lie within or beyond a hop.
  Rng rng(23);
  Counters c;
  for (const auto& [w, h] : {std::pair{400, 6}, std::pair{6, 400}, std::pair{300, 300}, std::pair{270, 40}}) {
    for (double d : {0.0, 0.001, 0.005, 0.02}) {
      TestMap m = random_map(rng, w, h, d);
      check_map(m, rng, 3, 8, "long runs", c);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(c.found, c.queries / 2);
}

}  // namespace
}  // namespace starnav
