#pragma once
// A LiDAR recording (lidar_recording.hpp) played as the messages its robot's drivers gave
// (sense/sensor_source.hpp): per frame, in order, the wheel odometry at the frame's time as an
// OdometryMessage when the recording has it (frames.csv's columns, a bag's odometry interpolated
// to the cloud's stamp), then the cloud as a CloudMessage in the sensor frame with the sensor's
// mount, in the recording's order.
#include <cstddef>
#include <functional>
#include <string>

#include "starnav/cloud/lidar_recording.hpp"
#include "starnav/sense/sensor_source.hpp"

namespace starnav {

struct LidarRecordingStreams {
  std::string cloud = "lidar";
  std::string odometry = "odom";
};

class LidarRecordingSource final : public SensorSource {
 public:
  // The first `frames` frames of `recording` (0: all); `recording` must outlive the source.
  LidarRecordingSource(const LidarRecording& recording, std::size_t frames = 0, LidarRecordingStreams streams = {});
  std::size_t readings() const override { return count_; }
  const std::string& origin() const override { return recording_.path; }
  void play(const SensorSink& sink, const std::function<void(std::size_t)>& published) override;

 private:
  const LidarRecording& recording_;
  std::size_t count_ = 0;
  LidarRecordingStreams streams_;
};

}  // namespace starnav
