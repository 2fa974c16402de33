// Hybrid-A* (plan/hybrid_astar): typical queries at 0.05 m.
//  - Parking: the car (0.9 m x 1.8 m, R = 2.5 m, Reeds-Shepp) backs into a 1.3 m bay of a
//    row of bays off a 20 m x 12 m lot.
//  - Rooms: a 24 m x 16 m floor of 3 x 2 rooms joined by 1 m doors; a small car (0.6 m x 0.4 m,
//    R = 0.5 m) from one corner room to the opposite one; heuristic weight 1 (admissible) and 1.5.
//  - Open: the parking car crossing a 20 m x 20 m yard with 60 random boxes, Dubins and
//    Reeds-Shepp.
// The planner's construction (the map's distance field and costs, once per map) is timed apart.
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=HybridAStar
#include <benchmark/benchmark.h>

#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/plan/hybrid_astar.hpp"

namespace bench_hybrid_astar {

using namespace starnav;

OccupancyGrid blank(double w_m, double h_m) {
  GridGeometry g;
  g.resolution = 0.05;
  g.width = static_cast<int>(std::lround(w_m / g.resolution));
  g.height = static_cast<int>(std::lround(h_m / g.resolution));
  return OccupancyGrid(g, kFreeOccupancy);
}

void fill(OccupancyGrid& grid, double x0, double y0, double x1, double y1) {
  const double r = grid.resolution();
  for (int iy = 0; iy < grid.height(); ++iy)
    for (int ix = 0; ix < grid.width(); ++ix) {
      const double x = (ix + 0.5) * r, y = (iy + 0.5) * r;
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) grid(ix, iy) = kOccupiedOccupancy;
    }
}

HybridAStarOptions car() {
  HybridAStarOptions o;
  o.minimum_turning_radius_m = 2.5;
  o.footprint_length_m = 1.8;
  o.footprint_width_m = 0.9;
  o.analytic_expansion_max_length_m = 0.0;
  return o;
}

struct Query {
  OccupancyGrid grid;
  Pose2 start, goal;
  HybridAStarOptions options;
};

// Bays 1.3 m wide and 2.6 m deep along the bottom of a 20 m x 12 m lot, separated by 0.2 m walls.
Query parking() {
  Query q{blank(20.0, 12.0), Pose2(4.0, 8.0, 0.0), Pose2(11.35, 1.5, kPi / 2), car()};
  fill(q.grid, 0.0, 0.0, 20.0, 0.2);
  for (int k = 0; k * 1.5 < 20.0; ++k) fill(q.grid, k * 1.5, 0.0, k * 1.5 + 0.2, 2.6);
  return q;
}

Query rooms(double weight) {
  Query q{blank(24.0, 16.0), Pose2(2.0, 2.0, 0.0), Pose2(22.0, 14.0, kPi / 2), HybridAStarOptions{}};
  // Outer walls, two inner walls across x and one along y, a door of 1 m in the middle of each.
  fill(q.grid, 0.0, 0.0, 24.0, 0.1);
  fill(q.grid, 0.0, 15.9, 24.0, 16.0);
  fill(q.grid, 0.0, 0.0, 0.1, 16.0);
  fill(q.grid, 23.9, 0.0, 24.0, 16.0);
  for (const double x : {8.0, 16.0}) {
    fill(q.grid, x - 0.05, 0.0, x + 0.05, 3.5);
    fill(q.grid, x - 0.05, 4.5, x + 0.05, 11.5);
    fill(q.grid, x - 0.05, 12.5, x + 0.05, 16.0);
  }
  for (const double x0 : {0.0, 8.0, 16.0}) {
    fill(q.grid, x0, 7.95, x0 + 3.5, 8.05);
    fill(q.grid, x0 + 4.5, 7.95, x0 + 8.0, 8.05);
  }
  q.options.minimum_turning_radius_m = 0.5;
  q.options.footprint_length_m = 0.6;
  q.options.footprint_width_m = 0.4;
  q.options.heuristic_weight = weight;
  return q;
}

Query open_yard(HybridMotionModel model) {
  Query q{blank(20.0, 20.0), Pose2(2.5, 2.5, 0.0), Pose2(17.5, 17.5, kPi / 2), car()};
  Rng rng(45);
  for (int k = 0; k < 60; ++k) {
    const double x = rng.uniform(1.0, 19.0), y = rng.uniform(1.0, 19.0), s = rng.uniform(0.2, 0.6);
    if (std::hypot(x - 2.5, y - 2.5) < 4.0 || std::hypot(x - 17.5, y - 17.5) < 4.0) continue;
    fill(q.grid, x - s, y - s, x + s, y + s);
  }
  q.options.motion_model = model;
  return q;
}

void run(benchmark::State& state, const Query& q) {
  HybridAStar planner(q.grid, q.options);
  PlanResult r;
  for (auto _ : state) {
    r = planner.plan(q.start, q.goal);
    benchmark::DoNotOptimize(r);
  }
  if (!r.found()) state.SkipWithError(plan_status_reason(r.status));
  state.counters["expanded"] = static_cast<double>(r.expanded);
  state.counters["length_m"] = r.length;
  state.counters["cost"] = r.cost;
}

void BM_HybridAStarParking(benchmark::State& state) { run(state, parking()); }
void BM_HybridAStarRooms(benchmark::State& state) { run(state, rooms(state.range(0) == 0 ? 1.0 : 1.5)); }
void BM_HybridAStarOpenYard(benchmark::State& state) {
  run(state, open_yard(state.range(0) == 0 ? HybridMotionModel::ReedsShepp : HybridMotionModel::Dubins));
}
void BM_HybridAStarBuild(benchmark::State& state) {
  const Query q = rooms(1.0);
  for (auto _ : state) {
    HybridAStar planner(q.grid, q.options);
    benchmark::DoNotOptimize(planner);
  }
}

BENCHMARK(BM_HybridAStarParking)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HybridAStarRooms)->Arg(0)->Arg(1)->ArgName("weighted")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HybridAStarOpenYard)->Arg(0)->Arg(1)->ArgName("dubins")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HybridAStarBuild)->Unit(benchmark::kMillisecond);

}  // namespace bench_hybrid_astar
