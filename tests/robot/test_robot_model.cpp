// Robot kinematics and the actuator chain: Mecanum against the spec's closed forms, forward and
// inverse as exact inverses for every model, limits that keep the direction of motion, the lag's
// step response against 1 - exp(-t/tau).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/robot/robot_model.hpp"

using namespace starnav;

namespace {

RobotConfig config_of(DriveKind kind) {
  RobotConfig c;
  c.drive = kind;
  return c;
}

void expect_twist_near(const BodyTwist& a, const BodyTwist& b, double tol) {
  EXPECT_NEAR(a.vx, b.vx, tol);
  EXPECT_NEAR(a.vy, b.vy, tol);
  EXPECT_NEAR(a.wz, b.wz, tol);
}

}  // namespace

TEST(RobotModel, NamesRoundTripAndBadNameNamesTheField) {
  for (const DriveKind k : {DriveKind::Mecanum, DriveKind::Differential, DriveKind::Ackermann})
    EXPECT_EQ(parse_drive_kind(drive_kind_name(k), "robot.drive"), k);
  try {
    parse_drive_kind("tank", "robot.drive");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "robot.drive");
  }
}

TEST(RobotModel, ValidateNamesTheField) {
  RobotConfig c;
  c.wheel_radius_m = 0.0;
  try {
    c.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "robot.wheel_radius_m");
  }
  c = RobotConfig{};
  c.roller_angle_rad = 0.5 * kPi;
  EXPECT_THROW(make_robot_model(c), Error);
  c = RobotConfig{};
  c.actuator_lag_s = -1.0;
  EXPECT_THROW(RobotDrive{c}, Error);
}

TEST(Mecanum, MatchesTheClosedFormAt45Degrees) {
  const RobotConfig c;  // alpha = 45 deg
  const auto m = make_robot_model(c);
  ASSERT_EQ(m->actuator_count(), 4);
  EXPECT_TRUE(m->holonomic());
  EXPECT_TRUE(m->turns_in_place());
  Rng rng(7);
  const double r = c.wheel_radius_m, k = c.half_track_m + c.half_wheelbase_m;
  for (int i = 0; i < 100; ++i) {
    const BodyTwist v{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-2, 2)};
    std::array<double, 4> w{};
    m->inverse(v, w);
    EXPECT_NEAR(w[0], (v.vx - v.vy - k * v.wz) / r, 1e-12);  // FL
    EXPECT_NEAR(w[1], (v.vx + v.vy + k * v.wz) / r, 1e-12);  // FR
    EXPECT_NEAR(w[2], (v.vx + v.vy - k * v.wz) / r, 1e-12);  // RL
    EXPECT_NEAR(w[3], (v.vx - v.vy + k * v.wz) / r, 1e-12);  // RR
  }
}

TEST(Mecanum, ForwardAndInverseAreExactInversesAtSeveralRollerAngles) {
  for (const double alpha_deg : {20.0, 30.0, 45.0, 60.0, 75.0}) {
    RobotConfig c;
    c.roller_angle_rad = alpha_deg * kPi / 180.0;
    const auto m = make_robot_model(c);
    Rng rng(11);
    for (int i = 0; i < 50; ++i) {
      const BodyTwist v{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-2, 2)};
      std::array<double, 4> w{};
      m->inverse(v, w);
      expect_twist_near(m->forward(w), v, 1e-12);
      // Each wheel's roller constraint from the wheel's own velocity (independent derivation):
      // r w_i = (vx - wz y_i) + s_i (vy + wz x_i) / tan(alpha), s = -, +, +, - for FL, FR, RL, RR.
      const auto contacts = m->wheel_contacts();
      const double sgn[4] = {-1, 1, 1, -1};
      for (int j = 0; j < 4; ++j) {
        const double xi = contacts[j].x(), yi = contacts[j].y();
        const double expect = ((v.vx - v.wz * yi) + sgn[j] * (v.vy + v.wz * xi) / std::tan(c.roller_angle_rad)) /
                              c.wheel_radius_m;
        EXPECT_NEAR(w[j], expect, 1e-11) << alpha_deg << " deg wheel " << j;
      }
      // Wheel speeds in the range of inverse() come back unchanged.
      std::array<double, 4> w2{};
      m->inverse(m->forward(w), w2);
      for (int j = 0; j < 4; ++j) EXPECT_NEAR(w2[j], w[j], 1e-10);
    }
  }
}

TEST(Differential, WheelsAtHalfTrackAndExactInverse) {
  const RobotConfig c = config_of(DriveKind::Differential);
  const auto m = make_robot_model(c);
  EXPECT_FALSE(m->holonomic());
  EXPECT_TRUE(m->turns_in_place());
  ASSERT_EQ(m->actuator_count(), 2);
  // Turning in place at wz: each wheel's rim moves at L1 wz.
  std::array<double, 2> w{};
  m->inverse({0.0, 0.0, 1.0}, w);
  EXPECT_NEAR(w[0] * c.wheel_radius_m, -c.half_track_m, 1e-15);
  EXPECT_NEAR(w[1] * c.wheel_radius_m, c.half_track_m, 1e-15);
  Rng rng(3);
  for (int i = 0; i < 50; ++i) {
    const BodyTwist v{rng.uniform(-1, 1), 0.0, rng.uniform(-2, 2)};
    m->inverse(v, w);
    expect_twist_near(m->forward(w), v, 1e-12);
  }
  // vy is not realisable: dropped.
  m->inverse({0.3, 0.5, 0.0}, w);
  expect_twist_near(m->forward(w), {0.3, 0.0, 0.0}, 1e-12);
}

TEST(Ackermann, BicycleModelAboutTheRearAxle) {
  const RobotConfig c = config_of(DriveKind::Ackermann);
  const auto m = make_robot_model(c);
  EXPECT_FALSE(m->holonomic());
  EXPECT_FALSE(m->turns_in_place());
  const double b = 2.0 * c.half_wheelbase_m;
  const std::array<double, 2> a{5.0, 0.3};
  const BodyTwist v = m->forward(a);
  EXPECT_NEAR(v.vx, 5.0 * c.wheel_radius_m, 1e-15);
  EXPECT_NEAR(v.wz, v.vx * std::tan(0.3) / b, 1e-15);
  EXPECT_EQ(v.vy, 0.0);
  Rng rng(5);
  std::array<double, 2> out{};
  for (int i = 0; i < 50; ++i) {
    const BodyTwist t{rng.uniform(-1, 1), 0.0, rng.uniform(-1, 1)};
    m->inverse(t, out);
    expect_twist_near(m->forward(out), t, 1e-12);
  }
  // Turning in place is impossible: the wheels steer toward the turn and the robot stays.
  m->inverse({0.0, 0.0, 1.0}, out);
  EXPECT_EQ(out[0], 0.0);
  EXPECT_GT(out[1], 0.0);
}

TEST(RobotDrive, SpeedLimitScalesAllWheelsAndKeepsTheDirection) {
  RobotConfig c;
  c.actuator_lag_s = 0.0;
  c.max_wheel_accel_radps2 = 1e9;
  RobotDrive d(c);
  const BodyTwist cmd{3.0, 1.0, 0.5};  // far beyond 10 rad/s wheels
  const BodyTwist v = d.step(cmd, 0.01);
  double peak = 0.0;
  for (const double w : d.actuator_state()) peak = std::max(peak, std::abs(w));
  EXPECT_NEAR(peak, c.max_wheel_speed_radps, 1e-12);
  // Same direction: v = s * cmd with one s in (0, 1).
  const double s = v.vx / cmd.vx;
  EXPECT_GT(s, 0.0);
  EXPECT_LT(s, 1.0);
  EXPECT_NEAR(v.vy, s * cmd.vy, 1e-12);
  EXPECT_NEAR(v.wz, s * cmd.wz, 1e-12);
}

TEST(RobotDrive, AccelerationLimitPerWheel) {
  RobotConfig c;
  c.actuator_lag_s = 0.0;
  RobotDrive d(c);
  const double dt = 0.01;
  double prev = 0.0;
  for (int i = 0; i < 100; ++i) {
    d.step({0.5, 0.0, 0.0}, dt);
    const double w = d.actuator_state()[0];
    EXPECT_LE(w - prev, c.max_wheel_accel_radps2 * dt + 1e-12);
    // The state moves linearly while the limit binds: the step mean is the midpoint.
    if (w - prev > c.max_wheel_accel_radps2 * dt - 1e-9) {
      EXPECT_NEAR(d.actuator_mean()[0], 0.5 * (prev + w), 1e-12);
    }
    prev = w;
  }
  // Reaches the target (0.5 / r = 6.58 rad/s) after 6.58 / 20 = 0.33 s.
  EXPECT_NEAR(prev, 0.5 / c.wheel_radius_m, 1e-12);
}

TEST(RobotDrive, LagStepResponseIsOneMinusExp) {
  RobotConfig c;
  c.actuator_lag_s = 0.2;
  c.max_wheel_accel_radps2 = 1e9;
  for (const double dt : {0.001, 0.01, 0.05}) {
    RobotDrive d(c);
    const double target = 0.3 / c.wheel_radius_m, tau = c.actuator_lag_s;
    double angle = 0.0;
    for (int i = 1; i <= static_cast<int>(std::lround(1.0 / dt)); ++i) {
      const BodyTwist v = d.step({0.3, 0.0, 0.0}, dt);
      const double t = i * dt;
      EXPECT_NEAR(d.actuator_state()[0], target * (1.0 - std::exp(-t / tau)), 1e-9) << dt;
      EXPECT_NEAR(v.vx, 0.3 * (1.0 - std::exp(-t / tau)), 1e-9);
      // The step means integrate to the exact wheel angle T (t - tau (1 - exp(-t/tau))).
      angle += d.actuator_mean()[0] * dt;
      EXPECT_NEAR(angle, target * (t - tau * (1.0 - std::exp(-t / tau))), 1e-9) << dt;
    }
  }
}

TEST(RobotDrive, AckermannSteeringClampedAndRateLimited) {
  RobotConfig c = config_of(DriveKind::Ackermann);
  c.actuator_lag_s = 0.0;
  RobotDrive d(c);
  const double dt = 0.01;
  double prev = 0.0;
  for (int i = 0; i < 200; ++i) {
    d.step({0.2, 0.0, 5.0}, dt);  // asks for steer = atan(0.4 * 5 / 0.2), far beyond 0.5 rad
    const double steer = d.actuator_state()[1];
    EXPECT_LE(steer - prev, c.max_steer_rate_radps * dt + 1e-12);
    EXPECT_LE(steer, c.max_steer_rad + 1e-12);
    prev = steer;
  }
  EXPECT_NEAR(prev, c.max_steer_rad, 1e-12);
  d.stop_wheels();
  EXPECT_EQ(d.actuator_state()[0], 0.0);
  EXPECT_NEAR(d.actuator_state()[1], c.max_steer_rad, 1e-12);
  d.reset();
  for (const double a : d.actuator_state()) EXPECT_EQ(a, 0.0);
}
