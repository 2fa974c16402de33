// The CARMEN writer: a log written and read back holds the same scans (ranges to the written
// millimetre, beam layout, no-returns), odometry, ground truth and laser mount; FLASER for
// FLASER's layout, ROBOTLASER1 for any other.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/logs/carmen_log.hpp"

namespace starnav {
namespace {

RobotLog sample_log(double angle_min, double increment, std::size_t beams) {
  RobotLog log;
  log.laser_in_base = Pose2(0.12, 0.0, 0.0);
  for (int k = 0; k < 5; ++k) {
    const std::int64_t t = 1'000'000 + k * 100'000;
    log.odometry.push_back({t - 10, Pose2(0.1 * k, 0.01 * k, wrap_angle(3.1 + 0.05 * k)), 0.5, 0.1});
    log.truth.push_back({t, Pose2(0.1 * k + 0.001, 0.0, 0.02 * k), Pose2(0.1 * k, 0.01 * k, 0.05 * k)});
    LogScan s;
    s.stamp_us = t;
    s.angle_min_rad = angle_min;
    s.angle_increment_rad = increment;
    s.range_max_m = 30.0;
    for (std::size_t b = 0; b < beams; ++b) s.ranges_m.push_back(b % 17 == 3 ? 30.0f : static_cast<float>(1.0 + 0.0123 * static_cast<double>(b)));
    log.scans.push_back(s);
  }
  return log;
}

void expect_round_trip(const RobotLog& log, const std::string& line_type) {
  const std::string text = carmen_log_text(log);
  EXPECT_NE(text.find("\n" + line_type + " "), std::string::npos);
  const RobotLog back = read_carmen_log(text, "written.clf", {});
  ASSERT_EQ(back.scans.size(), log.scans.size());
  ASSERT_EQ(back.odometry.size(), log.odometry.size());
  ASSERT_EQ(back.truth.size(), log.truth.size());
  ASSERT_TRUE(back.laser_in_base.has_value());
  EXPECT_DOUBLE_EQ(back.laser_in_base->x, 0.12);
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    const LogScan& a = log.scans[k];
    const LogScan& b = back.scans[k];
    EXPECT_EQ(a.stamp_us, b.stamp_us);
    EXPECT_NEAR(a.angle_min_rad, b.angle_min_rad, 1e-9);
    EXPECT_NEAR(a.angle_increment_rad, b.angle_increment_rad, 1e-9);
    ASSERT_EQ(a.ranges_m.size(), b.ranges_m.size());
    for (std::size_t i = 0; i < a.ranges_m.size(); ++i) {
      EXPECT_EQ(a.returned(i), b.returned(i)) << k << " " << i;
      if (a.returned(i)) {
        EXPECT_NEAR(a.ranges_m[i], b.ranges_m[i], 6e-4);
      }
    }
    // The odometry written beside the scan is the interpolated odometry at its stamp.
    ASSERT_TRUE(b.odometry.has_value());
    EXPECT_NEAR(b.odometry->x, 0.1 * static_cast<double>(k), 1e-3);
    EXPECT_NEAR(b.laser_pose->x - b.odometry->x, 0.12 * std::cos(b.odometry->yaw), 1e-5);
  }
  for (std::size_t k = 0; k < log.truth.size(); ++k) {
    EXPECT_EQ(back.truth[k].stamp_us, log.truth[k].stamp_us);
    EXPECT_NEAR(back.truth[k].pose.x, log.truth[k].pose.x, 1e-6);
  }
  EXPECT_NEAR(back.odometry[2].pose.yaw, log.odometry[2].pose.yaw, 1e-6);
  EXPECT_EQ(carmen_log_text(back), text);  // a log read and written again keeps its bytes
}

TEST(CarmenWriter, FlaserLayoutRoundTrips) {
  RobotLog log = sample_log(-kPi / 2, deg_to_rad(1.0), 180);
  // FLASER stores no maximum range: the reader infers it from a repeated largest reading.
  for (LogScan& s : log.scans)
    for (float& r : s.ranges_m) r = std::min(r, 30.0f);
  expect_round_trip(log, "FLASER");
}

TEST(CarmenWriter, OtherLayoutsBecomeRobotLaser) {
  expect_round_trip(sample_log(-deg_to_rad(135.0), deg_to_rad(0.25), 1081), "ROBOTLASER1");
}

}  // namespace
}  // namespace starnav
