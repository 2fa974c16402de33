#include "starnav/logs/log_file.hpp"

#include <filesystem>
#include <iostream>
#include <system_error>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/logs/decompress.hpp"
#include "starnav/logs/ros2_bag.hpp"
#include "starnav/logs/ros_bag.hpp"

namespace starnav {

namespace {

// What a reader read in spite of a flaw (a recording cut short) is said on stderr, once per read.
RobotLog print_warnings(RobotLog log) {
  for (const std::string& w : log.warnings) std::cerr << "starnav: warning: " << w << "\n";
  return log;
}

}  // namespace

RobotLog read_robot_log(const std::string& path, const LogReadOptions& options) {
  const InputFileScope reading_path(path);
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw Error("no such file", path);
  if (fs::is_directory(st) && is_ros2_bag_folder(path)) return print_warnings(read_ros2_bag(path, options));
  // Devices and pipes could feed bytes without end.
  if (!fs::is_regular_file(st))
    throw Error(fs::is_directory(st) ? "is a directory without metadata.yaml, not a log or a rosbag2 folder" : "is not a regular file", path);
  // A log's head says its kind before the rest is read: a compressed stream, a bag or recording by
  // its magic, else text, which holds no NUL byte (a binary or sparse file costs its head).
  std::string bytes = read_input_file(path, kMaxLogFileBytes, kTextHeadBytes, [&](std::string_view head, std::uint64_t) {
    if (is_gzip(head) || is_ros1_bag(head) || is_ros2_bag_bytes(head)) return;
    const std::size_t nul = head.find('\0');
    if (nul != std::string_view::npos)
      throw Error("byte " + std::to_string(nul) +
                      " is a NUL: not a CARMEN log or text extract (text), a ROS 1 bag, an MCAP or SQLite3 recording, or gzip",
                  path);
  });
  if (is_gzip(bytes)) bytes = gunzip(bytes, path);
  if (is_ros1_bag(bytes)) return print_warnings(read_ros1_bag(bytes, path, options));
  if (is_ros2_bag_bytes(bytes)) return print_warnings(read_ros2_bag_bytes(bytes, path, options));
  if (looks_like_odomscan_text(bytes)) return read_odomscan_text(bytes, path, options);
  RobotLog log = read_carmen_log(bytes, path, options);
  if (log.scans.empty() && log.odometry.empty() && log.truth.empty())
    throw Error("holds no laser, odometry or ground-truth line: not a CARMEN log, text extract, ROS 1 bag or ROS 2 recording", path);
  return log;
}

}  // namespace starnav
