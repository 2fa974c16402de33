// The search core on the MovingAI maps of docs/benchmarks.md's table: open-list variants (4-ary / binary
// heap, decrease-key / lazy deletion), fixed-point vs double costs, A* and Dijkstra.
// Each iteration runs a fixed sample of the map's scenario instances (every k-th line, so all
// path lengths are represented). Counters: median_us = median time per query (median over
// instances of each instance's median over iterations), mean_us, Mexp_per_s = expansions per
// second over all queries. Times are the thread's CPU time (CLOCK_THREAD_CPUTIME_ID), which a busy
// machine disturbs less than wall time; wall_mean_us is the wall-clock mean for comparison.
// Also DStarLiteVsAStar (below): repairs after local changes against A* from scratch.
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter="SearchCore|DStarLite"
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/plan/dstar_lite.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/search_core.hpp"

namespace bench_search_core {

using starnav::bench::median;
using starnav::bench::thread_cpu_s;

using namespace starnav;

constexpr std::size_t kSampleSize = 128;

struct BenchMap {
  std::string name;
  GridSearchMap map;
  std::vector<std::pair<Cell, Cell>> queries;
  bool ok = false;
};

const BenchMap& bench_map(const std::string& relative) {
  static std::vector<std::unique_ptr<BenchMap>> cache;
  for (const auto& m : cache)
    if (m->name == relative) return *m;
  auto m = std::make_unique<BenchMap>();
  m->name = relative;
  const std::filesystem::path root = std::filesystem::path(STARNAV_SHARED_DIR) / "benchmarks/movingai";
  const auto map_path = root / (relative + ".map"), scen_path = root / (relative + ".map.scen");
  if (std::filesystem::exists(map_path) && std::filesystem::exists(scen_path)) {
    const OccupancyGrid grid = read_movingai_map(map_path.string()).to_occupancy();
    m->map = GridSearchMap(grid, OccupancyThresholds{}, false);
    const MovingAiScenario scen = read_movingai_scenario(scen_path.string());
    std::vector<ScenarioEntry> solvable;
    for (const auto& e : scen.entries)
      if (!e.unsolvable()) solvable.push_back(e);
    const std::size_t step = std::max<std::size_t>(1, solvable.size() / kSampleSize);
    for (std::size_t i = 0; i < solvable.size() && m->queries.size() < kSampleSize; i += step)
      m->queries.push_back({{solvable[i].start_x, solvable[i].start_y}, {solvable[i].goal_x, solvable[i].goal_y}});
    m->ok = true;
  }
  cache.push_back(std::move(m));
  return *cache.back();
}

template <class Cost, class OpenList, class CostModel, class Heuristic>
void run_bench(benchmark::State& state, const std::string& map_name, Heuristic make_h(const GridSearchMap&)) {
  const BenchMap& bm = bench_map(map_name);
  if (!bm.ok) {
    state.SkipWithError(("benchmarks/movingai/" + map_name + " not found").c_str());
    return;
  }
  BestFirstSearch<Cost, OpenList> search(bm.map.state_count());
  GridGraph<8, CostModel> graph(bm.map);
  Heuristic h = make_h(bm.map);
  std::vector<std::vector<double>> times(bm.queries.size());
  std::uint64_t expanded = 0;
  double total_s = 0.0, wall_s = 0.0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < bm.queries.size(); ++i) {
      const auto& [s, g] = bm.queries[i];
      const auto w0 = std::chrono::steady_clock::now();
      const double t0 = thread_cpu_s();
      h.set_goal(bm.map.state(g));
      const SearchOutcome o = search.run(graph, h, bm.map.state(s), SingleGoal{bm.map.state(g)});
      const double dt = thread_cpu_s() - t0;
      wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
      benchmark::DoNotOptimize(o);
      times[i].push_back(dt * 1e6);
      total_s += dt;
      expanded += search.stats().expanded;
    }
  }
  std::vector<double> per_instance;
  for (auto& t : times) per_instance.push_back(median(t));
  state.counters["median_us"] = median(per_instance);
  state.counters["mean_us"] = total_s * 1e6 / (static_cast<double>(state.iterations()) * bm.queries.size());
  state.counters["wall_mean_us"] = wall_s * 1e6 / (static_cast<double>(state.iterations()) * bm.queries.size());
  state.counters["Mexp_per_s"] = static_cast<double>(expanded) / total_s * 1e-6;
  state.counters["queries"] = static_cast<double>(bm.queries.size());
}

OctileHeuristic<std::int64_t> octile_fixed(const GridSearchMap& m) {
  return {m, UniformGridCost::kCardinal, UniformGridCost::kDiagonal};
}
OctileHeuristic<double> octile_double(const GridSearchMap& m) { return {m, 1.0, kSqrt2}; }
ZeroHeuristic<std::int64_t> zero_fixed(const GridSearchMap&) { return {}; }

using I64 = std::int64_t;

const char* const kMaps[] = {"random/random512-25-0", "bg512/AR0011SR", "dao/den520d", "room/32room_000",
                             "street/Berlin_0_512",   "maze/maze512-4-0", "sc1/Aurora"};

void register_all() {
  for (const char* map : kMaps) {
    const std::string m = map;
    auto reg = [&](const std::string& name, void (*fn)(benchmark::State&, const std::string&)) {
      benchmark::RegisterBenchmark(("SearchCore/" + name + "/" + m).c_str(), fn, m)->Unit(benchmark::kMillisecond)->MinTime(0.5);
    };
    reg("AStar_4aryDecreaseKey", [](benchmark::State& s, const std::string& mm) {
      run_bench<I64, DecreaseKeyOpenList<I64, 4>, UniformGridCost>(s, mm, octile_fixed);
    });
    reg("AStar_BinaryDecreaseKey", [](benchmark::State& s, const std::string& mm) {
      run_bench<I64, DecreaseKeyOpenList<I64, 2>, UniformGridCost>(s, mm, octile_fixed);
    });
    reg("AStar_4aryLazy", [](benchmark::State& s, const std::string& mm) {
      run_bench<I64, LazyOpenList<I64, 4>, UniformGridCost>(s, mm, octile_fixed);
    });
    reg("AStar_BinaryLazy", [](benchmark::State& s, const std::string& mm) {
      run_bench<I64, LazyOpenList<I64, 2>, UniformGridCost>(s, mm, octile_fixed);
    });
    reg("AStar_4aryDecreaseKey_DoubleCost", [](benchmark::State& s, const std::string& mm) {
      run_bench<double, DecreaseKeyOpenList<double, 4>, UniformGridCostDouble>(s, mm, octile_double);
    });
    reg("Dijkstra_4aryDecreaseKey", [](benchmark::State& s, const std::string& mm) {
      run_bench<I64, DecreaseKeyOpenList<I64, 4>, UniformGridCost>(s, mm, zero_fixed);
    });
    reg("Dijkstra_4aryLazy", [](benchmark::State& s, const std::string& mm) {
      run_bench<I64, LazyOpenList<I64, 4>, UniformGridCost>(s, mm, zero_fixed);
    });
  }
}

const int kRegistered = (register_all(), 0);

}  // namespace bench_search_core

// ---- D* Lite against A* from scratch ---------------------------------------------------------------
// A robot walks a long route of a MovingAI map; at each of 100 steps one random free cell within
// 3 cells of the path point 6 steps ahead becomes blocked (a local change; a change that would cut
// the goal off is undone). D* Lite repairs its search; A* plans from scratch from the robot's
// cell. Counters: mean expansions and mean CPU microseconds per replan of each (the initial D*
// Lite search separately).
namespace bench_search_core {

void BM_DStarLiteVsAStar(benchmark::State& state, const std::string& map_name) {
  const std::filesystem::path root = std::filesystem::path(STARNAV_SHARED_DIR) / "benchmarks/movingai";
  const auto map_path = root / (map_name + ".map"), scen_path = root / (map_name + ".map.scen");
  if (!std::filesystem::exists(map_path) || !std::filesystem::exists(scen_path)) {
    state.SkipWithError(("benchmarks/movingai/" + map_name + " not found").c_str());
    return;
  }
  const OccupancyGrid base = read_movingai_map(map_path.string()).to_occupancy();
  const MovingAiScenario scen = read_movingai_scenario(scen_path.string());
  const ScenarioEntry* route = &scen.entries.back();
  for (const auto& e : scen.entries)
    if (e.optimal_length > 200.0) {  // the first long route
      route = &e;
      break;
    }
  double dstar_expanded = 0, astar_expanded = 0, dstar_s = 0, astar_s = 0, replans = 0, initial_s = 0;
  for (auto _ : state) {
    Rng rng(7);
    OccupancyGrid grid = base;
    DStarLite dstar(grid);
    Cell start{route->start_x, route->start_y};
    const Cell goal{route->goal_x, route->goal_y};
    double t0 = thread_cpu_s();
    PlanResult r = dstar.plan(start, goal);
    initial_s += thread_cpu_s() - t0;
    for (int step = 0; step < 100 && r.found() && r.path_cells.size() > 8; ++step) {
      start = r.path_cells[1];
      dstar.move_start(start);
      const Cell ahead = r.path_cells[6];
      Cell c{ahead.x + static_cast<int>(rng.uniform_int(-3, 3)), ahead.y + static_cast<int>(rng.uniform_int(-3, 3))};
      const bool change = grid.contains(c.x, c.y) && grid(c.x, c.y) == kFreeOccupancy && !(c == start) && !(c == goal);
      if (change) {
        grid(c.x, c.y) = kOccupiedOccupancy;
        const CellChange blocked{c, kOccupiedOccupancy};
        dstar.update_cells({&blocked, 1});
      }
      auto astar = make_grid_planner("astar", grid);  // the changed map (construction not timed)
      t0 = thread_cpu_s();
      PlanResult fresh = astar->plan(start, goal);
      const double astar_dt = thread_cpu_s() - t0;
      if (!fresh.found() && change) {  // cut the goal off: undo
        grid(c.x, c.y) = kFreeOccupancy;
        const CellChange freed{c, kFreeOccupancy};
        dstar.update_cells({&freed, 1});
        astar = make_grid_planner("astar", grid);
        t0 = thread_cpu_s();
        fresh = astar->plan(start, goal);
        astar_s += thread_cpu_s() - t0;
      } else {
        astar_s += astar_dt;
      }
      t0 = thread_cpu_s();
      r = dstar.replan();
      dstar_s += thread_cpu_s() - t0;
      dstar_expanded += static_cast<double>(r.expanded);
      astar_expanded += static_cast<double>(fresh.expanded);
      if (fresh.found() != r.found() || (fresh.found() && std::abs(fresh.cost - r.cost) > 1e-6 * fresh.cost))
        state.SkipWithError("D* Lite and A* disagree");
      replans += 1;
    }
  }
  state.counters["replans"] = replans / static_cast<double>(state.iterations());
  state.counters["dstar_initial_us"] = initial_s * 1e6 / static_cast<double>(state.iterations());
  state.counters["dstar_expanded_per_replan"] = dstar_expanded / replans;
  state.counters["astar_expanded_per_plan"] = astar_expanded / replans;
  state.counters["dstar_us_per_replan"] = dstar_s * 1e6 / replans;
  state.counters["astar_us_per_plan"] = astar_s * 1e6 / replans;
}

const int kRegisteredDStar = [] {
  for (const char* map : {"dao/den520d", "random/random512-25-0", "room/32room_000"}) {
    const std::string m = map;
    benchmark::RegisterBenchmark(("DStarLiteVsAStar/" + m).c_str(), BM_DStarLiteVsAStar, m)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
  }
  return 0;
}();

}  // namespace bench_search_core
