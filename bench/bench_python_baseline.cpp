// The C++ side of bench/python_overhead.py (docs/python.md, "Speed"): the calls the Python package
// makes, made from C++ on the same map and queries, so that the script can quote the bindings' cost
// as a ratio. PythonBaseline/PlanQuery: one `starnav plan` query (plan_query_on_grid: the planner
// built, the search, the path metrics), per query, the median over a sample of the map's scenario
// (every k-th solvable line); PythonBaseline/PlanMany: one planner built, then the first 1,000
// sampled queries in a loop (what plan_many does on one thread), per batch. Times are the thread's
// CPU time, as the Python script measures its own. The map: ../shared's bg512/AR0011SR (512 x 512).
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=PythonBaseline
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "starnav/experiment/plan_query.hpp"
#include "starnav/io/movingai.hpp"

namespace bench_python_baseline {

using namespace starnav;
using starnav::bench::median;
using starnav::bench::thread_cpu_s;

constexpr const char* kMap = "bg512/AR0011SR";

struct Instance {
  OccupancyGrid grid;
  std::vector<PlanEndpoints> queries;  // every k-th solvable line, at most 1,000
  bool ok = false;
};

// The same selection as python_overhead.py: every k-th solvable line, k = max(1, solvable / 1000).
const Instance& instance() {
  static const Instance in = [] {
    Instance i;
    const std::filesystem::path root = std::filesystem::path(STARNAV_SHARED_DIR) / "benchmarks/movingai";
    const auto map_path = root / (std::string(kMap) + ".map"), scen_path = root / (std::string(kMap) + ".map.scen");
    if (!std::filesystem::exists(map_path) || !std::filesystem::exists(scen_path)) return i;
    i.grid = read_movingai_map(map_path.string()).to_occupancy();
    std::vector<ScenarioEntry> solvable;
    for (const ScenarioEntry& e : read_movingai_scenario(scen_path.string()).entries)
      if (!e.unsolvable()) solvable.push_back(e);
    const std::size_t step = std::max<std::size_t>(1, solvable.size() / 1000);
    for (std::size_t k = 0; k < solvable.size() && i.queries.size() < 1000; k += step)
      i.queries.push_back({{solvable[k].start_x, solvable[k].start_y}, {solvable[k].goal_x, solvable[k].goal_y}});
    i.ok = true;
    return i;
  }();
  return in;
}

void PythonBaseline_PlanQuery(benchmark::State& state) {
  const Instance& in = instance();
  if (!in.ok) {
    state.SkipWithError((std::string("benchmarks/movingai/") + kMap + " not found").c_str());
    return;
  }
  // A sample of 64 queries across all lengths (every 16th of the 1,000).
  std::vector<PlanEndpoints> sample;
  for (std::size_t k = 0; k < in.queries.size(); k += 16) sample.push_back(in.queries[k]);
  const PlanRequest rq = occupancy_plan_request("astar", {}, in.grid.geometry(), true, OccupancyThresholds{}, kMap);
  std::vector<std::vector<double>> times(sample.size());
  for (auto _ : state)
    for (std::size_t q = 0; q < sample.size(); ++q) {
      const double t0 = thread_cpu_s();
      const PlanOutcome out = plan_query_on_grid(in.grid, sample[q].start, sample[q].goal, rq, {});
      times[q].push_back((thread_cpu_s() - t0) * 1e6);
      benchmark::DoNotOptimize(out.result.cost);
    }
  std::vector<double> per_query;
  for (auto& t : times) per_query.push_back(median(t));
  state.counters["median_us"] = median(per_query);
  state.counters["queries"] = static_cast<double>(sample.size());
}
BENCHMARK(PythonBaseline_PlanQuery)->Unit(benchmark::kMillisecond)->Iterations(5);

void PythonBaseline_PlanMany(benchmark::State& state) {
  const Instance& in = instance();
  if (!in.ok) {
    state.SkipWithError((std::string("benchmarks/movingai/") + kMap + " not found").c_str());
    return;
  }
  const PlanRequest rq = occupancy_plan_request("astar", {}, in.grid.geometry(), true, OccupancyThresholds{}, kMap);
  std::vector<double> batches;
  for (auto _ : state) {
    const double t0 = thread_cpu_s();
    const std::unique_ptr<GridPlanner> planner = make_grid_planner(rq.planner, in.grid, grid_planner_options(rq));
    double cost = 0.0;
    for (const PlanEndpoints& q : in.queries) cost += planner->plan(q.start, q.goal, rq.limits).cost;
    batches.push_back((thread_cpu_s() - t0) * 1e3);
    benchmark::DoNotOptimize(cost);
  }
  state.counters["median_batch_ms"] = median(batches);
  state.counters["queries"] = static_cast<double>(in.queries.size());
}
BENCHMARK(PythonBaseline_PlanMany)->Unit(benchmark::kMillisecond)->Iterations(7);

}  // namespace bench_python_baseline
