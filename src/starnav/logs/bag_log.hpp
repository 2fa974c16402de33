#pragma once
// What the messages of a bag become in a RobotLog, whatever the bag's format and serialisation
// (ROS 1 bags, ROS 2 MCAP and SQLite3): the choice of topics, the odometry from nav_msgs/Odometry
// or from /tf, the ground truth, the IMU, and the laser's mount composed from /tf_static.
//
// Topics (LogReadOptions):
//  - scans: the sensor_msgs/LaserScan topic, the only one or the named one (--scan-topic);
//  - odometry: the nav_msgs/Odometry topic, the only one or the named one (--odom-topic); without
//    any, the transforms from the odometry frame `odom` to the base (base_link, else
//    base_footprint, else the only child of odom) on /tf (REP-105), as a robot's driver
//    publishes them; --odom-topic naming a tf2_msgs/TFMessage topic takes them from there;
//  - the IMU: the sensor_msgs/Imu topic, the only one or the named one (--imu-topic); with
//    several and none named none is read (a warning says so);
//  - the ground truth: only when named (--truth-topic): nav_msgs/Odometry,
//    geometry_msgs/PoseStamped or PoseWithCovarianceStamped (a simulator's or a motion-capture
//    system's base pose);
//  - the laser's mount: the chain of /tf_static transforms from the base (the odometry's child
//    frame, base_link without odometry) to the scans' frame.
// Types are compared without ROS 2's "/msg/" ("sensor_msgs/msg/LaserScan" is a LaserScan).
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/logs/carmen_log.hpp"
#include "starnav/logs/ros_bag.hpp"

namespace starnav {

// "sensor_msgs/msg/LaserScan" -> "sensor_msgs/LaserScan"; ROS 1 names are returned as they are.
std::string ros1_type_name(std::string_view type);
// A frame name without its leading slashes (ROS 1 wrote "/base_link").
std::string frame_name(std::string_view frame);
// The yaw of a quaternion; the whole pose (a zero or non-finite quaternion counts as the identity:
// some drivers leave it unset).
double yaw_of_quaternion(double x, double y, double z, double w);
Pose3 pose3_of(double x, double y, double z, double qx, double qy, double qz, double qw);

struct BagTopic {
  std::string name;
  std::string type;  // as the bag names it
};

// One geometry_msgs/TransformStamped: `child` in `parent`.
struct FrameTransform {
  std::int64_t stamp_us = 0;
  std::string parent, child;  // frame_name()s
  Pose2 pose;                 // the planar part
  Pose3 pose3;
};

// The pose of frame `to` in frame `from` through `transforms` (either direction), if linked.
std::optional<Pose2> planar_transform_chain(const std::vector<FrameTransform>& transforms, const std::string& from,
                                            const std::string& to);
std::optional<Pose3> transform_chain(const std::vector<FrameTransform>& transforms, const std::string& from,
                                     const std::string& to);

// The topic named `wanted` (of `type`), or the only one of `type` when none is named ("" when the
// bag has none); Error(path, flag) when the named one is missing or several are left to choose from.
std::string choose_bag_topic(const std::vector<BagTopic>& topics, const std::string& type, const std::string& wanted,
                             const std::string& path, const char* flag);

// The topics of a bag of clouds (ros_bag.hpp's PointCloudBagOptions): the PointCloud2 topic, the
// odometry's and the truth's (only when named; the odometry is then the other Odometry topic).
void choose_point_cloud_topics(const std::vector<BagTopic>& topics, const PointCloudBagOptions& options,
                               const std::string& path, PointCloudBagIndex& index);

// A decoded sensor_msgs/LaserScan's fields checked as every reader checks them (robot_log.hpp's
// scan_fault; the count before the ranges are read: check_scan_beams). Returns the reason a scan is
// refused ("" when fine) and its field.
struct ScanCheck {
  std::string field, what;
  explicit operator bool() const { return what.empty(); }
};
ScanCheck check_scan_beams(std::uint64_t beams);
ScanCheck check_scan_fields(const LogScan& scan);

// sensor_msgs/PointCloud2's layout, as both serialisations decode it: the x, y and z fields
// (FLOAT32 or FLOAT64, either byte order) and the steps.
struct CloudLayout {
  struct Field {
    std::uint32_t offset = 0;
    std::uint8_t datatype = 0;
    bool found = false;
  };
  std::uint64_t height = 0, width = 0, point_step = 0, row_step = 0;
  bool big_endian = false;
  Field xyz[3];
};
// Records a PointField; only x, y and z matter (the first of each name).
ScanCheck add_cloud_field(CloudLayout& layout, std::string_view name, std::uint32_t offset, std::uint8_t datatype);
// Checks that x, y and z were found and that height x width points of point_step bytes fit `data_bytes`.
ScanCheck check_cloud_layout(const CloudLayout& layout, std::size_t data_bytes);
// Appends the points whose three coordinates are finite; counts the others in `dropped`.
void cloud_points(const CloudLayout& layout, std::string_view data, std::vector<Vec3>& points, std::size_t& dropped);

enum class BagTopicUse { Skip, Scan, Odometry, OdometryTf, Truth, Imu, TfStatic };

// Assembles a RobotLog from a bag's messages in file order: ask use() for each message's topic,
// decode it accordingly and hand it over; finish() composes the mount and the tf odometry.
class BagLogAssembler {
 public:
  BagLogAssembler(const std::vector<BagTopic>& topics, const LogReadOptions& options, std::string path,
                  std::string format);

  BagTopicUse use(const std::string& topic) const;
  const std::string& type_of(const std::string& topic) const;

  // Counts the messages of `topic` (every topic's, decoded or not), before begin().
  void count(const std::string& topic, std::size_t messages);
  // Before the first message: `source_bytes` is the bag's size with its compressed parts counted
  // decompressed. A log for scans (not allow_no_scans) whose scan topic has no message is refused
  // here, and so is one whose counted messages' records would pass the bound (LogRecordBudget);
  // each record is charged against it as it is added.
  void begin(std::uint64_t source_bytes);
  // Data decompressed while reading (messages compressed one by one) that source_bytes left out.
  void add_source_bytes(std::uint64_t bytes);
  void add_scan(LogScan scan, std::string_view frame_id);
  void add_odometry(LogOdometry odometry, std::string_view child_frame_id);
  // The transforms of one tf2_msgs/TFMessage of /tf_static or of the odometry's tf topic.
  void add_transforms(const std::vector<FrameTransform>& transforms, BagTopicUse use, std::size_t source_index);
  void add_truth(std::int64_t stamp_us, const Pose2& pose);
  void add_imu(LogImu imu);
  void warn(std::string warning) { log_.warnings.push_back(std::move(warning)); }

  RobotLog finish();

 private:
  // Charges `bytes` of records (begin() first).
  void charge(std::uint64_t bytes);
  std::string stored() const;

  LogReadOptions options_;
  std::optional<LogRecordBudget> budget_;
  std::size_t tf_odometry_count_ = 0;
  RobotLog log_;
  std::map<std::string, std::string> types_;
  std::map<std::string, BagTopicUse> uses_;
  std::map<std::string, std::size_t> counts_;
  std::string laser_frame_, base_frame_;
  std::vector<FrameTransform> statics_;
  std::set<std::pair<std::string, std::string>> static_pairs_;  // (parent, child) of statics_
  // odom -> child transforms of the tf odometry topic, per child frame.
  std::map<std::string, std::vector<LogOdometry>> tf_odometry_;
};

// One message of a bag handed to the assembler as its topic is used, decoded by `Decode` (the
// serialisation's decoders on a reader `r`: scan, odometry, pose_stamped, imu, tf), so that ROS 1
// and ROS 2 recordings share the dispatch. `topic_type` is the topic's type as the bag writes it.
template <class Decode, class Reader>
void assemble_bag_message(BagLogAssembler& log, BagTopicUse use, std::string_view topic_type, Reader& r, std::size_t index,
                          std::vector<FrameTransform>& transforms) {
  switch (use) {
    case BagTopicUse::Scan: {
      auto d = Decode::scan(r);
      d.scan.source_index = index;
      log.add_scan(std::move(d.scan), d.frame_id);
      break;
    }
    case BagTopicUse::Odometry: {
      auto d = Decode::odometry(r);
      d.odometry.source_index = index;
      log.add_odometry(d.odometry, d.child_frame_id);
      break;
    }
    case BagTopicUse::Truth: {
      const std::string type = ros1_type_name(topic_type);
      if (type == "nav_msgs/Odometry") {
        const auto d = Decode::odometry(r);
        log.add_truth(d.odometry.stamp_us, d.odometry.pose);
      } else {
        const auto [stamp, pose] = Decode::pose_stamped(r, type == "geometry_msgs/PoseWithCovarianceStamped");
        log.add_truth(stamp, pose);
      }
      break;
    }
    case BagTopicUse::Imu: {
      LogImu imu = Decode::imu(r);
      imu.source_index = index;
      log.add_imu(imu);
      break;
    }
    case BagTopicUse::OdometryTf:
    case BagTopicUse::TfStatic:
      transforms.clear();
      Decode::tf(r, transforms);
      log.add_transforms(transforms, use, index);
      break;
    case BagTopicUse::Skip: break;
  }
}

}  // namespace starnav
