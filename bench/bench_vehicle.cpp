// One simulator step of the vehicle (attitude from the surface under the wheels, steps, slides,
// collisions) while the paper's Mecanum robot drives at 0.2 m/s over the test platform's slope
// and step and a gravel field on a flat 10 m terrain (the scene of Li 2019's E1). The steps of
// one iteration cover the whole 6 m drive, so every phase (flat, ramp, step, gravel) counts.
// Counter: us_per_step. Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Vehicle
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/sim/obstacles.hpp"
#include "starnav/sim/vehicle.hpp"
#include "starnav/sim/world.hpp"

namespace bench_vehicle {

using namespace starnav;

World platform_world() {
  GridGeometry g;
  g.width = g.height = 200;
  g.resolution = 0.05;
  g.origin = Pose2(-1.0, -5.0, 0.0);
  ElevationMap flat(g);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) flat.set_height(ix, iy, 0.0);
  SlopeStep ss;
  ss.position = Vec3(1.5, 0.0, 0.0);
  Gravel gr;
  gr.position = Vec3(4.0, 0.0, 0.0);
  gr.follow_terrain = false;
  WorldDescription d;
  d.obstacles = {make_slope_step(ss), make_gravel(gr)};
  d.terrain = flat;
  return World(d);
}

void BM_VehicleStepOverTestPlatform(benchmark::State& state) {
  const World world = platform_world();
  constexpr int kSteps = 3000;  // 30 s at dt = 0.01 s: x from 0 to 6 m
  std::vector<VehicleEvent> events;
  for (auto _ : state) {
    Vehicle v(world, VehicleConfig{}, Pose2(0.0, 0.0, 0.0), Rng(1));
    for (int i = 0; i < kSteps; ++i) v.step({0.2, 0.0, 0.0}, 0.01, events);
    benchmark::DoNotOptimize(v.state().pose.position.x());
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
  // kIsRate | kInvert: seconds per (value), so a value of steps / 1e6 reads as microseconds per step.
  state.counters["us_per_step"] = benchmark::Counter(
      static_cast<double>(state.iterations() * kSteps) * 1e-6,
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_VehicleStepOverTestPlatform)->Unit(benchmark::kMillisecond);

}  // namespace bench_vehicle
