// The DWA controller (control/dwa_controller): one control step (the local window and its
// distances, the wavefront to the local goal, every sample rolled out, tested with the footprint
// and scored by the critics) in a cluttered room and an open one at 0.05 m. Spec target: 15 x 9 x 15 = 2,025
// samples over a 1.7 s horizon at 0.05 s steps in <= 5 ms median on one core with the circular
// footprint; the rectangle (0.55 m x 0.50 m) beside it.
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Dwa
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "starnav/control/dwa_controller.hpp"
#include "bench_support.hpp"

namespace bench_dwa {

using namespace starnav;


void BM_DwaStep(benchmark::State& state) {
  const bool circle = state.range(0) != 0;
  const int boxes = static_cast<int>(state.range(1));
  DwaConfig c;
  c.vx_samples = 15;
  c.vy_samples = 9;
  c.wz_samples = 15;
  c.sim_time_s = 1.7;
  c.sim_step_s = 0.05;
  c.footprint = circle ? "circle" : "rectangle";
  RobotConfig robot;  // the Mecanum robot: 0.55 m x 0.50 m
  robot.actuator_lag_s = 0.0;
  DwaController dwa(c, robot);
  const OccupancyGrid map = bench::cluttered_room(7, boxes);
  const std::vector<Vec2> path{{5.0, 6.0}, {7.0, 6.0}, {9.5, 6.5}};
  dwa.set_path(path);
  ControlInput in;
  in.limits = velocity_limits_of(robot);
  in.pose = Pose2(5.0, 6.0, 0.1);
  in.velocity = {0.3, 0.05, 0.2};
  in.local_map = &map;
  std::size_t valid = 0;
  for (auto _ : state) {
    const ControlOutput out = dwa.compute(in);
    benchmark::DoNotOptimize(out);
  }
  dwa.keep_samples(true);
  dwa.compute(in);
  for (const DwaSample& s : dwa.last_step().samples) valid += s.valid;
  state.counters["samples"] = static_cast<double>(dwa.last_step().samples.size());
  state.counters["valid"] = static_cast<double>(valid);
}
BENCHMARK(BM_DwaStep)
    ->ArgsProduct({{1, 0}, {200, 0}})
    ->ArgNames({"circle", "boxes"})
    ->Unit(benchmark::kMillisecond);

}  // namespace bench_dwa
