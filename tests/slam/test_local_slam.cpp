// Local SLAM (scan-to-local-map matching from odometry): on a simulated drive through a furnished
// room with drifting odometry it stays near the truth while the odometry drifts away; and on the
// first 300 scans of the aces log it beats the odometry on the benchmark relations inside them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "room_fixture.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/slam/local_slam.hpp"
#include "starnav/slam/relative_pose_error.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(LocalSlam, StaysWithTheTruthWhereTheOdometryDrifts) {
  // A loop around the room's middle; the odometry over-reads distance by 3 % and turning by 2 %.
  RobotLog log;
  std::vector<Pose2> truth;
  // An ellipse around (2.8, 2.1), clear of the box and the pillar, heading along it.
  Rng rng(3);
  Pose2 odom;
  for (int k = 0; k <= 240; ++k) {
    const double s = k / 240.0 * 2 * kPi;
    const Pose2 t(2.8 - 1.8 * std::cos(s), 2.1 - 1.0 * std::sin(s), std::atan2(-1.0 * std::cos(s), 1.8 * std::sin(s)));
    if (k == 0) odom = t;
    if (k > 0) {
      const Pose2 d = truth.back().inverse().compose(t);
      odom = odom.compose(Pose2(d.x * 1.03, d.y * 1.03, d.yaw * 1.02));
    }
    truth.push_back(t);
    LogScan scan;
    scan.stamp_us = k * 100'000;
    scan.angle_min_rad = -kPi;
    scan.angle_increment_rad = 2 * kPi / 360;
    scan.range_max_m = 50.0;
    scan.ranges_m = test::ranges_from(t, 360, 80.0f);
    for (float& r : scan.ranges_m)
      if (r < 50) r += static_cast<float>(0.005 * rng.normal());
    scan.odometry = odom;
    log.scans.push_back(scan);
  }
  const LocalSlamResult r = run_local_slam(log, LocalSlamConfig{}, CorrelativeScanMatcher(local_slam_matcher_config()));
  ASSERT_EQ(r.poses.size(), truth.size());
  EXPECT_GT(r.matched, 230u);
  // Both start at the first odometry pose, which is the truth there.
  double slam_err = 0, odom_err = 0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    slam_err = std::max(slam_err, (r.poses[k].pose.translation() - truth[k].translation()).norm());
    odom_err = std::max(odom_err, (log.scans[k].odometry->translation() - truth[k].translation()).norm());
  }
  EXPECT_GT(odom_err, 0.15);
  EXPECT_LT(slam_err, 0.05) << "odometry drifted " << odom_err << " m";
  EXPECT_LT(slam_err, odom_err / 4);
}

TEST(LocalSlam, BeatsTheOdometryOnTheFirstScansOfAces) {
  // (300 scans keep the test short; the whole log runs in `make bench`.)
  STARNAV_SKIP_WITHOUT_SHARED("datasets/carmen_raw/ros1_bags/aces.orig.bag");
  LogReadOptions o;
  o.flaser_beam_angles = true;
  RobotLog log = read_robot_log(test::shared_path("datasets/carmen_raw/ros1_bags/aces.orig.bag"), o);
  log.scans.resize(300);
  const std::vector<PoseRelation> all = read_relations(test::shared_path("datasets/slam_benchmark_relations/aces.relations"));
  // The relations inside the first 300 scans.
  const std::int64_t last = log.scans.back().stamp_us;
  std::vector<PoseRelation> inside;
  for (const PoseRelation& rel : all)
    if (rel.t_i_us <= last && rel.t_j_us <= last) inside.push_back(rel);
  ASSERT_GT(inside.size(), 30u);
  const LocalSlamResult r = run_local_slam(log, LocalSlamConfig{}, CorrelativeScanMatcher(local_slam_matcher_config()));
  const RelativePoseError slam = relative_pose_error(r.poses, inside);
  const RelativePoseError odom = relative_pose_error(odometry_trajectory(log), inside);
  EXPECT_EQ(slam.unmatched, 0u);
  EXPECT_LT(slam.translation_m.mean, odom.translation_m.mean);
  EXPECT_LT(slam.translation_m.mean, 0.06) << "odometry " << odom.translation_m.mean;
  EXPECT_LT(slam.rotation_deg.mean, odom.rotation_deg.mean);
}

}  // namespace
}  // namespace starnav
