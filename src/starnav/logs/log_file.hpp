#pragma once
// One entry point for robot logs: the format is read from the content (a ROS bag's magic line,
// the text extracts' ODOMETRY / LASERSCAN lines, else CARMEN), gzip is undone first.
#include <string>

#include "starnav/logs/carmen_log.hpp"

namespace starnav {

// Throws Error naming the file (and line or byte, and field) for anything it cannot read: not a
// regular file, too large, corrupt compression, malformed lines or records.
RobotLog read_robot_log(const std::string& path, const LogReadOptions& options = {});

}  // namespace starnav
