// The ground-truth localizer: exact without noise; with noise, zero-mean Gaussian errors of the
// declared standard deviations (sample statistics), a diagonal covariance saying so, and the
// same draws for the same seed.
#include <gtest/gtest.h>

#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {
namespace {

TEST(GroundTruthLocalizer, WithoutNoiseItReportsTheTruthExactly) {
  const auto loc = find_localizer("ground_truth").make({Pose2(1.0, 2.0, 0.3), 5, ""}, {});
  EXPECT_FALSE(loc->estimate().valid);
  EXPECT_EQ(loc->estimate().pose.x, 1.0);
  loc->on_ground_truth(0.5, Pose2(3.25, -1.5, 2.0));
  const PoseEstimate e = loc->estimate();
  EXPECT_TRUE(e.valid);
  EXPECT_EQ(e.t_s, 0.5);
  EXPECT_EQ(e.pose.x, 3.25);
  EXPECT_EQ(e.pose.y, -1.5);
  EXPECT_EQ(e.pose.yaw, 2.0);
  EXPECT_TRUE(e.covariance.isZero());
}

TEST(GroundTruthLocalizer, NoiseHasTheDeclaredStatisticsAndFollowsTheSeed) {
  const std::vector<ParamSetting> s = {{"sigma_xy_m", "0.05", "", 0, "x"}, {"sigma_yaw_deg", "2", "", 0, "y"}};
  const auto a = find_localizer("ground_truth").make({{}, 11, ""}, s);
  const auto b = find_localizer("ground_truth").make({{}, 11, ""}, s);
  const int n = 20000;
  double sx = 0, sxx = 0, syaw = 0, syy = 0;
  for (int i = 0; i < n; ++i) {
    a->on_ground_truth(i, Pose2(1.0, 1.0, 0.0));
    b->on_ground_truth(i, Pose2(1.0, 1.0, 0.0));
    const Pose2 p = a->estimate().pose;
    ASSERT_EQ(p.x, b->estimate().pose.x);
    sx += p.x - 1.0;
    sxx += (p.x - 1.0) * (p.x - 1.0);
    syaw += p.yaw;
    syy += p.yaw * p.yaw;
  }
  const double sigma_yaw = 2.0 * kPi / 180.0;
  // Mean within 5 standard errors; standard deviation within 3 %.
  EXPECT_NEAR(sx / n, 0.0, 5 * 0.05 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sxx / n), 0.05, 0.03 * 0.05);
  EXPECT_NEAR(syaw / n, 0.0, 5 * sigma_yaw / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(syy / n), sigma_yaw, 0.03 * sigma_yaw);
  const Eigen::Matrix3d c = a->estimate().covariance;
  EXPECT_DOUBLE_EQ(c(0, 0), 0.05 * 0.05);
  EXPECT_DOUBLE_EQ(c(2, 2), sigma_yaw * sigma_yaw);
  EXPECT_EQ(c(0, 1), 0.0);
}

}  // namespace
}  // namespace starnav
