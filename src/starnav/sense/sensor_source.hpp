#pragma once
// A recording played onto a SensorBus as the messages its sensors gave (sensor_messages.hpp): a
// robot log (logs/robot_log_source.hpp), a LiDAR recording (cloud/lidar_recording_source.hpp).
// A source publishes reading by reading in time order (a scan or a cloud, with the messages that
// belong to it) and calls back after each reading, where the one who plays it delivers what was
// published. The roles subscribed to the bus cannot tell a recording from a simulation.
//
// Odometry at a scan: before each scan or cloud a recording's source publishes an OdometryMessage
// stamped at the scan's time (the odom -> base pose at that instant, as the recording gives it or
// interpolates it, as a tf2 lookup would); a consumer uses the latest odometry it has when a scan
// arrives. A simulation integrates wheel odometry every step and its scans come after that step's
// odometry, so the same rule holds there.
#include <cstddef>
#include <functional>
#include <string>

#include "starnav/sense/sensor_bus.hpp"

namespace starnav {

class SensorSource {
 public:
  virtual ~SensorSource() = default;
  // The readings (scans, frames) the source will publish: what progress counts.
  virtual std::size_t readings() const = 0;
  // The recording's file or folder: what an error after the last reading (a SLAM's final
  // optimisation, say) names.
  virtual const std::string& origin() const = 0;
  // Publishes every reading on `bus`, in time order; after each, `published(k)` with the readings
  // published so far. Errors name the recording's file and field; a source may
  // locate an Error thrown by `published` (by a consumer of the reading's messages) that names no
  // file at the reading's place in the recording (a log's line: RobotLogSource).
  virtual void play(SensorBus& bus, const std::function<void(std::size_t)>& published) = 0;
};

}  // namespace starnav
