// D* Lite: after every batch of random cell edits and start moves, the repaired answer costs the
// same as a search from scratch (reference Dijkstra and A*), with a valid path on the current map.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "plan/plan_test_maps.hpp"
#include "starnav/core/error.hpp"
#include "starnav/plan/dstar_lite.hpp"
#include "starnav/plan/grid_planner.hpp"

namespace starnav {
namespace {

using plantest::Map;

using test::scaled;

testing::AssertionResult valid_path_on(const Map& m, int connectivity, const PlanResult& r, Cell s, Cell g) {
  if (r.path_cells.empty() || !(r.path_cells.front() == s) || !(r.path_cells.back() == g))
    return testing::AssertionFailure() << "wrong ends";
  double sum = 0.0;
  for (std::size_t i = 1; i < r.path_cells.size(); ++i) {
    const Cell a = r.path_cells[i - 1], b = r.path_cells[i];
    const int dx = b.x - a.x, dy = b.y - a.y;
    if (std::abs(dx) > 1 || std::abs(dy) > 1 || (dx == 0 && dy == 0) || !m.free(b.x, b.y))
      return testing::AssertionFailure() << "bad step";
    if (dx != 0 && dy != 0) {
      if (connectivity != 8 || !m.free(a.x + dx, a.y) || !m.free(a.x, a.y + dy))
        return testing::AssertionFailure() << "corner cut";
      sum += std::sqrt(2.0);
    } else {
      sum += 1.0;
    }
  }
  if (std::abs(sum - r.cost) > 1e-9 * std::max(1.0, sum)) return testing::AssertionFailure() << "cost != steps";
  return testing::AssertionSuccess();
}

TEST(DStarLite, RepairedAnswersEqualSearchesFromScratch) {
  Rng rng(2002);
  int replans = 0, changed_answers = 0;
  for (int i = 0; i < scaled(250); ++i) {
    Map m = plantest::any_map(rng, i, 8 + static_cast<int>(rng.uniform_int(0, 22)));
    const int connectivity = (i % 3 == 0) ? 4 : 8;
    GridPlannerOptions opt;
    opt.connectivity = connectivity;
    DStarLite dstar(m.grid(), opt);
    Cell start = plantest::random_free_cell(rng, m);
    const Cell goal = plantest::random_free_cell(rng, m);
    if (start.x < 0) continue;
    PlanResult r = dstar.plan(start, goal);
    double previous = -1.0;
    for (int round = 0; round < 12; ++round) {
      // The answer now, from scratch.
      const double optimal = plantest::reference_dijkstra(m, connectivity, start.x, start.y)[m.index(goal.x, goal.y)];
      const PlanResult astar = make_grid_planner("astar", m.grid(), opt)->plan(start, goal);
      SCOPED_TRACE("map " + std::to_string(i) + " round " + std::to_string(round));
      if (!m.free(start.x, start.y)) {
        ASSERT_EQ(r.status, PlanStatus::StartBlocked);
      } else if (!m.free(goal.x, goal.y)) {
        ASSERT_EQ(r.status, PlanStatus::GoalBlocked);
      } else if (std::isinf(optimal)) {
        ASSERT_EQ(r.status, PlanStatus::NoPath);
        ASSERT_EQ(astar.status, PlanStatus::NoPath);
      } else {
        ASSERT_EQ(r.status, PlanStatus::Found);
        ASSERT_NEAR(r.cost, optimal, 1e-9 * optimal);
        ASSERT_NEAR(r.cost, astar.cost, 1e-9 * optimal);
        ASSERT_TRUE(valid_path_on(m, connectivity, r, start, goal));
        if (previous >= 0.0 && std::abs(previous - r.cost) > 1e-9) ++changed_answers;
        previous = r.cost;
      }
      // Change the world: a few cells flip (often near the current path), the robot may move.
      std::vector<CellChange> changes;
      const int n_changes = static_cast<int>(rng.uniform_int(1, 6));
      for (int k = 0; k < n_changes; ++k) {
        Cell c{static_cast<int>(rng.uniform_int(0, m.w - 1)), static_cast<int>(rng.uniform_int(0, m.h - 1))};
        if (r.found() && rng.bernoulli(0.6)) c = r.path_cells[rng.uniform_int(0, static_cast<std::int64_t>(r.path_cells.size()) - 1)];
        if (c == goal && rng.bernoulli(0.8)) continue;
        const bool block = m.free(c.x, c.y);
        changes.push_back({c, block ? kOccupiedOccupancy : kFreeOccupancy});
        m.set(c.x, c.y, block);
      }
      dstar.update_cells(changes);
      if (r.found() && r.path_cells.size() > 1 && rng.bernoulli(0.7)) {
        const std::size_t steps = static_cast<std::size_t>(rng.uniform_int(1, std::min<std::int64_t>(4, static_cast<std::int64_t>(r.path_cells.size()) - 1)));
        start = r.path_cells[steps];
        dstar.move_start(start);
      }
      r = dstar.replan();
      ++replans;
    }
  }
  EXPECT_GT(replans, 1000);
  EXPECT_GT(changed_answers, 100);  // the edits do change the answers
}

TEST(DStarLite, RepairsWithFewerExpansionsThanFromScratchOnSmallChanges) {
  Rng rng(31);
  Map m = plantest::random_obstacles(rng, 120, 120, 0.2);
  m.set(0, 0, false);
  m.set(119, 119, false);
  DStarLite dstar(m.grid());
  PlanResult r = dstar.plan({119, 119}, {0, 0});
  ASSERT_TRUE(r.found());
  std::uint64_t repaired = 0, scratch = 0;
  for (int k = 0; k < 20 && r.found(); ++k) {
    const Cell next = r.path_cells[1];
    dstar.move_start(next);
    const Cell c = r.path_cells[std::min<std::size_t>(r.path_cells.size() - 1, 6)];
    if (!(c == Cell{0, 0})) {
      const CellChange change{c, kOccupiedOccupancy};
      dstar.update_cells({&change, 1});
      m.set(c.x, c.y, true);
    }
    r = dstar.replan();
    const PlanResult fresh = make_grid_planner("dijkstra", m.grid())->plan(next, {0, 0});
    ASSERT_EQ(r.status, fresh.status);
    if (r.found()) {
      ASSERT_NEAR(r.cost, fresh.cost, 1e-9 * fresh.cost);
    }
    repaired += r.expanded;
    scratch += fresh.expanded;
  }
  EXPECT_LT(repaired, scratch);
}

TEST(DStarLite, ApiErrorsAndStartGoalCases) {
  Map m{5, 5, std::vector<std::uint8_t>(25, 0)};
  DStarLite d(m.grid());
  EXPECT_THROW(d.replan(), Error);
  const CellChange outside{{5, 0}, kOccupiedOccupancy};
  EXPECT_THROW(d.update_cells({&outside, 1}), Error);
  const CellChange bad_value{{1, 1}, static_cast<std::int8_t>(101)};
  EXPECT_THROW(d.update_cells({&bad_value, 1}), Error);
  EXPECT_EQ(d.plan({0, 0}, {7, 7}).status, PlanStatus::GoalOutsideMap);
  const PlanResult same = d.plan({2, 2}, {2, 2});
  ASSERT_TRUE(same.found());
  EXPECT_EQ(same.cost, 0.0);
  ASSERT_TRUE(d.plan({0, 0}, {4, 4}).found());
  d.move_start({-1, 0});
  EXPECT_EQ(d.replan().status, PlanStatus::StartOutsideMap);
  d.move_start({1, 0});
  const PlanResult back = d.replan();
  ASSERT_TRUE(back.found());
  EXPECT_NEAR(back.cost, 3 * std::sqrt(2.0) + 1.0, 1e-12);
  const CellChange block_goal{{4, 4}, kOccupiedOccupancy};
  EXPECT_EQ(d.update_cells({&block_goal, 1}), 1u);
  EXPECT_EQ(d.replan().status, PlanStatus::GoalBlocked);
  const CellChange free_goal{{4, 4}, kFreeOccupancy};
  d.update_cells({&free_goal, 1});
  EXPECT_TRUE(d.replan().found());
  const CellChange unknown{{4, 4}, kUnknownOccupancy};  // unknown is blocked by default
  EXPECT_EQ(d.update_cells({&unknown, 1}), 1u);
  EXPECT_EQ(d.replan().status, PlanStatus::GoalBlocked);
}

}  // namespace
}  // namespace starnav
