#pragma once
// CARMEN logs (.clf, .log, also gzipped) and the plain-text extracts of
// ../shared/datasets/carmen_raw/derived_from_bags (ODOMETRY / LASERSCAN lines).
//
// CARMEN lines read (fields as CARMEN's logger writes them; ipc_timestamp is the message's time):
//   FLASER n r1..rn x y theta odom_x odom_y odom_theta ipc_timestamp ipc_hostname logger_timestamp
//   RAWLASER1..4 type start_angle fov resolution max_range accuracy remission_mode n r1..rn
//       m e1..em ipc_timestamp ipc_hostname logger_timestamp
//   ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode n r1..rn m e1..em
//       laser_x laser_y laser_theta x y theta tv rv forward_safety side_safety turn_axis
//       ipc_timestamp ipc_hostname logger_timestamp
//   ODOM x y theta tv rv accel ipc_timestamp ipc_hostname logger_timestamp
//   TRUEPOS x y theta odom_x odom_y odom_theta ipc_timestamp ipc_hostname logger_timestamp
//   PARAM name value ...   (robot_frontlaser_offset gives the laser's forward offset)
// Other line types are skipped and counted; '#' lines are comments.
//
// FLASER and LASERSCAN store no beam angles: n beams span the front half-plane as CARMEN's
// lasers did (docs/slam.md): 180 beams 1 deg apart from -90 deg, 360 beams 0.5 deg apart from -90
// deg, any other n from -90 to +90 deg inclusive (361: 0.5 deg). Their no-return value is not
// stored either: it is the value a saturated sensor repeats at the top of its readings (81.91 m,
// 81.83 m, 50.00 m in the benchmark logs): the largest value repeated at least 10 times and 0.1 %
// of the readings. Readings above it repeat less: strays (one reading 0.01 m above it, a
// corrupt value), no return too, with a warning; without such a value every reading counts, with a
// warning. `range_max_m` overrides. A reading beyond a float's range is refused.
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "starnav/logs/robot_log.hpp"

namespace starnav {

struct LogReadOptions {
  std::optional<double> range_max_m;  // readings at or beyond it returned nothing
  // Bags (ROS 1 and ROS 2; logs/bag_log.hpp): the topics read, each by name or, empty, by type.
  std::string scan_topic;   // the LaserScan topic (default: the only one)
  std::string odom_topic;   // an Odometry topic, or a TFMessage topic (/tf: the odom -> base transforms);
                            // default: the only Odometry topic, else /tf when it holds odom -> base
  std::string imu_topic;    // the Imu topic (default: the only one)
  std::string truth_topic;  // the ground truth: an Odometry, PoseStamped or PoseWithCovarianceStamped
                            // topic (default: none)
  // A log without scans is read (a bag's topics listed) rather than refused: `log info`. Otherwise
  // a log that holds no scan is refused before its odometry is stored.
  bool allow_no_scans = false;
  // The most the parsed records may take, instead of the log's size rule (LogRecordBudget): tests
  // try the bound on small logs.
  std::optional<std::size_t> record_limit_bytes;
  // Bags converted from FLASER logs: the beam angles of FLASER (above) instead of the messages'
  // angle_min and angle_increment, which such converters invented.
  bool flaser_beam_angles = false;
  // Told what the reader assumed about the log (an inferred no-return value that leaves readings
  // above it); a command prints it as a warning.
  std::function<void(const std::string&)> warn;
};

// FLASER's beam layout for n beams (see above): angle_min and angle_increment of `scan`.
void set_flaser_beam_angles(LogScan& scan, std::size_t n);

// `text` is the whole (decompressed) file; `path` names it in errors (FILE:LINE: FIELD: what).
RobotLog read_carmen_log(std::string_view text, const std::string& path, const LogReadOptions& options = {});
RobotLog read_odomscan_text(std::string_view text, const std::string& path, const LogReadOptions& options = {});

// True when the first non-comment line of `text` is an ODOMETRY or LASERSCAN line.
bool looks_like_odomscan_text(std::string_view text);

// `log` as a CARMEN log, lines in time order (stable): PARAM robot_frontlaser_offset (the mount's
// forward offset, when it has one), ODOM, TRUEPOS and one line per scan: FLASER when the scan has
// FLASER's beam layout (above), else ROBOTLASER1 (it carries the start angle, resolution and
// maximum range). A scan's odometry is the pose its line carries, else the odometry interpolated
// at its stamp; the laser pose written beside it is the one the scan carries, else that pose moved
// by the mount (so a log read and written again keeps its bytes). Beams that
// returned nothing are written as range_max. Ranges with 3 decimals, poses with 6, stamps with 6.
std::string carmen_log_text(const RobotLog& log, const std::string& host = "starnav");

}  // namespace starnav
