// Ou et al. 2022 (docs/papers/ou2022.md) speed checks.
//
// Ou2022/<variant>/<map>: the planner variants on MovingAI maps (hard inflation R in cells as
// listed in kMaps, so that every variant runs on the same inflated map), over a fixed sample of
// each map's scenario queries that are solvable there. Counters: ns_per_expansion = thread CPU
// time per expanded state (the bar: the full method within 1.3x of plain A* on the same
// map and heuristic), mean_us per query, expanded per query.
//   AStar_<h>      plain A*, heuristic h (manhattan as the paper, octile)
//   TurnW_<h>      + the paper's steering cost (cell states)
//   TurnWW_<h>     + the adaptive weight
//   Full_<h>       the full method: inflation + LOS smoothing + turn_w + W (time includes the
//                  smoothing; the inflation is per map)
//   TurnExact_octile  the exact (cell, direction) steering variant
// Ou2022Inflation/n: inflate_obstacles (distance transform, hard radius, graded band) on n x n
// random maps, n = 500 .. 4000; time_per_cell stays flat when it is linear (scripts/bench-ablation.sh
// fits time = c * cells^k).
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Ou2022
#include <benchmark/benchmark.h>

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/ou2022.hpp"

namespace bench_ou2022 {

using starnav::bench::median;
using starnav::bench::thread_cpu_s;

using namespace starnav;

constexpr std::size_t kSample = 96;

struct MapSpec {
  const char* name;
  double inflate;  // cells
};
// Room maps have doors one cell wide: any inflation would close them.
const MapSpec kMaps[] = {{"bg512/AR0011SR", 1.0}, {"dao/den520d", 1.0}, {"room/32room_000", 0.0}, {"room/8room_000", 0.0}};

struct BenchMap {
  std::string name;
  OccupancyGrid grid;
  std::vector<std::pair<Cell, Cell>> queries;
  bool ok = false;
};

const BenchMap& bench_map(const MapSpec& spec) {
  static std::vector<std::unique_ptr<BenchMap>> cache;
  for (const auto& m : cache)
    if (m->name == spec.name) return *m;
  auto m = std::make_unique<BenchMap>();
  m->name = spec.name;
  const std::filesystem::path root = std::filesystem::path(STARNAV_SHARED_DIR) / "benchmarks/movingai";
  const auto map_path = root / (std::string(spec.name) + ".map"), scen_path = root / (std::string(spec.name) + ".map.scen");
  if (std::filesystem::exists(map_path) && std::filesystem::exists(scen_path)) {
    m->grid = read_movingai_map(map_path.string()).to_occupancy();
    const MovingAiScenario scen = read_movingai_scenario(scen_path.string());
    // Queries that plain A* solves on the inflated map, spread over the whole file.
    GridPlannerOptions o;
    o.ou2022.inflation.radius_m = spec.inflate;
    ImprovedAStarPlanner check(m->grid, o, false);
    const std::size_t step = std::max<std::size_t>(1, scen.entries.size() / (2 * kSample));
    for (std::size_t i = 0; i < scen.entries.size() && m->queries.size() < kSample; i += step) {
      const auto& e = scen.entries[i];
      const Cell s{e.start_x, e.start_y}, g{e.goal_x, e.goal_y};
      if (!(s == g) && check.plan(s, g).found()) m->queries.push_back({s, g});
    }
    m->ok = !m->queries.empty();
  }
  cache.push_back(std::move(m));
  return *cache.back();
}

struct VariantSpec {
  const char* name;
  const char* heuristic;
  double turn_cost;
  bool adaptive;
  bool smooth;
  bool exact;
};
const VariantSpec kVariants[] = {
    {"AStar_manhattan", "manhattan", 0, false, false, false}, {"TurnW_manhattan", "manhattan", 1, false, false, false},
    {"TurnWW_manhattan", "manhattan", 1, true, false, false}, {"Full_manhattan", "manhattan", 1, true, true, false},
    {"AStar_octile", "octile", 0, false, false, false},       {"Full_octile", "octile", 1, true, true, false},
    {"TurnExact_octile", "octile", 1, false, false, true},
};

void BM_Variant(benchmark::State& state, const MapSpec& spec, const VariantSpec& v) {
  const BenchMap& bm = bench_map(spec);
  if (!bm.ok) {
    state.SkipWithError((std::string("benchmarks/movingai/") + spec.name + " not found").c_str());
    return;
  }
  GridPlannerOptions o;
  o.heuristic = v.heuristic;
  o.ou2022.inflation.radius_m = spec.inflate;
  o.ou2022.turn_cost = v.turn_cost;
  o.ou2022.adaptive_weight = v.adaptive;
  o.ou2022.turn_exact = v.exact;
  o.ou2022.smoothing = v.smooth ? PathSmoothing::LineOfSight : PathSmoothing::None;
  ImprovedAStarPlanner planner(bm.grid, o, false);
  for (const auto& [s, g] : bm.queries) benchmark::DoNotOptimize(planner.plan(s, g));  // warm-up
  std::uint64_t expanded = 0;
  double cpu = 0.0;
  for (auto _ : state) {
    for (const auto& [s, g] : bm.queries) {
      const double t0 = thread_cpu_s();
      const PlanResult r = planner.plan(s, g);
      cpu += thread_cpu_s() - t0;
      expanded += r.expanded;
      benchmark::DoNotOptimize(r.cost);
    }
  }
  const double queries = static_cast<double>(state.iterations()) * static_cast<double>(bm.queries.size());
  state.counters["ns_per_expansion"] = expanded ? cpu * 1e9 / static_cast<double>(expanded) : 0.0;
  state.counters["mean_us"] = cpu * 1e6 / queries;
  state.counters["expanded"] = static_cast<double>(expanded) / queries;
  state.counters["queries"] = static_cast<double>(bm.queries.size());
}

// range(1) = 0: inflate_obstacles, a fresh result every call; 1: one ObstacleInflator and one
// result reused across calls (no allocation after the first).
void BM_Inflation(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool reuse = state.range(1) != 0;
  GridGeometry g;
  g.width = n;
  g.height = n;
  g.resolution = 0.05;
  OccupancyGrid grid(g);
  Rng rng(7);
  for (auto& v : grid.data()) v = rng.bernoulli(0.05) ? kOccupiedOccupancy : kFreeOccupancy;
  InflationOptions o;
  o.radius_m = 0.2;
  o.cost_radius_m = 0.6;
  ObstacleInflator inflator;
  InflatedMap reused;
  // Warm-up outside the timing: at 4000^2 a call takes about a second, so the benchmark may time
  // a single iteration, which would otherwise be the one that allocates.
  if (reuse) inflator.inflate(grid, {}, false, o, reused);
  for (auto _ : state) {
    if (reuse) {
      inflator.inflate(grid, {}, false, o, reused);
      benchmark::DoNotOptimize(reused.blocked.data());
    } else {
      const InflatedMap inf = inflate_obstacles(grid, {}, false, o);
      benchmark::DoNotOptimize(inf.blocked.data());
    }
  }
  const double cells = static_cast<double>(n) * n;
  state.counters["cells"] = cells;
  state.counters["time_per_cell"] =
      benchmark::Counter(cells, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void register_all() {
  for (const MapSpec& m : kMaps)
    for (const VariantSpec& v : kVariants)
      benchmark::RegisterBenchmark((std::string("Ou2022/") + v.name + "/" + m.name).c_str(), BM_Variant, m, v)
          ->Unit(benchmark::kMillisecond)
          ->MinTime(0.3);
  benchmark::RegisterBenchmark("Ou2022Inflation", BM_Inflation)
      ->ArgNames({"n", "reuse"})
      ->ArgsProduct({{500, 1000, 2000, 4000}, {0, 1}})
      ->Unit(benchmark::kMillisecond);
}

const bool kRegistered = (register_all(), true);

}  // namespace bench_ou2022
