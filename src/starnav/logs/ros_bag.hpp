#pragma once
// ROS 1 bag files (format 2.0) without ROS: the record layout of the rosbag format
// (wiki.ros.org/Bags/Format/2.0), chunks stored plain or compressed with bzip2 or LZ4, and the
// messages a 2D SLAM needs decoded from their ROS serialisation: sensor_msgs/LaserScan,
// nav_msgs/Odometry and tf2_msgs/TFMessage (for the base-to-laser transform on /tf_static).
//
// Topics: the LaserScan and Odometry topics are found by type; a bag with several of one type
// needs the topic named (LogReadOptions::scan_topic / odom_topic, the CLI's --scan-topic /
// --odom-topic). Stamps are header.stamp (the CARMEN ipc_timestamp for the converted benchmark
// logs) rounded to 1 us. The laser's pose on the base comes from /tf_static: the chain of static
// transforms from the odometry's child frame (base_link without odometry) to the scan's frame.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/logs/carmen_log.hpp"

namespace starnav {

struct BagConnection {
  std::uint32_t id = 0;
  std::string topic;
  std::string type;  // "sensor_msgs/LaserScan"
  std::string md5sum;
};

struct BagMessageView {
  const BagConnection* connection = nullptr;
  std::uint64_t record_time_ns = 0;  // the time the recorder stored (receipt time)
  std::string_view data;             // the serialised message
  std::size_t file_offset = 0;       // of the record, or of its chunk when compressed
};

// Walks every message record of a bag in file order (chunks decompressed one at a time).
// Throws Error naming `path`, the byte offset and the record field for malformed input.
void for_each_bag_message(std::string_view bytes, const std::string& path,
                          const std::function<void(const BagMessageView&)>& visit);
// The connections (topics and types) of a bag, in id order.
std::vector<BagConnection> bag_connections(std::string_view bytes, const std::string& path);

// True when `bytes` starts with the bag 2.0 magic line.
bool is_ros1_bag(std::string_view bytes);

RobotLog read_ros1_bag(std::string_view bytes, const std::string& path, const LogReadOptions& options = {});

}  // namespace starnav
