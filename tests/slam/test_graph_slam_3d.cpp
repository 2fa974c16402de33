// 3D graph SLAM on synthetic frames: a room sampled anew for every frame and seen from a known
// trajectory; the estimated trajectory against it, the floor found in every key frame, same
// inputs same result.
#include <gtest/gtest.h>

#include <cmath>

#include "cloud/synthetic_scene.hpp"
#include "starnav/cloud/gicp.hpp"
#include "starnav/cloud/ndt.hpp"
#include "starnav/core/error.hpp"
#include "starnav/slam/graph_slam_3d.hpp"

namespace starnav {
namespace {

const Pose3 kSlam3dMount = Pose3::from_rpy(Vec3(0.0, 0.0, 0.55), 0.0, 0.0, 0.0);

// Base poses along a gentle arc on the floor, 0.1 m per frame.
std::vector<Rigid3> slam3d_truth(int frames) {
  std::vector<Rigid3> out;
  for (int k = 0; k < frames; ++k) {
    const double s = 0.1 * k;
    out.push_back(to_rigid(Pose3::from_rpy(Vec3(-3.0 + s, -1.0 + 0.02 * s * s, 0.0), 0, 0, 0.04 * s)));
  }
  return out;
}

struct Slam3dRun {
  std::vector<Rigid3> estimate, truth_sensor;
  std::size_t keyframes = 0, floors = 0;
};

Slam3dRun run_synthetic(const std::string& matcher, bool odometry, std::uint64_t seed) {
  GraphSlam3dConfig c;
  c.prefilter.window.min_range_m = 0.3;
  c.loops = false;
  GraphSlam3d slam(c, kSlam3dMount, [&]() -> std::unique_ptr<ScanMatcher3d> {
    if (matcher == "gicp") return std::make_unique<GicpMatcher>(GicpConfig{});
    return std::make_unique<NdtMatcher>(NdtConfig{});
  });
  Rng rng(seed);
  Slam3dRun r;
  const std::vector<Rigid3> truth = slam3d_truth(40);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const Rigid3 sensor = truth[k] * to_rigid(kSlam3dMount);
    const PointCloud world = test::synthetic_room(rng, 150, 0.005);
    std::optional<Pose2> odom;
    if (odometry) odom = to_pose3(truth[k]).to_pose2();
    slam.add(0.1 * static_cast<double>(k), transform_cloud(world, sensor.inverse()), odom);
    r.truth_sensor.push_back(sensor);
  }
  slam.finish();
  r.estimate = slam.sensor_poses();
  r.keyframes = slam.keyframes().size();
  for (const Slam3dKeyframe& kf : slam.keyframes()) r.floors += kf.floor.has_value();
  return r;
}

TEST(GraphSlam3d, FollowsAKnownTrajectoryThroughARoom) {
  for (const std::string matcher : {"ndt", "gicp"}) {
    SCOPED_TRACE(matcher);
    const Slam3dRun r = run_synthetic(matcher, false, 3);
    ASSERT_EQ(r.estimate.size(), 40u);
    // 3.9 m travelled: a key frame about every metre, each seeing the floor.
    EXPECT_GE(r.keyframes, 4u);
    EXPECT_LE(r.keyframes, 6u);
    EXPECT_EQ(r.floors, r.keyframes);
    // The map frame is the mount above the origin; the truth's first sensor pose is elsewhere:
    // compare motions relative to the first pose.
    for (std::size_t k = 0; k < r.estimate.size(); ++k) {
      const Rigid3 est = r.estimate.front().inverse() * r.estimate[k];
      const Rigid3 tru = r.truth_sensor.front().inverse() * r.truth_sensor[k];
      EXPECT_LT(translation_norm(tru.inverse() * est), 0.03) << "frame " << k;
      EXPECT_LT(rotation_angle(tru.inverse() * est) * 180 / kPi, 0.3) << "frame " << k;
    }
    // The floor holds the height: every pose 0.55 m above z = 0 and level.
    for (const Rigid3& t : r.estimate) {
      EXPECT_NEAR(t.translation().z(), 0.55, 0.02);
      EXPECT_GT((t.linear() * Vec3::UnitZ()).z(), std::cos(0.5 * kPi / 180));
    }
  }
}

TEST(GraphSlam3d, SameInputsSameTrajectoryAndOdometryAsTheGuess) {
  const Slam3dRun a = run_synthetic("ndt", true, 5), b = run_synthetic("ndt", true, 5);
  ASSERT_EQ(a.estimate.size(), b.estimate.size());
  for (std::size_t k = 0; k < a.estimate.size(); ++k) EXPECT_TRUE(a.estimate[k].matrix() == b.estimate[k].matrix());
  const Rigid3 last = a.estimate.front().inverse() * a.estimate.back();
  const Rigid3 truth = a.truth_sensor.front().inverse() * a.truth_sensor.back();
  EXPECT_LT(translation_norm(truth.inverse() * last), 0.03);
}

TEST(GraphSlam3d, BadInputGetsClearErrors) {
  GraphSlam3dConfig c;
  c.keyframe_delta_trans_m = 0.0;
  EXPECT_THROW(GraphSlam3d(c, kSlam3dMount, [] { return std::make_unique<NdtMatcher>(NdtConfig{}); }), Error);
  GraphSlam3d slam(GraphSlam3dConfig{}, kSlam3dMount, [] { return std::make_unique<NdtMatcher>(NdtConfig{}); });
  try {
    slam.add(0.0, PointCloud{{1, 0, 0}, {2, 0, 0}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "prefilter");
  }
  EXPECT_THROW(GraphSlam3d(GraphSlam3dConfig{}, kSlam3dMount, [] { return std::unique_ptr<ScanMatcher3d>(); }), Error);
}

}  // namespace
}  // namespace starnav
