#pragma once
// A folder of LiDAR frames as a robot records them for 3D mapping (what `starnav sim` writes with
// outputs.lidar_frames, and what `starnav slam3d` reads):
//
//   sensor.yaml   the LiDAR: model, lines, beams, rate_hz, range_min_m, range_max_m, and its mount
//                 in base_link {x_m, y_m, z_m, roll_deg, pitch_deg, yaw_deg}
//   frames.csv    one row per frame:
//                 frame,t_s,cloud,odom_x_m,odom_y_m,odom_yaw_rad,imu_yaw_rate_radps,
//                 true_x_m,true_y_m,true_z_m,true_roll_rad,true_pitch_rad,true_yaw_rad
//                 (cloud: the file name beside frames.csv; odom: the wheel odometry's base_link pose;
//                 imu: the latest gyro reading; true: base_link's true pose; empty cells when the
//                 robot has no such sensor or the truth is unknown)
//   NNNNNN.pcd    the frame's points in the SENSOR frame (binary PCD), as the sensor saw them
//
// Clouds in the world frame are not SLAM input (registering them would return the identity), so
// the folder always holds sensor-frame clouds.
#include <optional>
#include <string>
#include <vector>

#include "starnav/cloud/point_cloud.hpp"

namespace starnav {

struct LidarFrameRecord {
  int frame = 0;
  double t_s = 0.0;
  std::string cloud;  // file name, relative to the folder
  std::optional<Pose2> odometry;
  std::optional<double> imu_yaw_rate_radps;
  std::optional<Pose3> truth;  // base_link
};

struct LidarFrameFolder {
  std::string dir;
  std::string model;
  int lines = 0, beams = 0;
  double rate_hz = 10.0, range_min_m = 0.0, range_max_m = 0.0;
  Pose3 mount;  // the sensor in base_link
  std::vector<LidarFrameRecord> frames;
  std::string cloud_path(const LidarFrameRecord& f) const;
};

std::string lidar_frames_header();
std::string lidar_frame_row(const LidarFrameRecord& record);
std::string lidar_sensor_yaml(const std::string& model, int lines, int beams, double rate_hz, double range_min_m,
                              double range_max_m, const Pose3& mount);

// Reads sensor.yaml and frames.csv (not the clouds). Errors name the file, line and column.
LidarFrameFolder read_lidar_frame_folder(const std::string& dir);

}  // namespace starnav
