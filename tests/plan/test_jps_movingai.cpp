// JPS and JPS+ on a sample of every MovingAI map under ../shared/benchmarks/movingai: a few
// problems spread over each scenario file (short and long paths) and its unsolvable length-0
// lines, exact by the issue-3 rule, with the returned cell path checked move by move.
// Every instance runs in `make bench` (scripts/bench-movingai.sh).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "starnav/io/movingai.hpp"
#include "starnav/plan/jps.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;


// Sum of the moves of a path, or -1 when a move is not legal on the map (not adjacent, into an
// obstacle, or a diagonal cutting a corner).
double walk_cost(const MovingAiMap& m, const std::vector<Cell>& path) {
  auto free = [&](int x, int y) { return x >= 0 && y >= 0 && x < m.width && y < m.height && MovingAiMap::passable(m.at(x, y)); };
  double sum = 0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    if (!free(path[k].x, path[k].y)) return -1;
    if (k == 0) continue;
    const int dx = path[k].x - path[k - 1].x, dy = path[k].y - path[k - 1].y;
    if (std::abs(dx) > 1 || std::abs(dy) > 1 || (!dx && !dy)) return -1;
    if (dx && dy) {
      if (!free(path[k - 1].x + dx, path[k - 1].y) || !free(path[k - 1].x, path[k - 1].y + dy)) return -1;
      sum += std::numbers::sqrt2;
    } else {
      sum += 1;
    }
  }
  return sum;
}

TEST(JpsMovingAi, SampleOfEveryMapIsExact) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  const std::string root = test::shared_path("benchmarks/movingai");
  std::vector<fs::path> maps;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file() && e.path().extension() == ".map" && fs::exists(e.path().string() + ".scen"))
      maps.push_back(e.path());
  std::sort(maps.begin(), maps.end());
  ASSERT_GE(maps.size(), 40u);
  std::size_t checked = 0, unsolvable = 0;
  for (const fs::path& path : maps) {
    const MovingAiMap mai = read_movingai_map(path.string());
    const MovingAiScenario scen = read_movingai_scenario(path.string() + ".scen");
    ASSERT_FALSE(scen.entries.empty()) << path;
    const OccupancyGrid grid = mai.to_occupancy();
    auto jps = make_jps_planner(grid, {}, false);
    auto plus = make_jps_planner(grid, {}, true);
    // Five problems spread over the file (the last one is among the longest), and up to three
    // unsolvable ones.
    std::vector<std::size_t> sample;
    const std::size_t n = scen.entries.size();
    for (std::size_t k = 0; k < 5; ++k) sample.push_back(std::min(n - 1, k * (n - 1) / 4));
    std::size_t zero = 0;
    for (std::size_t i = 0; i < n && zero < 3; ++i)
      if (scen.entries[i].unsolvable()) {
        sample.push_back(i);
        ++zero;
      }
    for (const std::size_t i : sample) {
      const ScenarioEntry& e = scen.entries[i];
      const Cell s{e.start_x, e.start_y}, g{e.goal_x, e.goal_y};
      for (GridPlanner* p : {jps.get(), plus.get()}) {
        SCOPED_TRACE(path.filename().string() + " problem " + std::to_string(i + 1) + " " + std::string(p->name()));
        const PlanResult r = p->plan(s, g);
        if (e.unsolvable()) {
          EXPECT_EQ(r.status, PlanStatus::NoPath);
          ++unsolvable;
          continue;
        }
        ASSERT_EQ(r.status, PlanStatus::Found);
        EXPECT_LE(std::abs(r.cost - e.optimal_length), std::max(0.01, 1e-5 * e.optimal_length))
            << r.cost << " vs " << e.optimal_length;
        ASSERT_EQ(r.path_cells.front(), s);
        ASSERT_EQ(r.path_cells.back(), g);
        EXPECT_NEAR(walk_cost(mai, r.path_cells), r.cost, 1e-9 * std::max(1.0, r.cost));
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 2u * 5u * 40u);
  EXPECT_GT(unsolvable, 0u);  // brc201d has unsolvable lines
}

// JPS and JPS+ search the same jump points, so their node counts agree exactly.
TEST(JpsMovingAi, JpsAndJpsPlusExpandTheSameJumpPoints) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai");
  for (const char* name : {"bg512/AR0011SR", "street/Berlin_0_256", "maze/maze512-2-0"}) {
    const std::string map_path = test::shared_path(std::string("benchmarks/movingai/") + name + ".map");
    if (map_path.empty()) continue;
    const MovingAiScenario scen = read_movingai_scenario(map_path + ".scen");
    const OccupancyGrid grid = read_movingai_map(map_path).to_occupancy();
    auto jps = make_jps_planner(grid, {}, false);
    auto plus = make_jps_planner(grid, {}, true);
    EXPECT_GT(plus->preprocess_ms(), 0.0);
    for (std::size_t i = 0; i < scen.entries.size(); i += std::max<std::size_t>(1, scen.entries.size() / 25)) {
      const ScenarioEntry& e = scen.entries[i];
      const PlanResult a = jps->plan({e.start_x, e.start_y}, {e.goal_x, e.goal_y});
      const PlanResult b = plus->plan({e.start_x, e.start_y}, {e.goal_x, e.goal_y});
      SCOPED_TRACE(std::string(name) + " problem " + std::to_string(i + 1));
      EXPECT_EQ(a.expanded, b.expanded);
      EXPECT_EQ(a.generated, b.generated);
      EXPECT_EQ(a.path_cells, b.path_cells);
    }
  }
}

}  // namespace
}  // namespace starnav
