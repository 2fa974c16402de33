#pragma once
// ROS 1 bag files (format 2.0) without ROS: the record layout of the rosbag format
// (wiki.ros.org/Bags/Format/2.0), chunks stored plain or compressed with bzip2 or LZ4, and the
// messages a 2D or 3D SLAM needs decoded from their ROS serialisation: sensor_msgs/LaserScan,
// sensor_msgs/PointCloud2, nav_msgs/Odometry and tf2_msgs/TFMessage (for the base-to-sensor
// transform on /tf_static).
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

#include "starnav/core/geometry.hpp"
#include "starnav/logs/carmen_log.hpp"

namespace starnav {

struct BagConnection {
  std::uint32_t id = 0;
  std::string topic;
  std::string type;  // "sensor_msgs/LaserScan"
  std::string md5sum;
  std::uint64_t messages = 0;  // message records on the connection
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
// What one pass over a bag finds before any message is decoded: its connections (topics, types
// and message counts) in id order, and its size with every chunk counted decompressed.
struct BagContents {
  std::vector<BagConnection> connections;
  std::uint64_t decompressed_bytes = 0;
};
BagContents bag_contents(std::string_view bytes, const std::string& path);

// True when `bytes` starts with the bag 2.0 magic line.
bool is_ros1_bag(std::string_view bytes);

RobotLog read_ros1_bag(std::string_view bytes, const std::string& path, const LogReadOptions& options = {});

// ---- 3D LiDAR recordings: sensor_msgs/PointCloud2 -------------------------------------------------
//
// The cloud topic is found by type like the scan topic (named when there are several); the
// odometry (nav_msgs/Odometry, the registration's guess) likewise, and a second Odometry topic can
// be named as the ground truth (a simulator's or a motion-capture system's base pose). A cloud's
// points are the x, y, z fields (FLOAT32 or FLOAT64, either byte order) of every point whose three
// coordinates are finite, in the cloud's frame; the sensor's pose on the base is the chain of
// /tf_static transforms from the odometry's child frame (base_link without odometry) to it.

struct PointCloudBagOptions {
  std::string cloud_topic, odom_topic, truth_topic;  // empty: by type (truth: none)
};

struct StampedPose3 {
  std::int64_t stamp_us = 0;
  Pose3 pose;
};

// What a bag of clouds holds, but the points: read in one pass before the clouds are streamed.
struct PointCloudBagIndex {
  std::string cloud_topic, odom_topic, truth_topic;
  std::vector<std::int64_t> cloud_stamps_us;  // header stamps, in file order
  std::string cloud_frame, base_frame;
  std::vector<LogOdometry> odometry;          // planar, odom frame
  std::vector<StampedPose3> truth;            // the base's true pose
  std::optional<Pose3> sensor_in_base;        // from /tf_static
};

struct BagPointCloud {
  std::int64_t stamp_us = 0;
  std::string frame_id;
  std::vector<Vec3> points;
  std::size_t dropped = 0;        // points with a non-finite coordinate
  std::size_t source_index = 0;   // the message's number in the bag, from 1
};

PointCloudBagIndex index_point_cloud_bag(std::string_view bytes, const std::string& path, const PointCloudBagOptions& options = {});
// The clouds of the indexed topic in file order, decoded one at a time.
void for_each_bag_point_cloud(std::string_view bytes, const std::string& path, const PointCloudBagIndex& index,
                              const std::function<void(BagPointCloud&&)>& visit);

}  // namespace starnav
