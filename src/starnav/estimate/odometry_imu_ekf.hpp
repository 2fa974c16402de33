#pragma once
// EKF fusion of wheel odometry and a yaw gyro (docs/papers/ren2022.md, the paper's Eq. 9-14 with
// the gain's inverse restored).
//
// State: the paper's (x, y, theta) in the odom frame, or with `bias_state` five states
// (x, y, theta, psi, b): psi the IMU's yaw minus the robot's (it drifts as the gyro integrates its
// bias) and b the gyro bias. The simulator's IMU reports yaw integrated from biased, noisy rates,
// so z_yaw = theta + psi + v exactly models it; a (theta, b) state could not explain an
// integrated yaw.
//
// Prediction from the odometry increment between two odometry poses (dx, dy in the body frame at
// the start of the period, dtheta: the full body increment, so a Mecanum base's sideways motion
// is predicted too): x' = x (+) increment, F the Jacobian of the composition. Its noise: the wheel
// angle increments (inverse kinematics of the increment) each with standard deviation
// slip_sigma |d_gamma_i| (the simulator's slip model), through the forward kinematics to the body
// and rotated into the odom frame, plus the encoders' quantisation (each increment's count off by
// the difference of two uniform roundings: variance tick^2 / 6 per wheel). A standstill (no tick
// moved, once the wheels have settled: period_covariance) adds no noise, so the gyro alone then
// explains the yaw reading's drift: the bias is learnt whenever the robot stands still.
//
// IMU: psi' = psi + b dt with the integration noise (sigma_gyro dt)^2 per sample and a bias
// random walk; the update z = theta (+ psi) with K = P H^T (H P H^T + R)^-1, the innovation wrapped
// to (-pi, pi], the Joseph form for P, and a Mahalanobis gate (d^2 = nu^2 / S above gate_chi2 is
// an outlier, counted and skipped).
#include <array>
#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "starnav/core/geometry.hpp"
#include "starnav/robot/robot_model.hpp"

namespace starnav {

struct EkfConfig {
  bool bias_state = false;
  double wheel_slip_sigma = 0.05;         // per wheel, relative to its angle increment
  double tick_rad = 0.0;                  // encoder resolution (2 pi / ticks per revolution; 0: unquantised)
  double imu_yaw_sigma_rad = 0.0087;      // R of the yaw update (the 3-state filter's stand-in for the drift)
  double gyro_noise_sigma_radps = 0.002;  // white noise of each rate sample (integrated into psi)
  double gyro_bias_walk = 1e-6;           // rad/s per sqrt(s)
  double initial_sigma_xy_m = 0.0;
  double initial_sigma_yaw_rad = 0.0;
  double initial_bias_sigma_radps = 0.001;
  double initial_imu_offset_sigma_rad = 0.0;  // 0: the IMU's yaw reads the robot's yaw at the start
  double gate_chi2 = 16.0;                // 0 turns the gate off
  // Throws Error naming the field (prefix "ekf.").
  void validate() const;
};

class OdometryImuEkf {
 public:
  static constexpr int kMaxStates = 5;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStates, 1>;
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxStates, kMaxStates>;

  // `model` (kinematics for the slip noise) must outlive the filter; validates the configuration.
  OdometryImuEkf(const EkfConfig& config, const RobotModel& model, const Pose2& start);

  // The odometry moved by `increment` (body frame at the start of the period) with noise `q`
  // (covariance of (dx, dy, dtheta)).
  void predict(const Pose2& increment, const Eigen::Matrix3d& q);
  // The same with the slip noise of the configuration.
  void predict(const Pose2& increment) { predict(increment, slip_covariance(increment)); }
  // Covariance of an odometry increment under the slip model.
  Eigen::Matrix3d slip_covariance(const Pose2& increment) const;
  // Covariance of one odometry period's increment, for a caller that hands every period in turn:
  // the slip model's, except in the first kSettlePeriods still periods after motion. A wheel
  // that stops turns on by less than a tick after its last count, unseen (up to 1.1 mrad of
  // yaw for the paper's Mecanum base turning in place); those periods carry the rounding of
  // every wheel (tick^2 / 6 each) instead of nothing, so the IMU yaw's move in them goes to the
  // robot's yaw, not to the gyro's drift and bias.
  Eigen::Matrix3d period_covariance(const Pose2& increment);
  static constexpr int kSettlePeriods = 2;

  // An IMU reading: the gyro model advanced by dt (> 0; bias state only), then the yaw update.
  // Returns false when the gate rejected the reading.
  bool update_yaw(double yaw_rad, double dt);

  Pose2 pose() const { return {x_(0), x_(1), x_(2)}; }
  Eigen::Matrix3d pose_covariance() const { return P_.topLeftCorner<3, 3>(); }
  const Vector& state() const { return x_; }
  const Matrix& covariance() const { return P_; }
  double bias() const { return config_.bias_state ? x_(4) : 0.0; }
  std::int64_t rejected() const { return rejected_; }
  const EkfConfig& config() const { return config_; }
  // Shifts the state by `offset` (the start's error in a consistency experiment).
  void set_pose(const Pose2& pose) { x_(0) = pose.x, x_(1) = pose.y, x_(2) = pose.yaw; }

 private:
  // The covariance of wheel increments gamma (rad) through the kinematics: each wheel's slip and,
  // where its count moved or `settling`, its rounding.
  // Wheel angles (rad), the first model_->actuator_count() used.
  using WheelAngles = std::array<double, 8>;
  Eigen::Matrix3d wheel_covariance(const WheelAngles& gamma, bool settling) const;
  // The increment's wheel angles by the inverse kinematics.
  WheelAngles wheel_angles(const Pose2& increment) const;
  // Whether a wheel's count moved: by more than a quarter tick (kUnquantisedStill_rad unquantised).
  bool wheel_moved(double gamma_rad) const;
  static constexpr double kUnquantisedStill_rad = 1e-9;

  EkfConfig config_;
  const RobotModel* model_;
  int n_;
  Vector x_;
  Matrix P_;
  std::int64_t rejected_ = 0;
  int still_periods_ = kSettlePeriods;  // still odometry periods in a row (the start counts as settled)
};

}  // namespace starnav
