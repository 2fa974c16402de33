#pragma once
// The localizer role: the robot's pose in the map frame from what a real robot gives it, odometry
// (a pose in the odom frame from wheel encoders, or a fused one), the IMU, LiDAR scans and, in
// simulation only, ground truth. The navigation loop reads its pose from a localizer, always.
// It reports a planar pose (x, y, yaw) with its 3 x 3 covariance; z, roll and pitch keep coming
// from the vehicle's attitude on the terrain. Implementations: ground_truth (this module, with
// optional Gaussian noise), ekf (odometry + IMU) and amcl (particle filter on a known map). Built by name from the
// component registry with their declared parameters.
#include <cstdint>
#include <span>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/robot/robot_model.hpp"
#include "starnav/sense/sensor_messages.hpp"

namespace starnav {

struct PoseEstimate {
  double t_s = 0.0;
  Pose2 pose;                                              // map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();   // of (x, y, yaw)
  bool valid = false;                                      // false until the first input
  int particles = 0;        // particle filters: the particles now
  int updates = 0;          // particle filters: filter updates so far
  bool converged = true;    // particle filters: the best cluster is tight and holds most weight
};

class Localizer {
 public:
  virtual ~Localizer() = default;
  virtual std::string_view name() const = 0;
  // The odom -> base pose and the body twist (a wheel odometry's, or a filter's fused one).
  virtual void on_odometry(const OdometryMessage& /*odometry*/) {}
  // An inertial sample in its sensor frame; its yaw_rad, when the unit integrates one.
  virtual void on_imu(const ImuMessage& /*imu*/) {}
  // A planar scan in its sensor frame, with its mount (from a simulated LiDAR or a recording alike).
  virtual void on_scan(const ScanMessage& /*scan*/) {}
  // The simulator's truth; a real robot never calls it (a motion-capture system would).
  virtual void on_ground_truth(double /*t_s*/, const Pose2& /*pose*/) {}
  virtual PoseEstimate estimate() const = 0;
  // At most `max` poses drawn evenly from the belief, for viewers (a particle filter's particles);
  // empty for a localizer whose belief is not a sample set.
  virtual std::vector<Pose2> belief_samples(std::size_t /*max*/) const { return {}; }
};

// What a localizer is built from: the start pose, the scenario's seed, the scenario file, and
// what the robot knows of itself and its world (each may be absent: a localizer that needs one
// says so when it is built).
struct LocalizerContext {
  LocalizerContext() = default;
  LocalizerContext(const Pose2& start_, std::uint64_t seed_, std::string file_)
      : start(start_), seed(seed_), file(std::move(file_)) {}
  Pose2 start;
  std::uint64_t seed = 0;
  std::string file;
  const RobotConfig* robot = nullptr;   // kinematics (odometry noise, motion model)
  const OccupancyGrid* map = nullptr;   // the known map (map-based localizers)
  OccupancyThresholds thresholds;       // the map's free / occupied thresholds
  Pose2 laser_in_base;                  // the 2D LiDAR's mount
  double laser_range_min_m = 0.0;       // its valid ranges (0, 0: no LiDAR)
  double laser_range_max_m = 0.0;
  int laser_lines = 1;                  // its lines (a localizer that needs a planar scan refuses more)
};
using LocalizerDef = ComponentDef<Localizer, LocalizerContext>;

}  // namespace starnav
