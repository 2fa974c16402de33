#include "starnav/logs/robot_log_source.hpp"

#include <optional>
#include <utility>
#include <vector>

#include "starnav/core/error.hpp"

namespace starnav {

ScanMessage scan_message(const LogScan& scan, const Pose3& mount, const std::string& stream) {
  ScanMessage m;
  m.header = {scan.t_s(), stream};
  m.mount = mount;
  m.angle_min_rad = scan.angle_min_rad;
  m.angle_increment_rad = scan.angle_increment_rad;
  m.range_min_m = scan.range_min_m;
  m.range_max_m = scan.range_max_m;
  m.ranges_m.assign(scan.ranges_m.begin(), scan.ranges_m.end());
  return m;
}

Pose3 log_laser_mount(const RobotLog& log) {
  const Pose2 m = log.laser_in_base.value_or(Pose2());
  return Pose3::from_rpy(Vec3(m.x, m.y, 0.0), 0.0, 0.0, m.yaw);
}

RobotLogSource::RobotLogSource(const RobotLog& log, RobotLogStreams streams) : log_(log), streams_(std::move(streams)) {}

void RobotLogSource::play(const SensorSink& sink, const std::function<void(std::size_t)>& published) {
  const std::vector<std::optional<Pose2>> odometry = scan_odometry(log_);
  const Pose3 mount = log_laser_mount(log_);
  for (std::size_t k = 0; k < log_.scans.size(); ++k) {
    const LogScan& scan = log_.scans[k];
    try {
      if (const std::optional<Pose2>& odom = odometry[k]) {
        OdometryMessage o;
        o.header = {scan.t_s(), streams_.odometry};
        o.pose = *odom;
        sink(SensorMessage(std::move(o)));
      }
      sink(SensorMessage(scan_message(scan, mount, streams_.scan)));
      if (published) published(k + 1);
    } catch (const Error& e) {
      throw error_at_scan(log_, scan, e);
    }
  }
}

}  // namespace starnav
