#pragma once
// A robot log as SLAM and mapping read it, whatever file it came from (CARMEN .clf, the text
// extracts of ../shared/datasets/carmen_raw, ROS 1 bags): 2D laser scans, wheel odometry, and
// ground-truth poses where a simulator wrote them. Times are the log's own stamps in integer
// microseconds, so that a stamp printed with 6 decimals survives exactly (the SLAM benchmark's
// relation files are matched by them); scans and odometry keep the log's order, which is not
// always time order (docs/slam.md).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/geometry.hpp"

namespace starnav {

// The most readings one scan may have: far above any real scanner (the SICK LMS 1xx family has
// 1141). Every reader refuses more before storing them.
inline constexpr std::size_t kMaxScanBeams = 100000;

// What a log's parsed records (scans with their readings, odometry, ground truth, IMU, transforms)
// may take beyond the bytes they come from: the log's size with its compressed parts counted
// decompressed (a .gz, a bag's chunks, a rosbag2 file or message compressed with zstd), at most
// kMaxLogFileBytes. A real log's records are smaller than its bytes (a reading of 6 or 7
// characters is stored as a 4-byte float, a 700-byte Odometry message as 56 bytes); only a
// degenerate log (30 million bare ODOM lines, a small archive of millions of messages) costs more,
// and is refused: from its counts (lines, messages per topic) before any record is stored, else
// as the records are stored.
inline constexpr std::size_t kLogRecordSlackBytes = std::size_t{64} << 20;
// The most bytes a log file may have on disk (2 GiB); decompressed, see core/input_file.hpp.
inline constexpr std::size_t kMaxLogFileBytes = std::size_t{2} << 30;
// The most any log's records may take: the largest log's size plus the slack.
inline constexpr std::size_t kMaxLogRecordBytes = kMaxLogFileBytes + kLogRecordSlackBytes;

// The account of a log's records against that bound (every reader keeps one).
class LogRecordBudget {
 public:
  // `source_bytes`: the log's size as read (decompressed); `limit`: instead of the rule (tests).
  LogRecordBudget(std::string path, std::uint64_t source_bytes, std::optional<std::size_t> limit = std::nullopt);
  // Decompressed data met while reading, beyond what `source_bytes` counted (messages compressed
  // one by one).
  void add_source(std::uint64_t bytes);
  std::uint64_t limit() const;
  // Throws when `bytes` more would pass the limit; `what` names the records ("2000000 odometry
  // lines"), `line` where they come from (0: the file).
  void check(std::uint64_t bytes, const std::function<std::string()>& what, int line = 0) const;
  // Adds `bytes` (check first).
  void charge(std::uint64_t bytes, const std::function<std::string()>& what, int line = 0);
  std::uint64_t used() const { return used_; }

 private:
  std::string path_;
  std::uint64_t source_ = 0, used_ = 0;
  std::optional<std::size_t> limit_;
};

struct LogScan {
  std::int64_t stamp_us = 0;        // CARMEN ipc_timestamp, bag header.stamp (rounded to 1 us)
  double angle_min_rad = 0.0;       // beam i at angle_min + i * angle_increment (sensor frame)
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;         // readings at or beyond it returned nothing
  std::vector<float> ranges_m;
  std::optional<Pose2> odometry;    // the robot's pose the line itself carries (FLASER, ROBOTLASER1)
  std::optional<Pose2> laser_pose;  // the laser's pose the line carries (FLASER x y theta, ROBOTLASER1);
                                    // corrected logs hold corrected poses here
  std::size_t source_index = 0;     // line (CARMEN, text) or message (bag) number, from 1

  double t_s() const { return static_cast<double>(stamp_us) * 1e-6; }
  double angle(std::size_t i) const { return angle_min_rad + static_cast<double>(i) * angle_increment_rad; }
  bool returned(std::size_t i) const {
    const double r = ranges_m[i];
    return r >= range_min_m && r < range_max_m;  // NaN fails both
  }
  // The end points (map frame) of the returned beams with a positive range, seen from `sensor`,
  // taking every k-th beam so that at most `max` beams are visited (a viewer's thinned scan).
  std::vector<Vec2> end_points(const Pose2& sensor, std::size_t max) const;
};

// What is wrong with a scan, in the words of sensor_msgs/LaserScan's fields (angle_min,
// angle_increment, range_min, range_max, ranges), for its reader to place at its line or message:
// more than kMaxScanBeams readings, angles that are not finite, an angle_increment of 0 with
// several beams, beams spanning more than a turn, range_min not finite or negative, range_max not
// above range_min (no reading could return), a negative reading (NaN and -inf, "too close" in
// REP 117, are fine). nullopt for a sound scan.
struct ScanFault {
  std::string field;
  std::string what;
};
std::optional<ScanFault> scan_fault(const LogScan& scan);

struct LogOdometry {
  std::int64_t stamp_us = 0;
  Pose2 pose;              // odom frame
  double tv_mps = 0.0;     // forward speed, where the log has it
  double rv_radps = 0.0;   // yaw rate
  std::size_t source_index = 0;  // line or message number, from 1 (as LogScan's; 0: unknown)
};

struct LogTruePose {
  std::int64_t stamp_us = 0;
  Pose2 pose;      // ground truth (simulator)
  Pose2 odometry;  // the odometry at the same instant
};

// An inertial reading (sensor_msgs/Imu), in the IMU's frame.
struct LogImu {
  std::int64_t stamp_us = 0;
  std::optional<double> yaw_rad;   // from the orientation, when the message has one (covariance[0] != -1)
  Vec3 angular_velocity_radps = Vec3::Zero();
  Vec3 linear_acceleration_mps2 = Vec3::Zero();
  std::size_t source_index = 0;
};

// A topic of a bag as `log info` lists it: every message counted, read or skipped.
struct LogTopic {
  std::string name;
  std::string type;            // as the bag names it ("sensor_msgs/LaserScan", "sensor_msgs/msg/LaserScan")
  std::size_t messages = 0;
  std::string use;             // "scan", "odometry", "truth", "imu", "tf", "tf_static"; empty: skipped
};

struct RobotLog {
  std::string path;
  std::string format;  // "carmen", "odomscan_text", "ros1_bag", "ros2_mcap", "ros2_sqlite3"
  std::vector<LogScan> scans;
  std::vector<LogOdometry> odometry;
  std::vector<LogTruePose> truth;
  std::vector<LogImu> imu;
  std::optional<Pose2> laser_in_base;           // PARAM robot_frontlaser_offset, /tf_static
  std::map<std::string, std::string> params;    // CARMEN PARAM lines, bag topics chosen
  std::map<std::string, std::size_t> skipped;   // lines of unknown types, messages of other topics
  std::vector<LogTopic> topics;                 // bags: every topic, in name order
  std::vector<std::string> warnings;            // what was read in spite of a flaw (a file cut short)
};

// A decimal timestamp ("1134864629.895182", "-0.5", "70.18", also %g's "4.29497e+09") as integer
// microseconds, computed in decimal (never through a double) and rounded half away from zero
// beyond 6 decimals; false for anything else (inf, nan, hex, overflow).
bool parse_stamp_us(std::string_view text, std::int64_t& us);
// With exactly 6 decimals, as the logs print them.
std::string format_stamp_us(std::int64_t us);

// The odometry pose at `stamp_us`: linear between the two readings around it in time (yaw the
// short way round), the nearest reading outside their span; nullopt without odometry. `sorted`
// must be in time order (sort_by_time).
std::optional<Pose2> odometry_at(const std::vector<LogOdometry>& sorted, std::int64_t stamp_us);
// The odometry pose at each scan of `log` (nullopt: none). The pose a scan's own line carries
// (FLASER, ROBOTLASER1) first; else, when the log's scans and odometry are each in time order,
// the odometry interpolated at the scan's stamp; else (stamps that are arrival times and go
// backwards, as intel's) the last odometry reading before the scan in the file (the first after
// it for scans before any), since time order scrambles such readings.
std::vector<std::optional<Pose2>> scan_odometry(const RobotLog& log);
// Calls `fn(scan, odometry)` for every scan that has an odometry pose (scan_odometry), in file
// order; `progress(done, total)` every 100 scans and once at the end.
void for_each_scan_with_odometry(const RobotLog& log, const std::function<void(const LogScan&, const Pose2&)>& fn,
                                 const std::function<void(std::size_t, std::size_t)>& progress = {});
// `e`, an error about one scan raised by code that knows nothing of files (a map or SLAM refusing
// its pose), placed at the scan: the log's file with the scan's line (text logs) or message (bags).
Error error_at_scan(const RobotLog& log, const LogScan& scan, const Error& e);
// The readings in time order (stable: equal stamps keep the log's order).
std::vector<LogOdometry> sort_by_time(std::vector<LogOdometry> odometry);

// A summary for `starnav log info`: counts, time span, beams, range limits, order.
struct RobotLogSummary {
  std::size_t scans = 0, odometry = 0, truth = 0, imu = 0;
  std::int64_t first_us = 0, last_us = 0;  // over scans and odometry
  std::size_t beams_min = 0, beams_max = 0;
  double range_max_m = 0.0;        // of the first scan
  std::size_t no_return = 0;       // readings at or beyond range_max
  std::size_t readings = 0;
  std::size_t scans_out_of_order = 0, odometry_out_of_order = 0;  // stamps earlier than the previous one
  bool scan_odometry_in_line = false;  // every scan carries its own odometry pose
};
RobotLogSummary summarise_log(const RobotLog& log);
// The summary as `starnav log info` prints it: text, or one JSON object.
std::string log_info_text(const RobotLog& log);
std::string log_info_json(const RobotLog& log);

}  // namespace starnav
