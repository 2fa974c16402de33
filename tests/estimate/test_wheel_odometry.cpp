// Wheel odometry (spec ren2022 section 1) against the simulator's ground truth: with exact wheel
// angles it reproduces the true trajectory to rounding; with quantised encoders it stays within
// the bound the tick size implies.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/estimate/wheel_odometry.hpp"
#include "starnav/sense/wheel_encoders.hpp"
#include "starnav/sim/vehicle.hpp"
#include "starnav/sim/world.hpp"

namespace starnav {
namespace {

// A command that changes every few tenths of a second: every drive and turn direction.
BodyTwist command_at(int step, bool holonomic) {
  const double t = step * 0.01;
  BodyTwist c;
  c.vx = 0.25 * std::sin(0.7 * t) + 0.05;
  c.vy = holonomic ? 0.2 * std::cos(0.45 * t) : 0.0;
  c.wz = 0.6 * std::sin(0.3 * t + 1.0);
  return c;
}

struct DriveRun {
  double max_position_error = 0.0;
  double max_yaw_error = 0.0;
  double distance = 0.0;
  double turned = 0.0;
};

// Drives the vehicle on the flat floor for `steps` steps of 0.01 s and runs the odometry beside it.
DriveRun drive(DriveKind drive_kind, double lag, bool quantised, int ticks_per_rev, int steps) {
  const World world;  // no terrain: the floor z = 0
  VehicleConfig c;
  c.robot.drive = drive_kind;
  c.robot.actuator_lag_s = lag;
  const Pose2 start(1.0, -2.0, 0.4);
  Vehicle v(world, c, start, Rng(3));
  WheelOdometry odo(v.model(), ticks_per_rev, start);
  EncoderConfig ec;
  ec.ticks_per_rev = ticks_per_rev;
  WheelEncoders enc(v.model().actuator_count(), ec, Rng(4));
  auto feed = [&] {
    if (quantised) {
      const std::vector<std::int64_t> ticks = enc.sample(v.state().wheel_angle_rad);
      odo.add_ticks(ticks);
    } else {
      odo.add_angles(v.state().wheel_angle_rad);
    }
  };
  feed();
  DriveRun r;
  std::vector<VehicleEvent> events;
  Pose2 last = v.state().pose.to_pose2();
  for (int k = 0; k < steps; ++k) {
    v.step(command_at(k, drive_kind == DriveKind::Mecanum), 0.01, events);
    feed();
    const Pose2 truth = v.state().pose.to_pose2();
    r.distance += std::hypot(truth.x - last.x, truth.y - last.y);
    r.turned += std::abs(angle_diff(truth.yaw, last.yaw));
    last = truth;
    r.max_position_error = std::max(r.max_position_error, std::hypot(odo.pose().x - truth.x, odo.pose().y - truth.y));
    r.max_yaw_error = std::max(r.max_yaw_error, std::abs(angle_diff(odo.pose().yaw, truth.yaw)));
  }
  EXPECT_TRUE(events.empty());
  return r;
}

TEST(WheelOdometry, ExactWheelAnglesReproduceTheTrueTrajectory) {
  for (const DriveKind kind : {DriveKind::Mecanum, DriveKind::Differential})
    for (const double lag : {0.0, 0.1}) {
      const DriveRun r = drive(kind, lag, false, 1024, 3000);
      SCOPED_TRACE(std::string(drive_kind_name(kind)) + " lag " + std::to_string(lag));
      EXPECT_GT(r.distance, 3.0);  // the run really goes somewhere and turns
      EXPECT_GT(r.turned, 2.0);
      EXPECT_LT(r.max_position_error, 1e-9);
      EXPECT_LT(r.max_yaw_error, 1e-9);
    }
}

TEST(WheelOdometry, QuantisedTicksStayWithinTheTickResolution) {
  const RobotConfig rc;
  for (const int xi : {256, 1024, 4096}) {
    const DriveRun r = drive(DriveKind::Mecanum, 0.1, true, xi, 3000);
    const double tick = 2.0 * kPi / xi;
    // Cumulative counts: every wheel angle is within one tick of the truth at every sample, so
    // the heading (linear in the wheel angles) is within r * tick / (L1 + L2), and the position
    // error is at most that heading error over the distance plus the wheel-angle error carried
    // through the turns (summation by parts), sqrt(2) r tick per radian turned and twice at the ends.
    const double yaw_bound = rc.wheel_radius_m * tick / (rc.half_track_m + rc.half_wheelbase_m);
    const double position_bound = yaw_bound * r.distance + std::sqrt(2.0) * rc.wheel_radius_m * tick * (2.0 + r.turned);
    SCOPED_TRACE("ticks per rev " + std::to_string(xi));
    EXPECT_LE(r.max_yaw_error, yaw_bound * (1.0 + 1e-9));
    EXPECT_LE(r.max_position_error, position_bound);
    EXPECT_GT(r.max_position_error, 1e-7);  // the quantisation is really there
  }
}

// A differential robot driving straight whose left wheel counts (1 + eL) and right wheel (1 + eR)
// times its travel: the odometry turns at v (eR - eL) / (2 L1) and advances at v (1 + (eL + eR) / 2),
// the closed form of a systematic odometry error (a wrong tyre radius), the true robot straight.
TEST(WheelOdometry, ScaleErrorOfTheEncodersBendsAStraightDriveByTheClosedForm) {
  const World world;
  VehicleConfig c;
  c.robot.drive = DriveKind::Differential;
  c.robot.actuator_lag_s = 0.0;
  const Pose2 start(0.0, 0.0, 0.0);
  Vehicle v(world, c, start, Rng(3));
  WheelOdometry odo(v.model(), 1 << 20, start);
  EncoderConfig ec;
  ec.ticks_per_rev = 1 << 20;
  const double e_left = -0.01, e_right = 0.015;
  ec.scale_error = {e_left, e_right};
  WheelEncoders enc(2, ec, Rng(4));
  odo.add_ticks(enc.sample(v.state().wheel_angle_rad));
  std::vector<VehicleEvent> events;
  BodyTwist cmd;
  cmd.vx = 0.3;
  for (int k = 0; k < 2000; ++k) {
    v.step(cmd, 0.01, events);
    odo.add_ticks(enc.sample(v.state().wheel_angle_rad));
  }
  const Pose2 truth = v.state().pose.to_pose2();
  ASSERT_GT(truth.x, 5.0);
  EXPECT_NEAR(truth.y, 0.0, 1e-9);
  EXPECT_NEAR(truth.yaw, 0.0, 1e-9);
  // The wheels' true travel is d / r each; the odometry's arc has length d (1 + (eL + eR) / 2) and
  // turns by d (eR - eL) / (2 L1).
  const double d = truth.x, L1 = c.robot.half_track_m;
  const double yaw = d * (e_right - e_left) / (2.0 * L1), length = d * (1.0 + 0.5 * (e_left + e_right));
  const double radius = length / yaw;
  EXPECT_NEAR(odo.pose().yaw, yaw, 1e-5);
  EXPECT_NEAR(odo.pose().x, radius * std::sin(yaw), 1e-4);
  EXPECT_NEAR(odo.pose().y, radius * (1.0 - std::cos(yaw)), 1e-4);
}

TEST(WheelOdometry, BodyIncrementsOfTheMecanumWheelPatterns) {
  const RobotConfig rc;  // alpha = 45 deg
  const auto model = make_robot_model(rc);
  const WheelOdometry odo(*model, 1000);
  const double r = rc.wheel_radius_m, d = 0.3;
  const std::vector<double> forward{d, d, d, d}, left{-d, d, d, -d}, turn{-d, d, -d, d};
  const BodyTwist f = odo.body_increment(forward), l = odo.body_increment(left), t = odo.body_increment(turn);
  EXPECT_NEAR(f.vx, r * d, 1e-15);
  EXPECT_NEAR(f.vy, 0.0, 1e-15);
  EXPECT_NEAR(f.wz, 0.0, 1e-15);
  EXPECT_NEAR(l.vx, 0.0, 1e-15);
  EXPECT_NEAR(l.vy, r * d, 1e-15);
  EXPECT_NEAR(t.wz, r * d / (rc.half_track_m + rc.half_wheelbase_m), 1e-15);
}

TEST(WheelOdometry, EulerIsThePapersFirstOrderUpdate) {
  // A quarter turn on a circle of radius R in one sample: the exact update lands on the circle,
  // the paper's Euler update goes straight along the initial heading.
  RobotConfig rc;
  rc.drive = DriveKind::Differential;
  const auto model = make_robot_model(rc);
  const double R = 2.0, arc = R * kPi / 2.0, r = rc.wheel_radius_m, L = rc.half_track_m;
  const double left = (arc - L * kPi / 2.0) / r, right = (arc + L * kPi / 2.0) / r;  // wheel angles
  WheelOdometry exact(*model, 1000), euler(*model, 1000, {}, OdometryUpdate::Euler);
  for (WheelOdometry* o : {&exact, &euler}) {
    o->add_angles(std::vector<double>{0.0, 0.0});
    o->add_angles(std::vector<double>{left, right});
  }
  EXPECT_NEAR(exact.pose().x, R, 1e-12);
  EXPECT_NEAR(exact.pose().y, R, 1e-12);
  EXPECT_NEAR(exact.pose().yaw, kPi / 2.0, 1e-12);
  EXPECT_NEAR(euler.pose().x, arc, 1e-12);
  EXPECT_NEAR(euler.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(euler.pose().yaw, kPi / 2.0, 1e-12);
}

TEST(WheelOdometry, BadInputNamesTheField) {
  RobotConfig rc;
  rc.drive = DriveKind::Ackermann;
  const auto ackermann = make_robot_model(rc);
  try {
    WheelOdometry o(*ackermann, 1000);
    FAIL() << "Ackermann accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "robot.drive");
  }
  const auto mecanum = make_robot_model(RobotConfig{});
  try {
    WheelOdometry o(*mecanum, 0);
    FAIL() << "0 ticks accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "encoders.ticks_per_rev");
  }
  WheelOdometry o(*mecanum, 1000);
  EXPECT_THROW(o.add_ticks(std::vector<std::int64_t>{1, 2, 3}), Error);
  EXPECT_THROW(o.add_angles(std::vector<double>{0.0, 0.0, NAN, 0.0}), Error);
}

}  // namespace
}  // namespace starnav
