#include "starnav/estimate/odometry_imu_ekf.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/params.hpp"

namespace starnav {

void EkfConfig::validate() const {
  const auto check = [](double v, double hi, const char* field) {
    if (!std::isfinite(v) || v < 0.0 || v > hi)
      throw Error("must lie in [0, " + format_param_real(hi) + "]", {}, 0, std::string("ekf.") + field);
  };
  check(wheel_slip_sigma, 1.0, "wheel_slip_sigma");
  check(tick_rad, kPi, "ticks_per_rev");
  check(imu_yaw_sigma_rad, kPi, "imu_yaw_sigma_deg");
  check(gyro_noise_sigma_radps, 1.0, "gyro_noise_sigma_radps");
  check(gyro_bias_walk, 1.0, "gyro_bias_walk");
  check(initial_sigma_xy_m, 100.0, "initial_sigma_xy_m");
  check(initial_sigma_yaw_rad, kPi, "initial_sigma_yaw_deg");
  check(initial_bias_sigma_radps, 1.0, "initial_bias_sigma_radps");
  check(initial_imu_offset_sigma_rad, kPi, "initial_imu_offset_sigma_deg");
  check(gate_chi2, 1e6, "gate_chi2");
  if (imu_yaw_sigma_rad <= 0.0 && !bias_state && gyro_noise_sigma_radps <= 0.0)
    throw Error("must be > 0 (the yaw update needs a noise)", {}, 0, "ekf.imu_yaw_sigma_deg");
}

OdometryImuEkf::OdometryImuEkf(const EkfConfig& config, const RobotModel& model, const Pose2& start)
    : config_(config), model_(&model), n_(config.bias_state ? 5 : 3) {
  config_.validate();
  x_ = Vector::Zero(n_);
  x_(0) = start.x, x_(1) = start.y, x_(2) = wrap_angle(start.yaw);
  P_ = Matrix::Zero(n_, n_);
  P_(0, 0) = P_(1, 1) = config_.initial_sigma_xy_m * config_.initial_sigma_xy_m;
  P_(2, 2) = config_.initial_sigma_yaw_rad * config_.initial_sigma_yaw_rad;
  if (config_.bias_state) {
    P_(3, 3) = config_.initial_imu_offset_sigma_rad * config_.initial_imu_offset_sigma_rad;
    P_(4, 4) = config_.initial_bias_sigma_radps * config_.initial_bias_sigma_radps;
  }
}

Eigen::Matrix3d OdometryImuEkf::wheel_covariance(const WheelAngles& gamma, bool settling) const {
  // The kinematics are linear: each wheel's error back to the body by the forward kinematics of
  // a unit increment of that wheel.
  const int wheels = model_->actuator_count();
  WheelAngles unit{};
  Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
  for (int i = 0; i < wheels; ++i) {
    unit.fill(0.0);
    unit[i] = 1.0;
    const BodyTwist j = model_->forward(std::span<const double>(unit.data(), wheels));
    const Eigen::Vector3d column(j.vx, j.vy, j.wz);
    const double sigma = config_.wheel_slip_sigma * gamma[static_cast<std::size_t>(i)];
    // A wheel whose count did not change has no rounding error in its increment (at rest: none),
    // unless it is settling.
    const bool rounded = settling || wheel_moved(gamma[static_cast<std::size_t>(i)]);
    const double rounding = rounded ? config_.tick_rad * config_.tick_rad / 6.0 : 0.0;
    q += (sigma * sigma + rounding) * column * column.transpose();
  }
  return q;
}

bool OdometryImuEkf::wheel_moved(double gamma_rad) const {
  // Counts move by whole ticks, and the body increment's wheel angles are their projection on
  // what the kinematics can express: at least half a tick on some wheel when the body moved (a
  // Mecanum base's tick on two opposite wheels). A quarter tick is far above the rounding of
  // composing two equal odometry poses (1e-16 m) and far below any motion.
  const double threshold = config_.tick_rad > 0.0 ? 0.25 * config_.tick_rad : kUnquantisedStill_rad;
  return std::abs(gamma_rad) > threshold;
}

OdometryImuEkf::WheelAngles OdometryImuEkf::wheel_angles(const Pose2& increment) const {
  WheelAngles gamma{};
  const auto wheels = static_cast<std::size_t>(model_->actuator_count());
  model_->inverse({increment.x, increment.y, increment.yaw}, std::span<double>(gamma.data(), wheels));
  return gamma;
}

Eigen::Matrix3d OdometryImuEkf::slip_covariance(const Pose2& increment) const {
  return wheel_covariance(wheel_angles(increment), false);
}

Eigen::Matrix3d OdometryImuEkf::period_covariance(const Pose2& increment) {
  // Still when no wheel's count moved. An exact-zero test fails at rest away from the origin: the
  // increment between two equal poses is 1e-16 m there, and such a period took the rounding
  // noise of a moving wheel, so the rests at the square's corners taught the bias nothing.
  const WheelAngles gamma = wheel_angles(increment);
  const bool still = std::none_of(gamma.begin(), gamma.begin() + model_->actuator_count(),
                                  [this](double g) { return wheel_moved(g); });
  still_periods_ = still ? std::min(still_periods_ + 1, kSettlePeriods + 1) : 0;
  if (!still) return wheel_covariance(gamma, false);
  if (still_periods_ > kSettlePeriods) return Eigen::Matrix3d::Zero();
  return wheel_covariance(WheelAngles{}, true);
}

void OdometryImuEkf::predict(const Pose2& increment, const Eigen::Matrix3d& q) {
  const double c = std::cos(x_(2)), s = std::sin(x_(2));
  Matrix f = Matrix::Identity(n_, n_);
  f(0, 2) = -s * increment.x - c * increment.y;
  f(1, 2) = c * increment.x - s * increment.y;
  Eigen::Matrix3d g = Eigen::Matrix3d::Identity();
  g.topLeftCorner<2, 2>() << c, -s, s, c;
  x_(0) += c * increment.x - s * increment.y;
  x_(1) += s * increment.x + c * increment.y;
  x_(2) = wrap_angle(x_(2) + increment.yaw);
  P_ = f * P_ * f.transpose();
  P_.topLeftCorner<3, 3>() += g * q * g.transpose();
}

bool OdometryImuEkf::update_yaw(double yaw_rad, double dt) {
  if (config_.bias_state && dt > 0.0) {
    // psi' = psi + b dt: each rate sample's noise integrates into psi, the bias walks.
    x_(3) += x_(4) * dt;
    Matrix f = Matrix::Identity(n_, n_);
    f(3, 4) = dt;
    P_ = f * P_ * f.transpose();
    const double integration = config_.gyro_noise_sigma_radps * dt;
    P_(3, 3) += integration * integration;
    P_(4, 4) += config_.gyro_bias_walk * config_.gyro_bias_walk * dt;
  }
  Vector h = Vector::Zero(n_);
  h(2) = 1.0;
  if (config_.bias_state) h(3) = 1.0;
  const double predicted = x_(2) + (config_.bias_state ? x_(3) : 0.0);
  const double nu = wrap_angle(yaw_rad - predicted);
  const double r = config_.imu_yaw_sigma_rad * config_.imu_yaw_sigma_rad;
  const Vector ph = P_ * h;
  const double s = h.dot(ph) + r;
  if (!(s > 0.0)) return false;  // nothing uncertain and a noiseless reading: nothing to learn
  if (config_.gate_chi2 > 0.0 && nu * nu / s > config_.gate_chi2) {
    ++rejected_;
    return false;
  }
  const Vector k = ph / s;
  x_ += k * nu;
  x_(2) = wrap_angle(x_(2));
  // Joseph form: stays symmetric and positive semi-definite with a tiny R.
  const Matrix a = Matrix::Identity(n_, n_) - k * h.transpose();
  P_ = a * P_ * a.transpose() + r * k * k.transpose();
  return true;
}

}  // namespace starnav
