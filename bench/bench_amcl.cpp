// AMCL (estimate/amcl): one filter update (motion model, likelihood field over the used beams,
// KLD resampling, clusters) against the particle count and the beams used, on a 30 m x 20 m
// office-like map at 0.05 m. min_particles = max_particles fixes the count. The odometry
// alternates between two poses 0.3 m apart so that every call updates (update_min_d 0.25 m);
// the scans are cast from the true poses. Spec target: <= 5 ms for 5,000 particles and 60 beams
// on one core. Counter time_per_beam: time per particle and used beam.
// Also the likelihood field's construction (exact distance transforms) on a 1000 x 1000 map.
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Amcl
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/estimate/amcl.hpp"

namespace bench_amcl {

using namespace starnav;

// Rooms of 5 m x 5 m with 1 m doors, outer walls, and random furniture boxes.
OccupancyGrid office_map(double width_m, double height_m, double resolution, std::uint64_t seed) {
  GridGeometry g;
  g.width = static_cast<int>(std::lround(width_m / resolution));
  g.height = static_cast<int>(std::lround(height_m / resolution));
  g.resolution = resolution;
  OccupancyGrid grid(g, kFreeOccupancy);
  const int wall = static_cast<int>(std::lround(0.1 / resolution));
  const int room = static_cast<int>(std::lround(5.0 / resolution));
  const int door = static_cast<int>(std::lround(1.0 / resolution));
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const bool outer = ix < wall || iy < wall || ix >= g.width - wall || iy >= g.height - wall;
      const bool vertical = ix % room < wall && (iy % room) > door + wall && (iy % room) < room - door;
      const bool horizontal = iy % room < wall && (ix % room) > door + wall && (ix % room) < room - door;
      if (outer || vertical || horizontal) grid(ix, iy) = kOccupiedOccupancy;
    }
  Rng rng(seed);
  for (int k = 0; k < 40; ++k) {
    const int x0 = static_cast<int>(rng.uniform_int(wall, g.width - 30)), y0 = static_cast<int>(rng.uniform_int(wall, g.height - 30));
    const int w = static_cast<int>(rng.uniform_int(4, 16)), h = static_cast<int>(rng.uniform_int(4, 16));
    for (int iy = y0; iy < y0 + h; ++iy)
      for (int ix = x0; ix < x0 + w; ++ix) grid(ix, iy) = kOccupiedOccupancy;
  }
  // Keep the robot's corridor clear.
  for (int iy = static_cast<int>(2.2 / resolution); iy < static_cast<int>(2.8 / resolution); ++iy)
    for (int ix = static_cast<int>(1.0 / resolution); ix < static_cast<int>(4.0 / resolution); ++ix)
      grid(ix, iy) = kFreeOccupancy;
  return grid;
}

PlanarScan cast_scan(const BeamModel& caster, const Pose2& laser, int beams, double range_max) {
  PlanarScan s;
  s.range_min_m = 0.05;
  s.range_max_m = range_max;
  for (int i = 0; i < beams; ++i) {
    const double a = kPi - i * (2.0 * kPi / beams);
    const double r = caster.expected_range(Pose2(laser.x, laser.y, laser.yaw + a), range_max);
    s.ranges.push_back(r);
    s.angles_rad.push_back(a);
  }
  return s;
}

void BM_AmclUpdate(benchmark::State& state) {
  const int particles = static_cast<int>(state.range(0));
  const int beams = static_cast<int>(state.range(1));
  const OccupancyGrid map = office_map(30.0, 20.0, 0.05, 1);
  const BeamModel caster(map, {}, {});
  AmclConfig c;
  c.min_particles = c.max_particles = particles;
  c.max_beams = beams;
  const Pose2 mount(0.1, 0.0, 0.0);
  Amcl amcl(map, {}, c, mount, 1);
  const Pose2 truth_a(2.0, 2.5, 0.0), truth_b(2.3, 2.5, 0.0);
  const PlanarScan scan_a = cast_scan(caster, truth_a.compose(mount), 360, 30.0);
  const PlanarScan scan_b = cast_scan(caster, truth_b.compose(mount), 360, 30.0);
  amcl.initialize(truth_a, Eigen::Vector3d(0.09, 0.09, 0.03).asDiagonal());
  amcl.update(truth_a, scan_a);  // the first update: the odometry reference
  bool at_b = false;
  for (auto _ : state) {
    at_b = !at_b;
    benchmark::DoNotOptimize(at_b ? amcl.update(truth_b, scan_b) : amcl.update(truth_a, scan_a));
  }
  state.counters["particles"] = amcl.estimate().particles;
  // Seconds per particle and beam (printed with an SI prefix).
  state.counters["time_per_beam"] = benchmark::Counter(static_cast<double>(particles) * beams,
                                                       benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_AmclLikelihoodFieldBuild(benchmark::State& state) {
  const OccupancyGrid map = office_map(50.0, 50.0, 0.05, 2);
  LikelihoodFieldConfig c;
  c.reference = state.range(0) == 0 ? FieldReference::Centre : FieldReference::Surface;
  for (auto _ : state) {
    LikelihoodField field(map, {}, c);
    benchmark::DoNotOptimize(field.distance_m(Vec2(1.0, 1.0)));
  }
  state.SetLabel(state.range(0) == 0 ? "centre" : "surface");
}

BENCHMARK(BM_AmclUpdate)
    ->ArgNames({"particles", "beams"})
    ->ArgsProduct({{500, 5000, 20000}, {60, 360}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AmclLikelihoodFieldBuild)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace bench_amcl
