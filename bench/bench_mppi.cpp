// The MPPI controller (control/mppi_controller): one control step (the local window and its
// distances, the path ahead resampled, 2,000 noised sequences of 56 steps of 0.05 s kept within the
// limits, rolled out, scored by the default critics, softmax-averaged, checked and smoothed) in a
// cluttered room and an open one at 0.05 m, for the Mecanum robot (omni: vx, vy, wz) and a
// differential one (vx, wz); the footprint-checked obstacle critic beside the inscribed circle's.
// Spec target: 2,000 x 56 in <= 5 ms median on one core (Nav2's MPPI: about 11.8 ms).
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Mppi
#include <benchmark/benchmark.h>

#include <vector>

#include "starnav/control/mppi_controller.hpp"
#include "bench_support.hpp"

namespace bench_mppi {

using namespace starnav;


void BM_MppiStep(benchmark::State& state) {
  const bool omni = state.range(0) != 0;
  const int boxes = static_cast<int>(state.range(1));
  MppiConfig c;  // Nav2's defaults; batch 2,000 x 56 steps
  c.obstacles.consider_footprint = state.range(2) != 0;
  RobotConfig robot;  // the Mecanum robot: 0.55 m x 0.50 m
  robot.actuator_lag_s = 0.0;
  if (!omni) robot.drive = DriveKind::Differential;
  MppiController mppi(c, robot, 1);
  const OccupancyGrid map = bench::cluttered_room(7, boxes);
  const std::vector<Vec2> path{{5.0, 6.0}, {7.0, 6.0}, {9.5, 6.5}};
  mppi.set_path(path);
  ControlInput in;
  in.limits = velocity_limits_of(robot);
  in.pose = Pose2(5.0, 6.0, 0.1);
  in.velocity = {0.3, omni ? 0.05 : 0.0, 0.2};
  in.local_map = &map;
  in.goal = path.back();
  for (auto _ : state) {
    in.t_s += c.control_period_s;  // a new step: the sequence shifts as in a run
    const ControlOutput out = mppi.compute(in);
    benchmark::DoNotOptimize(out);
  }
  state.counters["samples"] = static_cast<double>(mppi.costs().size());
  state.counters["steps"] = static_cast<double>(c.time_steps);
}
BENCHMARK(BM_MppiStep)
    ->Args({1, 200, 0})
    ->Args({1, 0, 0})
    ->Args({0, 200, 0})
    ->Args({1, 200, 1})
    ->ArgNames({"omni", "boxes", "footprint"})
    ->Unit(benchmark::kMillisecond);

}  // namespace bench_mppi
