#pragma once
// A robot log (robot_log.hpp) played as the messages its robot's drivers gave
// (sense/sensor_source.hpp): per scan, in file order (the order of receipt), the odometry at the scan's stamp as an
// OdometryMessage on the odometry stream, then the scan as a ScanMessage in its sensor frame with
// the laser's mount (the log's laser_in_base, else zero) on the scan stream. The odometry is the
// one rule of robot_log.hpp's scan_odometry: the pose the scan's line carries, else the odometry
// interpolated at its stamp, else (stamps that go backwards) the last reading before it in the
// file. A scan without any odometry pose is published alone (its twist: zero, a log's odometry
// pose carries none). Message times are the stamps in seconds (LogScan::t_s); rounded to whole
// microseconds they give the same stamps back (checked for every stamp up to the year 2096).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "starnav/logs/robot_log.hpp"
#include "starnav/sense/sensor_messages.hpp"
#include "starnav/sense/sensor_source.hpp"

namespace starnav {

struct RobotLogStreams {
  std::string scan = "lidar";
  std::string odometry = "odom";
};

// A log's scan as its driver published it: the same beams and range limits, stamped `scan.t_s()`.
ScanMessage scan_message(const LogScan& scan, const Pose3& mount, const std::string& stream);
// The laser's mount of a log in space: laser_in_base at z = 0 (zero without one).
Pose3 log_laser_mount(const RobotLog& log);

class RobotLogSource final : public SensorSource {
 public:
  // `log` must outlive the source.
  explicit RobotLogSource(const RobotLog& log, RobotLogStreams streams = {});
  std::size_t readings() const override { return log_.scans.size(); }
  const std::string& origin() const override { return log_.path; }
  // Scans in file order. An Error from `sink` or `published` that names no file names the scan's
  // line (error_at_scan).
  void play(const SensorSink& sink, const std::function<void(std::size_t)>& published) override;

 private:
  const RobotLog& log_;
  RobotLogStreams streams_;
};

}  // namespace starnav
