// JPS and JPS+ on the MovingAI maps of docs/benchmarks.md's speed table, through the GridPlanner interface
// (what `starnav bench movingai` times). Each iteration runs a fixed sample of the map's
// scenario problems (every k-th solvable line, so all path lengths are represented).
// Counters: median_us = median time per query (median over problems of each problem's median
// over iterations, from PlanResult::time_ms), mean_us, Mexp_per_s = jump points expanded per
// second; JpsPlusTables times the per-map preprocessing; BitGridScan one long straight scan.
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Jps
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/plan/bit_grid.hpp"
#include "starnav/plan/jps.hpp"

namespace bench_jps {

using starnav::bench::median;
using starnav::bench::thread_cpu_s;

using namespace starnav;

constexpr std::size_t kSample = 128;

const char* const kMaps[] = {"random/random512-25-0", "bg512/AR0011SR",   "dao/den520d", "room/32room_000",
                             "street/Berlin_0_512",   "maze/maze512-4-0", "sc1/Aurora"};

struct JpsBenchMap {
  std::string name;
  std::unique_ptr<OccupancyGrid> grid;
  std::vector<std::pair<Cell, Cell>> queries;
};

const JpsBenchMap& load(const std::string& relative) {
  static std::vector<std::unique_ptr<JpsBenchMap>> cache;
  for (const auto& m : cache)
    if (m->name == relative) return *m;
  auto m = std::make_unique<JpsBenchMap>();
  m->name = relative;
  const std::filesystem::path root = std::filesystem::path(STARNAV_SHARED_DIR) / "benchmarks/movingai";
  const auto map_path = root / (relative + ".map");
  const auto scen_path = root / (relative + ".map.scen");
  if (std::filesystem::exists(map_path) && std::filesystem::exists(scen_path)) {
    m->grid = std::make_unique<OccupancyGrid>(read_movingai_map(map_path.string()).to_occupancy());
    std::vector<ScenarioEntry> solvable;
    for (const auto& e : read_movingai_scenario(scen_path.string()).entries)
      if (!e.unsolvable()) solvable.push_back(e);
    const std::size_t step = std::max<std::size_t>(1, solvable.size() / kSample);
    for (std::size_t i = 0; i < solvable.size() && m->queries.size() < kSample; i += step)
      m->queries.push_back({{solvable[i].start_x, solvable[i].start_y}, {solvable[i].goal_x, solvable[i].goal_y}});
  }
  cache.push_back(std::move(m));
  return *cache.back();
}

void BM_JpsQueries(benchmark::State& state, const std::string& map, bool plus) {
  const JpsBenchMap& bm = load(map);
  if (!bm.grid) {
    state.SkipWithError(("benchmarks/movingai/" + map + " not found").c_str());
    return;
  }
  auto planner = make_jps_planner(*bm.grid, {}, plus);
  for (const auto& [s, g] : bm.queries) (void)planner->plan(s, g);  // warm-up
  std::vector<std::vector<double>> times(bm.queries.size());
  std::uint64_t expanded = 0;
  double total_ms = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < bm.queries.size(); ++i) {
      const PlanResult r = planner->plan(bm.queries[i].first, bm.queries[i].second);
      if (!r.found()) {
        state.SkipWithError("a benchmark problem was not solved");
        return;
      }
      times[i].push_back(r.time_ms * 1000.0);
      total_ms += r.time_ms;
      expanded += r.expanded;
      benchmark::DoNotOptimize(r.cost);
    }
  }
  std::vector<double> per_query;
  for (const auto& t : times) per_query.push_back(median(t));
  const double queries = static_cast<double>(bm.queries.size()) * static_cast<double>(state.iterations());
  state.counters["queries"] = static_cast<double>(bm.queries.size());
  state.counters["median_us"] = median(per_query);
  state.counters["mean_us"] = queries > 0 ? total_ms * 1000.0 / queries : 0.0;
  state.counters["Mexp_per_s"] = total_ms > 0 ? static_cast<double>(expanded) / (total_ms * 1e3) : 0.0;
  state.counters["preprocess_ms"] = planner->preprocess_ms();
}

void BM_JpsPlusTables(benchmark::State& state, const std::string& map) {
  const JpsBenchMap& bm = load(map);
  if (!bm.grid) {
    state.SkipWithError(("benchmarks/movingai/" + map + " not found").c_str());
    return;
  }
  for (auto _ : state) {
    auto planner = make_jps_planner(*bm.grid, {}, true);
    benchmark::DoNotOptimize(planner.get());
  }
  state.counters["cells"] = static_cast<double>(bm.grid->cell_count());
}

// One straight scan along a free row of n cells (the block-based inner loop).
void BM_BitGridScan(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::vector<std::uint8_t> blocked(static_cast<std::size_t>(n) * 3, 0);
  const BitGrid grid(blocked, n, 3, false);
  const std::uint32_t from = grid.index(0, 1);
  for (auto _ : state) benchmark::DoNotOptimize(grid.scan_forward(from, 0));
  state.counters["Gcells_per_s"] =
      benchmark::Counter(static_cast<double>(n) * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}

const int kRegistered = [] {
  for (const char* m : kMaps) {
    benchmark::RegisterBenchmark((std::string("JpsQueries/jps/") + m).c_str(), BM_JpsQueries, std::string(m), false)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark((std::string("JpsQueries/jpsplus/") + m).c_str(), BM_JpsQueries, std::string(m), true)
        ->Unit(benchmark::kMillisecond);
  }
  for (const char* m : kMaps)
    benchmark::RegisterBenchmark((std::string("JpsPlusTables/") + m).c_str(), BM_JpsPlusTables, std::string(m))
        ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("JpsBitGridScan", BM_BitGridScan)->Arg(64)->Arg(512)->Arg(4096);
  return 0;
}();

}  // namespace bench_jps
