#pragma once
// The localizer role: the robot's pose in the map frame from what a real robot gives it, odometry
// (a pose in the odom frame from wheel encoders, or a fused one), the IMU, LiDAR scans and, in
// simulation only, ground truth. The navigation loop reads its pose from a localizer, always.
// It reports a planar pose (x, y, yaw) with its 3 x 3 covariance; z, roll and pitch keep coming
// from the vehicle's attitude on the terrain. Implementations: ground_truth (this module, with
// optional Gaussian noise); the EKF and AMCL come with their issue. Built by name from the
// component registry with their declared parameters.
#include <cstdint>
#include <span>
#include <string>

#include <Eigen/Core>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/robot/robot_model.hpp"
#include "starnav/sense/imu.hpp"
#include "starnav/sense/lidar.hpp"

namespace starnav {

struct PoseEstimate {
  double t_s = 0.0;
  Pose2 pose;                                              // map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();   // of (x, y, yaw)
  bool valid = false;                                      // false until the first input
};

// Odometry as a robot publishes it: the pose in the odom frame and the body twist.
struct OdometrySample {
  double t_s = 0.0;
  Pose2 pose;
  BodyTwist twist;
};

class Localizer {
 public:
  virtual ~Localizer() = default;
  virtual std::string_view name() const = 0;
  virtual void on_odometry(const OdometrySample& /*odometry*/) {}
  virtual void on_imu(const ImuModel::ImuReading& /*reading*/) {}
  virtual void on_scan(const LidarScan& /*scan*/) {}
  // The simulator's truth; a real robot never calls it (a motion-capture system would).
  virtual void on_ground_truth(double /*t_s*/, const Pose2& /*pose*/) {}
  virtual PoseEstimate estimate() const = 0;
};

// What a localizer is built from: the start pose, the scenario's seed, the scenario file.
struct LocalizerContext {
  Pose2 start;
  std::uint64_t seed = 0;
  std::string file;
};
using LocalizerDef = ComponentDef<Localizer, LocalizerContext>;

}  // namespace starnav
