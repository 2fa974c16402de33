// Terrain module: analysis of a 1000 x 1000 elevation map (0.1 m cells, 100 m x 100 m hills),
// incremental update, the IA* move-cost table, terrain generation (road directional / paper,
// hills), and the planners' time per expansion on the same map (IA* within 1.5x of
// plain A*'s time per expansion).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"
#include "starnav/terrain/terrain_analysis.hpp"
#include "starnav/terrain/terrain_generator.hpp"

namespace bench_terrain {

using namespace starnav;

// 100 m x 100 m of hills at 0.1 m: 1000 x 1000 cells (built once).
const ElevationMap& hills_1000() {
  static const ElevationMap map = [] {
    HillsOptions o;
    o.width_m = 100.0;
    o.height_m = 100.0;
    o.resolution = 0.1;
    o.seed = 1;
    o.amplitude = 0.5;  // gentler hills, so that IA* has long passable routes to search
    return generate_hills(o);
  }();
  return map;
}

std::shared_ptr<const TerrainAnalysis> analysis_1000() {
  static const auto a = std::make_shared<const TerrainAnalysis>(hills_1000());
  return a;
}

void per_cell(benchmark::State& state, double cells) {
  state.counters["cells"] = cells;
  state.counters["time_per_cell"] =
      benchmark::Counter(cells, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_TerrainAnalysis(benchmark::State& state) {
  const ElevationMap& m = hills_1000();
  TerrainAnalysis t;
  for (auto _ : state) {
    t.compute(m, {});
    benchmark::DoNotOptimize(t.ruggedness().data());
  }
  per_cell(state, static_cast<double>(m.cell_count()));
}
BENCHMARK(BM_TerrainAnalysis)->Unit(benchmark::kMillisecond);

// Incremental update after a 20 x 20 cell patch changed (a sensor update).
void BM_TerrainAnalysisUpdate(benchmark::State& state) {
  ElevationMap m = hills_1000();
  TerrainAnalysis t(m);
  int i = 0;
  for (auto _ : state) {
    const int x0 = 100 + (i * 37) % 700, y0 = 100 + (i * 53) % 700;
    ++i;
    for (int y = y0; y < y0 + 20; ++y)
      for (int x = x0; x < x0 + 20; ++x) m.set_height(x, y, m.height_at(x, y) + 0.001);
    t.update(m, {x0, y0, x0 + 20, y0 + 20});
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_TerrainAnalysisUpdate)->Unit(benchmark::kMicrosecond);

// The IA* move-cost table (8 costs per cell). Per cell this is also what computing the costs on
// the fly would add to every expansion.
template <class Store>
void BM_IaMoveCostTable(benchmark::State& state) {
  const auto t = analysis_1000();
  for (auto _ : state) {
    MoveCostTable<Store> table(*t, LiuCostParams{});
    benchmark::DoNotOptimize(table.costs().data());
  }
  per_cell(state, static_cast<double>(t->observed().size()));
}
BENCHMARK_TEMPLATE(BM_IaMoveCostTable, float)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_IaMoveCostTable, double)->Unit(benchmark::kMillisecond);

void per_expansion(benchmark::State& state, const PlanResult& r) {
  state.counters["expanded"] = static_cast<double>(r.expanded);
  state.counters["generated"] = static_cast<double>(r.generated);
  state.counters["found"] = r.found() ? 1 : 0;
  state.counters["time_per_expansion"] = benchmark::Counter(
      static_cast<double>(r.expanded), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Corner to corner on the 1000 x 1000 hills.
constexpr Cell kStart{5, 5};
constexpr Cell kGoal{994, 994};

void BM_RoughTerrainPlan(benchmark::State& state) {
  const auto kind = static_cast<RoughTerrainPlannerKind>(state.range(0));
  RoughTerrainPlannerOptions o;
  o.heuristic = state.range(1) ? LiuHeuristic::Paper : LiuHeuristic::Admissible;
  o.reopen = state.range(1) != 2;
  RoughTerrainPlanner p(kind, analysis_1000(), o);
  PlanResult r = p.plan(kStart, kGoal);  // warm-up (sizes the open list)
  for (auto _ : state) {
    r = p.plan(kStart, kGoal);
    benchmark::DoNotOptimize(r.cost);
  }
  state.SetLabel(std::string(rough_terrain_planner_name(kind)) + (kind == RoughTerrainPlannerKind::IA
                     ? (state.range(1) == 0 ? " admissible H" : state.range(1) == 1 ? " paper H, reopening" : " paper H, no reopening")
                     : ""));
  per_expansion(state, r);
}
BENCHMARK(BM_RoughTerrainPlan)
    ->Args({static_cast<int>(RoughTerrainPlannerKind::IA), 0})
    ->Args({static_cast<int>(RoughTerrainPlannerKind::IA), 1})
    ->Args({static_cast<int>(RoughTerrainPlannerKind::IA), 2})
    ->Args({static_cast<int>(RoughTerrainPlannerKind::AOEA), 0})
    ->Args({static_cast<int>(RoughTerrainPlannerKind::OA), 0})
    ->Unit(benchmark::kMillisecond);

// Plain grid search of the project on the same map's AOEA* mask, with many expansions: A* with
// the Euclidean heuristic (weaker than octile, so it expands a region like IA* does) and
// Dijkstra: the per-expansion baseline for IA*.
void BM_PlainGridSearchSameMap(benchmark::State& state) {
  const auto t = analysis_1000();
  OccupancyGrid grid(t->geometry(), kFreeOccupancy);
  for (int y = 0; y < t->height(); ++y)
    for (int x = 0; x < t->width(); ++x)
      if (t->expanded_obstacle_mask()[t->index(x, y)]) grid(x, y) = kOccupiedOccupancy;
  GridPlannerOptions go;
  if (state.range(0) == 0) go.heuristic = "euclidean";
  auto planner = make_grid_planner(state.range(0) == 0 ? "astar" : "dijkstra", grid, go);
  PlanResult r = planner->plan(kStart, kGoal);
  for (auto _ : state) {
    r = planner->plan(kStart, kGoal);
    benchmark::DoNotOptimize(r.cost);
  }
  state.SetLabel(state.range(0) == 0 ? "astar euclidean" : "dijkstra");
  per_expansion(state, r);
}
BENCHMARK(BM_PlainGridSearchSameMap)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_RoadGenerate(benchmark::State& state) {
  RoadOptions o;
  o.width_m = static_cast<double>(state.range(0)) * 0.1;
  o.height_m = o.width_m;
  o.resolution = 0.1;
  o.method = state.range(1) ? RoadMethod::Paper : RoadMethod::Directional;
  std::uint64_t seed = 0;
  for (auto _ : state) {
    o.seed = seed++;
    RoadTerrain t = generate_road(o);
    benchmark::DoNotOptimize(t.map.heights().data());
  }
  state.SetLabel(road_method_name(o.method));
  per_cell(state, static_cast<double>(state.range(0)) * static_cast<double>(state.range(0)));
}
BENCHMARK(BM_RoadGenerate)->Args({1000, 0})->Args({1000, 1})->Unit(benchmark::kMillisecond);

void BM_HillsGenerate(benchmark::State& state) {
  HillsOptions o;
  o.width_m = 100.0;
  o.height_m = 100.0;
  o.resolution = 0.1;
  std::uint64_t seed = 0;
  for (auto _ : state) {
    o.seed = seed++;
    ElevationMap m = generate_hills(o);
    benchmark::DoNotOptimize(m.heights().data());
  }
  per_cell(state, 1e6);
}
BENCHMARK(BM_HillsGenerate)->Unit(benchmark::kMillisecond);

}  // namespace bench_terrain
