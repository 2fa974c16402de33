#pragma once
// Every kind of LiDAR recording 3D mapping reads, behind one description and one stream of clouds:
//
//  - a frames folder (lidar_frames.hpp: sensor.yaml, frames.csv and sensor-frame clouds), as
//    `starnav sim` writes it with outputs.lidar_frames; a simulator run folder holding lidar/ too;
//  - a folder of cloud files (PCD, PLY, KITTI .bin / .bin.gz, in name order), or a KITTI sequence
//    folder holding them in velodyne/, with an optional poses file of the sensor's reference
//    trajectory (below) and times from times.txt, else the poses file's, else the rate;
//  - a ROS 1 bag with sensor_msgs/PointCloud2 (logs/ros_bag.hpp): its odometry interpolated to
//    each cloud's stamp as the registration's guess, the sensor's mount from /tf_static, and the
//    base's true pose from a named Odometry topic when there is one (its motion, as a poses file's);
//  - a ROS 2 recording (logs/ros2_bag.hpp: MCAP, SQLite3, a rosbag2 folder), read the same way.
//
// Poses files (`--poses`, or poses.txt beside the clouds): one pose per line, either KITTI's 12
// numbers (the row-major 3 x 4 [R|t], optionally after a time column) or TUM's
// "t x y z qx qy qz qw". Cloud files named by numbers (000123.bin) take the pose of that row,
// others the row of their position. In a KITTI sequence folder (calib.txt beside poses.txt) the
// poses are the left camera's, turned into the LiDAR's with Tr (calib.txt's Tr line, else KITTI's
// calibration of a sequence folder named 00-10); elsewhere they are the sensor's. The truth given
// to the mapper is the base's: the sensor poses relative to the first, with the mount above the
// origin (a reference trajectory's frame is its own; only its motion is compared).
//
// The mount (the sensor in base_link) comes from sensor.yaml or /tf_static, or from the options;
// without any it is the identity, which puts the floor at the sensor's height: give the mount
// (its height above the floor) for the floor constraint to find the floor.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "starnav/cloud/lidar_frames.hpp"
#include "starnav/cloud/point_cloud.hpp"
#include "starnav/logs/ros_bag.hpp"

namespace starnav {

struct LidarRecordingOptions {
  std::string poses;            // a poses file for a folder of clouds (default: poses.txt beside them)
  std::optional<Pose3> mount;   // the sensor in base_link; overrides sensor.yaml and /tf_static
  double rate_hz = 10.0;        // a folder of clouds without times
  PointCloudBagOptions bag;
  void validate() const;
};

struct LidarRecording {
  std::string path;
  std::string kind;          // "frames folder", "cloud files", "ROS 1 bag" or "ROS 2 bag"
  LidarFrameFolder frames;   // mount, rate, per frame: time, odometry, truth (cloud: its file or message)
  // Visits the first `count` clouds (0: all) in order, sensor frame; reading errors name the file.
  std::function<void(std::size_t count, const std::function<void(std::size_t, PointCloud&&)>&)> for_each_cloud;
};

// By what `input` is: a folder with frames.csv (or lidar/frames.csv), a bag (by content), else a
// folder of cloud files (or its velodyne/). Errors name the file and field.
LidarRecording open_lidar_recording(const std::string& input, const LidarRecordingOptions& options = {});

// A poses file as above: per line the pose and, for TUM and timed KITTI lines, the time.
struct PoseFileEntry {
  std::optional<double> t_s;
  Rigid3 pose = Rigid3::Identity();
};
std::vector<PoseFileEntry> read_pose_file(const std::string& path);

}  // namespace starnav
