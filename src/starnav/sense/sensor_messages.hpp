#pragma once
// The messages a robot's sensors publish, each in its own frame (REP-103/105), as its drivers give
// them and as a recording holds them: a planar scan, a point cloud, an IMU sample, encoder ticks,
// wheel odometry, a bumper contact. A simulation and a recorded log are two sources of the same
// messages; the roles that consume them (localizer, SLAM, costmap layers) cannot tell which.
// Truth (the simulator's pose of the robot) never travels in a message: recorders read it from the
// simulation itself.
//
// Every message names its stream ("lidar", "lidar/rear", "imu", "odom", ...): a robot may carry
// several sensors of a kind, and a consumer subscribes to the streams it wants.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "starnav/core/geometry.hpp"

namespace starnav {

struct SensorHeader {
  double t_s = 0.0;    // when the reading was taken (a log's stamp in seconds; the simulation's clock)
  std::string stream;  // "lidar", "lidar/rear", "imu", "encoders", "odom", "bumper", ...
};

// A planar range scan (sensor_msgs/LaserScan): beam i at angle(i) in the sensor frame.
struct ScanMessage {
  SensorHeader header;
  Pose3 mount;  // the sensor in base_link
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  std::vector<double> angles_rad;  // when not empty, beam i's angle (irregular scans); overrides min + i * increment
  double range_min_m = 0.0;
  double range_max_m = 0.0;  // a reading at or beyond it, or not finite, returned nothing
  std::vector<double> ranges_m;

  double angle(std::size_t i) const {
    return angles_rad.empty() ? angle_min_rad + static_cast<double>(i) * angle_increment_rad : angles_rad[i];
  }
  bool returned(std::size_t i) const {
    const double r = ranges_m[i];
    return std::isfinite(r) && r >= range_min_m && r < range_max_m;
  }
};

// A 3D point cloud in the sensor frame (sensor_msgs/PointCloud2 reduced to x, y, z).
struct CloudMessage {
  SensorHeader header;
  Pose3 mount;                  // the sensor in base_link
  std::vector<Vec3> points;     // sensor frame
  std::vector<float> times_s;   // per point, relative to header.t_s, when the driver gives them (de-skewing)
};

// An inertial sample (sensor_msgs/Imu): rates and accelerations in the sensor frame.
struct ImuMessage {
  SensorHeader header;
  Pose3 mount;
  Vec3 angular_velocity_radps = Vec3::Zero();
  Vec3 linear_acceleration_mps2 = Vec3::Zero();
  std::optional<double> yaw_rad;  // an integrated heading, when the unit gives one (a gyro's own)
};

// Cumulative wheel encoder counts, one per wheel in the drive's wheel order.
struct EncoderMessage {
  SensorHeader header;
  std::vector<std::int64_t> ticks;
  int ticks_per_rev = 0;
};

// Odometry (nav_msgs/Odometry): the base's pose in the odom frame and its body twist.
struct OdometryMessage {
  SensorHeader header;
  Pose2 pose;
  BodyTwist twist;
};

// A bumper's state.
struct BumperMessage {
  SensorHeader header;
  bool contact = false;
};

}  // namespace starnav
