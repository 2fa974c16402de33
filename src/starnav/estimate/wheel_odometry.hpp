#pragma once
// Wheel odometry (docs/papers/ren2022.md, the paper's Eq. 1-8): encoder ticks -> wheel angle
// increments -> body increment through the robot's forward kinematics -> pose.
//
// Wheel i turns d_gamma_i = 2 pi d_e_i / xi in a sampling period (d_e_i ticks, xi ticks per
// revolution). The forward kinematics are linear in the wheel speeds, so applied to the angle
// increments they give the body increment (dx, dy, dtheta) over the period. Two pose updates:
//   Exact (default)  the increment taken as a constant twist over the period, integrated along its
//                    arc (advance_on_arc): exact whenever the twist was constant within the
//                    period, e.g. the simulator's steps.
//   Euler            the paper's Eq. 6 and 8: x += R(theta) (dx, dy), theta += dtheta (first order
//                    in dtheta: drifts on curves unless sampled fast).
// Mecanum and differential drives only: an Ackermann robot's steering angle is not a wheel.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/planar_motion.hpp"
#include "starnav/robot/robot_model.hpp"

namespace starnav {

enum class OdometryUpdate : std::uint8_t { Exact, Euler };

class WheelOdometry {
 public:
  // Throws Error (field "robot.drive") for an Ackermann model and (field "encoders.ticks_per_rev")
  // for ticks_per_rev < 1. `model` must outlive the odometry.
  WheelOdometry(const RobotModel& model, int ticks_per_rev, const Pose2& start = {},
                OdometryUpdate update = OdometryUpdate::Exact);

  // Cumulative encoder counts now (one per wheel, the model's wheel order). The first call sets
  // the zero and does not move the pose.
  void add_ticks(std::span<const std::int64_t> ticks);
  // Cumulative wheel angles now (rad): the same with unquantised encoders.
  void add_angles(std::span<const double> wheel_angle_rad);
  // The body increment (dx, dy in the body frame at the start of the period, dtheta) of wheel
  // angle increments; no state change.
  BodyTwist body_increment(std::span<const double> wheel_increment_rad) const;

  const Pose2& pose() const { return pose_; }
  void reset(const Pose2& pose);  // pose set, next sample is a new zero

 private:
  void advance(std::span<const double> increments);

  const RobotModel* model_;
  double rad_per_tick_;
  Pose2 pose_;
  OdometryUpdate update_;
  bool started_ = false;
  std::vector<double> last_;
  std::vector<double> increments_;
};

}  // namespace starnav
