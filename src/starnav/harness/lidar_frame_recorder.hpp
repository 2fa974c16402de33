#pragma once
// What a robot records for 3D mapping, from a simulation (outputs.lidar_frames): every n-th scan
// of the LiDAR as a binary PCD in the sensor frame, and per frame the wheel odometry (integrated
// from the encoders, slip included), the latest gyro reading and the true base_link pose; written
// into OUT/lidar/ as cloud/lidar_frames.hpp describes. Clouds go to disk as they come, so a long
// run holds only the table in memory.
#include <memory>
#include <string>

#include "starnav/cloud/lidar_frames.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {

class LidarFrameRecorder {
 public:
  // Subscribes to the first LiDAR's scans and the IMU (a recorder) and the encoders (their
  // odometry), and writes DIR/sensor.yaml. `sim` must outlive the subscriptions; the recorder must outlive the run. Throws
  // Error when the scenario has no LiDAR or DIR cannot be created.
  LidarFrameRecorder(Simulation& sim, const std::string& dir, int every_n_scans);
  // Writes DIR/frames.csv (after the run).
  void finish() const;
  std::size_t frames() const;

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace starnav
