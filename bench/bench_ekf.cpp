// The odometry + IMU EKF (estimate/odometry_imu_ekf): one step = a prediction from an odometry
// increment with the slip covariance plus an IMU yaw update, for the paper's three states and the
// five with the gyro bias. Spec target: one EKF step under 2 us.
// Run pinned: taskset -c 1 build/bin/starnav_bench --benchmark_filter=Ekf
#include <benchmark/benchmark.h>

#include "starnav/estimate/odometry_imu_ekf.hpp"

namespace bench_ekf {

using namespace starnav;

void BM_EkfStep(benchmark::State& state) {
  const auto model = make_robot_model(RobotConfig{});
  EkfConfig c;
  c.bias_state = state.range(0) != 0;
  c.initial_sigma_xy_m = 0.01;
  c.initial_sigma_yaw_rad = 0.01;
  c.tick_rad = 2.0 * 3.141592653589793 / 1024;
  OdometryImuEkf ekf(c, *model, {});
  double yaw = 0.0;
  for (auto _ : state) {
    ekf.predict(Pose2(0.006, 0.0005, 0.001));
    yaw += 0.001;
    benchmark::DoNotOptimize(ekf.update_yaw(yaw, 0.01));
  }
  benchmark::DoNotOptimize(ekf.pose());
}
BENCHMARK(BM_EkfStep)->Arg(0)->Arg(1)->ArgName("bias_state");

}  // namespace bench_ekf
