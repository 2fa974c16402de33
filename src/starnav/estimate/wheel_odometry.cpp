#include "starnav/estimate/wheel_odometry.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

WheelOdometry::WheelOdometry(const RobotModel& model, int ticks_per_rev, const Pose2& start, OdometryUpdate update)
    : model_(&model), rad_per_tick_(0.0), pose_(start), update_(update) {
  if (model.kind() == DriveKind::Ackermann)
    throw Error("wheel odometry needs a mecanum or differential drive (an Ackermann steering angle is not a wheel)",
                {}, 0, "robot.drive");
  if (ticks_per_rev < 1) throw Error("must be at least 1", {}, 0, "encoders.ticks_per_rev");
  rad_per_tick_ = 2.0 * kPi / ticks_per_rev;
  const auto n = static_cast<std::size_t>(model.actuator_count());
  last_.assign(n, 0.0);
  increments_.assign(n, 0.0);
}

void WheelOdometry::reset(const Pose2& pose) {
  pose_ = pose;
  started_ = false;
}

BodyTwist WheelOdometry::body_increment(std::span<const double> wheel_increment_rad) const {
  // The forward kinematics are linear: applied to angle increments they give the displacement.
  return model_->forward(wheel_increment_rad);
}

void WheelOdometry::add_ticks(std::span<const std::int64_t> ticks) {
  if (ticks.size() != last_.size())
    throw Error("expected " + std::to_string(last_.size()) + " encoder counts, got " + std::to_string(ticks.size()),
                {}, 0, "ticks");
  std::vector<double> angles(ticks.size());
  // Differences of cumulative counts are exact integers: convert each count, not the sum of
  // converted increments, so the quantisation error never accumulates.
  for (std::size_t i = 0; i < ticks.size(); ++i) angles[i] = static_cast<double>(ticks[i]) * rad_per_tick_;
  add_angles(angles);
}

void WheelOdometry::add_angles(std::span<const double> wheel_angle_rad) {
  if (wheel_angle_rad.size() != last_.size())
    throw Error("expected " + std::to_string(last_.size()) + " wheel angles, got " +
                    std::to_string(wheel_angle_rad.size()),
                {}, 0, "wheel_angle_rad");
  for (const double a : wheel_angle_rad)
    if (!std::isfinite(a)) throw Error("wheel angle is not finite", {}, 0, "wheel_angle_rad");
  if (!started_) {
    std::copy(wheel_angle_rad.begin(), wheel_angle_rad.end(), last_.begin());
    started_ = true;
    return;
  }
  for (std::size_t i = 0; i < last_.size(); ++i) {
    increments_[i] = wheel_angle_rad[i] - last_[i];
    last_[i] = wheel_angle_rad[i];
  }
  advance(increments_);
}

void WheelOdometry::advance(std::span<const double> increments) {
  const BodyTwist d = body_increment(increments);
  if (update_ == OdometryUpdate::Exact) {
    pose_ = advance_on_arc(pose_, d.vx, d.vy, d.wz, 1.0);
  } else {
    const double c = std::cos(pose_.yaw), s = std::sin(pose_.yaw);
    pose_ = {pose_.x + c * d.vx - s * d.vy, pose_.y + s * d.vx + c * d.vy, wrap_angle(pose_.yaw + d.wz)};
  }
}

}  // namespace starnav
