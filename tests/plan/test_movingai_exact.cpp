// Exactness on the MovingAI benchmarks (docs/benchmarks.md), a small sample for `make test`: the first
// instances and a few spread over the file (so long paths too) of one map per family (including brc201d's unsolvable length-0 problems and the
// street maps' CRLF files), solved by astar and dijkstra, and by wastar within its bound.
// |cost - optimal| <= max(0.01, 1e-5 * optimal): published lengths carry up to 0.005 of rounding.
// The full sets run in `make bench` (starnav bench movingai).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "starnav/io/movingai.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::long_tests;

void check_map(const std::string& family_and_name, std::size_t instances) {
  const std::string map_path = test::shared_path("benchmarks/movingai/" + family_and_name + ".map");
  const std::string scen_path = test::shared_path("benchmarks/movingai/" + family_and_name + ".map.scen");
  ASSERT_FALSE(map_path.empty() || scen_path.empty()) << family_and_name;
  const OccupancyGrid grid = read_movingai_map(map_path).to_occupancy();
  const MovingAiScenario scen = read_movingai_scenario(scen_path);
  ASSERT_FALSE(scen.entries.empty());
  GridPlannerOptions wopt;
  wopt.weight = 2.0;
  auto astar = make_grid_planner("astar", grid);
  auto dijkstra = make_grid_planner("dijkstra", grid);
  auto wastar = make_grid_planner("wastar", grid, wopt);
  std::vector<std::size_t> sample;
  for (std::size_t i = 0; i < scen.entries.size(); ++i)
    if (long_tests() || i < instances) sample.push_back(i);
  if (!long_tests())  // plus 5 spread over the rest (later lines have longer paths)
    for (std::size_t k = 1; k <= 5 && instances < scen.entries.size(); ++k)
      sample.push_back(instances + (scen.entries.size() - instances) * k / 6);
  for (const std::size_t i : sample) {
    const ScenarioEntry& e = scen.entries[i];
    const Cell s{e.start_x, e.start_y}, g{e.goal_x, e.goal_y};
    for (GridPlanner* p : {astar.get(), dijkstra.get(), wastar.get()}) {
      SCOPED_TRACE(family_and_name + " instance " + std::to_string(i) + " " + std::string(p->name()));
      const PlanResult r = p->plan(s, g);
      if (e.unsolvable()) {
        EXPECT_EQ(r.status, PlanStatus::NoPath);
        continue;
      }
      ASSERT_EQ(r.status, PlanStatus::Found);
      const double tolerance = std::max(0.01, 1e-5 * e.optimal_length);
      if (p->admissible()) EXPECT_LE(std::abs(r.cost - e.optimal_length), tolerance) << r.cost << " vs " << e.optimal_length;
      else EXPECT_LE(r.cost, 2.0 * e.optimal_length + tolerance);
      EXPECT_EQ(r.path_cells.front(), s);
      EXPECT_EQ(r.path_cells.back(), g);
    }
  }
}

TEST(MovingAiExact, BaldursGate) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("bg512/AR0011SR", 20);
}
TEST(MovingAiExact, DragonAgeWithUnsolvableProblems) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("dao/brc201d", 20);  // lines 1-10 are length 0: no path
  check_map("dao/den520d", 20);
}
TEST(MovingAiExact, DragonAge2) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("da2/ht_keep", 20);
}
TEST(MovingAiExact, Maze) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("maze/maze512-4-0", 20);
}
TEST(MovingAiExact, Random) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("random/random512-25-0", 20);
}
TEST(MovingAiExact, Room) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("room/32room_000", 20);
}
TEST(MovingAiExact, StarCraft) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("sc1/Aurora", 20);
}
TEST(MovingAiExact, StreetCrlfAndStartEqualsGoal) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  check_map("street/Berlin_0_512", 20);
  check_map("street/Boston_0_256", 20);
}

}  // namespace
}  // namespace starnav
