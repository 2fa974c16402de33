// The paper experiments as library calls: Ou et al. 2022's ablation (optimal rows against a
// brute-force Dijkstra, the random draw's constraints, the summaries' sample) and Liu et al.
// 2024's terrain experiment (path invariants, determinism); every number either writes is a
// metric named in the catalogue.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <queue>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/experiment/ablation_experiment.hpp"
#include "starnav/experiment/metrics.hpp"
#include "starnav/experiment/terrain_experiment.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using json = nlohmann::ordered_json;

// 20 x 12 with a wall at column 9 open at the bottom row (MovingAI: row 0 at the top).
const char* kWallMap =
    "type octile\nheight 12\nwidth 20\nmap\n"
    "....................\n"
    ".........@..........\n"
    ".........@..........\n"
    ".........@..........\n"
    ".........@..........\n"
    ".........@..........\n"
    ".........@..........\n"
    ".........@....@@....\n"
    ".........@....@@....\n"
    ".........@..........\n"
    ".........@..........\n"
    "....................\n";

// Octile shortest path lengths from `s` by Dijkstra over 8 moves without corner cutting.
std::vector<double> dijkstra(const std::vector<std::string>& rows, Cell s) {
  const int h = static_cast<int>(rows.size()), w = static_cast<int>(rows[0].size());
  auto free = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h && rows[y][x] == '.'; };
  std::vector<double> d(static_cast<std::size_t>(w * h), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  d[s.y * w + s.x] = 0;
  open.push({0.0, s.y * w + s.x});
  while (!open.empty()) {
    const auto [du, u] = open.top();
    open.pop();
    if (du > d[u]) continue;
    const int ux = u % w, uy = u / w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((!dx && !dy) || !free(ux + dx, uy + dy)) continue;
        if (dx && dy && (!free(ux + dx, uy) || !free(ux, uy + dy))) continue;
        const double c = du + ((dx && dy) ? std::sqrt(2.0) : 1.0);
        const int v = (uy + dy) * w + ux + dx;
        if (c < d[v]) {
          d[v] = c;
          open.push({c, v});
        }
      }
  }
  return d;
}

// Every number in `j` (recursively, keys in `skip` aside) is a metric of `experiment`.
void expect_named(const json& j, const std::string& experiment, const std::set<std::string>& skip) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (skip.count(it.key())) continue;
      if (it.value().is_number()) EXPECT_NE(find_metric(experiment, it.key()), nullptr) << experiment << ": " << it.key();
      else expect_named(it.value(), experiment, skip);
    }
  } else if (j.is_array()) {
    for (const auto& e : j) expect_named(e, experiment, skip);
  }
}

TEST(AblationExperiment, OptimalRowsMatchABruteForceDijkstraAndTheSummariesUseTheCommonQueries) {
  const test::ScratchDir dir;
  test::write_text(dir.file("wall.map"), kWallMap);
  // (column, row from the top): across the wall, along it, and one into the block (unsolvable).
  test::write_text(dir.file("q.csv"), "start_x,start_y,goal_x,goal_y\n1,1,18,2\n2,10,3,0\n16,4,14,7\n");
  AblationConfig c;
  c.map = dir.file("wall.map");
  c.queries = dir.file("q.csv");
  c.repeat = 1;
  const AblationResult r = run_ablation_experiment(c);
  ASSERT_EQ(r.queries.size(), 3u);
  ASSERT_EQ(r.tables.size(), 2u);  // manhattan, octile; no inflation
  std::vector<std::string> rows;
  const std::string text = kWallMap;
  for (std::size_t at = text.find("map\n") + 4; at < text.size(); at += 21) rows.push_back(text.substr(at, 20));
  ASSERT_EQ(rows.size(), 12u);
  ASSERT_EQ(rows[1][9], '@');
  for (const AblationTable& t : r.tables) {
    ASSERT_EQ(t.variants.size(), 7u);
    for (std::size_t q = 0; q < 3; ++q) {
      const double optimum = dijkstra(rows, r.queries[q].start)[r.queries[q].goal.y * 20 + r.queries[q].goal.x];
      for (std::size_t v = 0; v < t.variants.size(); ++v) {
        const AblationRun& run = t.runs[v][q];
        EXPECT_EQ(run.found, std::isfinite(optimum)) << t.variants[v].name << " query " << q;
        if (!run.found) continue;
        // No grid path beats the optimum (a smoothed one is any-angle: at least the straight line);
        // JPS (octile, exact) and A* with the octile heuristic meet it.
        const AblationQuery& qq = r.queries[q];
        const double bound = t.variants[v].smooth ? std::hypot(qq.goal.x - qq.start.x, qq.goal.y - qq.start.y) : optimum;
        EXPECT_GE(run.metrics.length, bound - 1e-9) << t.variants[v].name;
        if (t.variants[v].jps || (t.heuristic == "octile" && v == 0)) {
          EXPECT_NEAR(run.cost, optimum, 1e-9) << t.variants[v].name;
        }
        EXPECT_LE(run.vertices_los, run.metrics.vertices);
      }
    }
    // The means are over the two solvable queries, and A* is its own baseline.
    for (const AblationSummary& s : t.summaries) {
      EXPECT_EQ(s.common, 2u);
      EXPECT_EQ(s.solved, 2u);
    }
    EXPECT_DOUBLE_EQ(t.summaries[0].enr, 0.0);
    const double mean_expanded = 0.5 * static_cast<double>(t.runs[0][0].expanded + t.runs[0][1].expanded);
    EXPECT_DOUBLE_EQ(t.summaries[0].expanded, mean_expanded);
  }
  const json j = json::parse(ablation_json(r));
  expect_named(j["tables"], "ablation", {"query"});
  EXPECT_EQ(ablation_queries_csv(r), test::read_text(dir.file("q.csv")));
  EXPECT_NE(ablation_full_markdown(r).find("### Per query: Octile heuristic, original map"), std::string::npos);
}

TEST(AblationExperiment, RandomQueriesKeepTheirDistanceAndAreSolvableAndSeeded) {
  const test::ScratchDir dir;
  test::write_text(dir.file("wall.map"), kWallMap);
  AblationConfig c;
  c.map = dir.file("wall.map");
  c.random = 5;
  c.seed = 4;
  c.min_dist = 6;
  c.max_dist = 9;
  c.repeat = 1;
  c.exact_variant = false;
  const AblationResult a = run_ablation_experiment(c);
  ASSERT_EQ(a.queries.size(), 5u);
  for (const AblationQuery& q : a.queries) {
    const double d = std::hypot(q.goal.x - q.start.x, q.goal.y - q.start.y);
    EXPECT_GE(d, 6.0);
    EXPECT_LE(d, 9.0);
  }
  for (const AblationTable& t : a.tables) {
    EXPECT_EQ(t.variants.size(), 6u);
    EXPECT_EQ(t.summaries[0].common, 5u);  // every drawn query is solvable
  }
  EXPECT_EQ(ablation_queries_csv(run_ablation_experiment(c)), ablation_queries_csv(a));
  c.min_dist = 50;
  c.max_dist = 60;  // farther than the map is wide
  try {
    run_ablation_experiment(c);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--random");
  }
}

TEST(TerrainExperiment, PathsKeepTheirInvariantsAndTheReportIsDeterministic) {
  TerrainExperimentConfig c;
  c.generate = 2;
  c.seed = 7;
  c.amplitude = 0.5;
  c.options.reopen = true;
  const TerrainExperimentResult a = run_terrain_experiment(c);
  ASSERT_EQ(a.terrains.size(), 2u);
  for (const TerrainOutcome& t : a.terrains) {
    EXPECT_EQ(t.start.x, 5);  // (0.5, 0.5) m on 0.1 m cells
    EXPECT_EQ(t.goal.x, 95);
    for (const TerrainRun& run : t.runs) {
      if (!run.found) continue;
      EXPECT_GE(run.metrics.lv_m, run.length_2d_m - 1e-9);  // 3D length >= horizontal length
      EXPECT_TRUE(run.samples.empty());                      // no figures asked for
    }
    // OA* is shortest (2D) over a superset of AOEA*'s free cells.
    if (t.runs[0].found && t.runs[1].found) {
      EXPECT_LE(t.runs[0].length_2d_m, t.runs[1].length_2d_m + 1e-9);
    }
  }
  const std::string ja = terrain_json(a);
  EXPECT_EQ(terrain_json(run_terrain_experiment(c)), ja);
  const json j = json::parse(ja);
  expect_named(j["per_terrain"], "terrain", {"seed"});
  expect_named(j["comparisons"], "terrain", {"n", "mean", "sd", "min", "max"});
  for (const auto& p : j["planners"]) EXPECT_NE(find_metric("terrain", "found"), nullptr) << p.dump();
  expect_named(json::parse(terrain_timing_json(a)), "terrain", {});
  EXPECT_NE(terrain_full_markdown(a, 1).find("(svg/hills_seed7_paths.svg)"), std::string::npos);
}

TEST(TerrainExperiment, RefusesAnOccupancyMapAndConflictingSources) {
  const test::ScratchDir dir;
  test::write_text(dir.file("wall.map"), kWallMap);
  TerrainExperimentConfig c;
  c.map = dir.file("wall.map");
  EXPECT_THROW(run_terrain_experiment(c), Error);
  c.generate = 2;
  EXPECT_THROW(run_terrain_experiment(c), Error);
}

}  // namespace
}  // namespace starnav
