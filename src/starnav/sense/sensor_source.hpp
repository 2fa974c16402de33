#pragma once
// A recording played as the messages its sensors gave (sensor_messages.hpp): a robot log
// (logs/robot_log_source.hpp), a LiDAR recording (cloud/lidar_recording_source.hpp). A source
// gives its messages to a sink reading by reading (a scan or a cloud, with the messages that
// belong to it) in the recording's order, and calls back after each reading. That order is the
// order of receipt, as rosbag play keeps it: a log whose stamps go backwards now and then (intel's
// bag has 631 such scans) is played as it was recorded, onto a SensorBus in receipt order
// (play_onto_bus), as a robot's middleware delivers it. The roles fed by a source cannot tell a
// recording from a simulation.
//
// Odometry at a scan: before each scan or cloud a recording's source gives an OdometryMessage
// stamped at the scan's time (the odom -> base pose at that instant, as the recording gives it or
// interpolates it, as a tf2 lookup would); a consumer uses the latest odometry it has when a scan
// arrives. A simulation integrates wheel odometry every step and its scans come after that step's
// odometry, so the same rule holds there.
#include <cstddef>
#include <functional>
#include <string>

#include "starnav/sense/sensor_bus.hpp"

namespace starnav {

using SensorSink = std::function<void(const SensorMessage&)>;

class SensorSource {
 public:
  virtual ~SensorSource() = default;
  // The readings (scans, frames) the source will publish: what progress counts.
  virtual std::size_t readings() const = 0;
  // The recording's file or folder: what an error after the last reading (a SLAM's final
  // optimisation, say) names.
  virtual const std::string& origin() const = 0;
  // Gives every reading's messages to `sink`, in the recording's order; after each reading,
  // `published(k)` with the readings given so far. Errors name the recording's file and field; a
  // source may locate an Error thrown by `sink` or `published` (by a consumer of the reading's
  // messages) that names no file at the reading's place in the recording (a log's line:
  // RobotLogSource).
  virtual void play(const SensorSink& sink, const std::function<void(std::size_t)>& published) = 0;
};

// Plays `source` onto `bus`, delivering everything after each reading (then `published(k)`). A bus
// in time order refuses a message stamped before one it has delivered; one in receipt order
// (SensorBus::Order::Receipt) plays any recording as received.
void play_onto_bus(SensorSource& source, SensorBus& bus, const std::function<void(std::size_t)>& published = {});

}  // namespace starnav
