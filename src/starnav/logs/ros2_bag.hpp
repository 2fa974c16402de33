#pragma once
// ROS 2 recordings (rosbag2) without ROS, behind the same RobotLog and point-cloud interfaces as
// ROS 1 bags (docs/ros2.md):
//  - one file: MCAP (logs/mcap.hpp; the default storage since ROS 2 Iron) or SQLite3 (.db3,
//    logs/rosbag2_sqlite.hpp), told apart by content;
//  - a rosbag2 folder: metadata.yaml (rosbag2_bagfile_information: storage_identifier,
//    relative_file_paths, compression_format and compression_mode) and its split files, read in the
//    order metadata.yaml lists them; files compressed whole (compression_mode FILE, `.zstd`) or
//    message by message (MESSAGE) with zstd.
// Only CDR-serialised topics (rosbag2's serialization_format cdr, MCAP's message_encoding cdr) are
// decoded: sensor_msgs/msg/LaserScan, PointCloud2, Imu, nav_msgs/msg/Odometry,
// tf2_msgs/msg/TFMessage, geometry_msgs/msg/PoseStamped and PoseWithCovarianceStamped (logs/cdr.hpp
// for the encoding); every other topic is listed and counted, not decoded. Topics are chosen and
// assembled as for ROS 1 bags (logs/bag_log.hpp). Messages are read in the order the recorder stored
// them (MCAP: file order; SQLite3: row order), as ROS 1 bags are read in file order.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/logs/carmen_log.hpp"
#include "starnav/logs/ros_bag.hpp"

namespace starnav {

// A folder holding metadata.yaml.
bool is_ros2_bag_folder(const std::string& path);
// An MCAP or SQLite3 file, by content.
bool is_ros2_bag_bytes(std::string_view bytes);

struct Ros2Topic {
  std::string name;
  std::string type;  // "sensor_msgs/msg/LaserScan"; a topic not in CDR: its type and "(encoding)"
  bool cdr = false;
  std::uint64_t messages = 0;
};

struct Ros2Message {
  const Ros2Topic* topic = nullptr;
  std::int64_t time_ns = 0;  // the recorder's time
  std::string_view data;     // the CDR bytes (decompressed when the bag compresses messages)
  std::string where;         // "file byte N" (MCAP: the record or its chunk), "row N" (SQLite3)
  const std::string* file = nullptr;
  std::size_t inflated = 0;  // what decompressing the message added (compression_mode MESSAGE)
};

// A recording: one file (its bytes) or a rosbag2 folder (its files read one at a time).
class Ros2Bag {
 public:
  explicit Ros2Bag(const std::string& path);
  // One file already in memory (`bytes` must outlive the bag); `path` names it in errors.
  Ros2Bag(std::string_view bytes, const std::string& path);
  ~Ros2Bag();
  Ros2Bag(const Ros2Bag&) = delete;
  Ros2Bag& operator=(const Ros2Bag&) = delete;

  const std::string& path() const { return path_; }
  const std::string& format() const { return format_; }  // "ros2_mcap" or "ros2_sqlite3"
  // Every topic of every file, by name (messages summed).
  const std::vector<Ros2Topic>& topics() const { return topics_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  // The recording's size: every file's bytes (decompressed when compressed whole) and what its
  // MCAP chunks decompress to; messages compressed one by one add theirs as they are read.
  std::uint64_t source_bytes() const { return source_bytes_; }
  // The messages of the wanted topics, file after file, in each file's order.
  void for_each_message(const std::function<bool(const Ros2Topic&)>& wanted, const std::function<void(const Ros2Message&)>& visit);

 private:
  struct File;
  void open_file(File& f);
  void add_topics(const File& f);
  void add_source_bytes(const File& f);

  std::string path_, format_;
  std::vector<std::unique_ptr<File>> files_;
  std::vector<Ros2Topic> topics_;
  std::vector<std::string> warnings_;
  bool compressed_messages_ = false;
  std::uint64_t source_bytes_ = 0;
};

RobotLog read_ros2_bag(const std::string& path, const LogReadOptions& options = {});
// One MCAP or SQLite3 file in memory (read_robot_log, fuzz targets).
RobotLog read_ros2_bag_bytes(std::string_view bytes, const std::string& path, const LogReadOptions& options = {});

// 3D LiDAR recordings: the index and the stream of clouds of ros_bag.hpp on a ROS 2 recording.
PointCloudBagIndex index_ros2_point_cloud_bag(const std::string& path, const PointCloudBagOptions& options = {});
void for_each_ros2_point_cloud(const std::string& path, const PointCloudBagIndex& index,
                               const std::function<void(BagPointCloud&&)>& visit);

// The CDR decoders (fuzz_cdr calls them on arbitrary bytes): `type` in either naming; throws Error
// naming `path`, `where` and the field. Returns false for a type that is not decoded.
bool decode_ros2_message(std::string_view type, std::string_view data, const std::string& path, const std::string& where);

}  // namespace starnav
