// The Slam role, one for 2D and 3D, driven by messages on a SensorBus alone:
//  - the planar `graph` built by the registry, fed a log through its source, gives the trajectory
//    the direct calls gave before the role took messages (the digests below were written by
//    GraphSlam::add(scan, odometry, mount) per scan of the same logs, before that call was
//    replaced by on_odometry + on_scan);
//  - `graph3d` built by the registry, fed clouds and odometry as messages, gives bit for bit the
//    trajectory, key frames and floors of GraphSlam3d::add called directly with the same frames;
//  - the typed capability: each method says what it maps, and refuses the other kind of data;
//  - a fake ScanMatcher injected into GraphSlam without the registry is what it calls, for the
//    local map and for every submap, and a matcher that never converges leaves the odometry.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "cloud/synthetic_scene.hpp"
#include "room_fixture.hpp"
#include "slam_playback.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/slam/graph_slam.hpp"
#include "starnav/slam/graph_slam_3d.hpp"
#include "support/sha256.hpp"

namespace starnav {
namespace {

std::unique_ptr<Slam> registry_slam(const std::string& name, const SlamMatcherChoice& matcher = {}) {
  SlamContext ctx;
  ctx.matcher = matcher;
  return find_slam(name).make(ctx, {});
}

TEST(SlamRole, PlanarGraphThroughMessagesGivesTheDirectCallsTrajectory) {
  std::vector<Pose2> truth;
  const RobotLog ring = test::ring_drive(truth);
  std::unique_ptr<Slam> slam = registry_slam("graph");
  ASSERT_EQ(slam->space(), SlamSpace::Planar);
  test::play_log(*slam, ring);
  const std::vector<TrajectoryPose> t = planar_trajectory(slam->trajectory());
  EXPECT_EQ(t.size(), 640u);
  EXPECT_EQ(slam->graph().nodes.size(), 256u);
  EXPECT_EQ(slam->graph().closures(), 40u);
  EXPECT_EQ(test::sha256_hex(trajectory_csv(t)), "ba774eb1547d087be7d579e5572cea436d5c33814c4300063c79070334337f26");

  // A laser off the base's centre and turned: its mount travels as a Pose3 (a quaternion, whose yaw
  // reads back to within an ulp) and the trajectory is the same.
  RobotLog mounted = ring;
  mounted.laser_in_base = Pose2(0.2, -0.05, 0.03);
  mounted.scans.resize(300);
  std::unique_ptr<Slam> again = registry_slam("graph");
  test::play_log(*again, mounted);
  const std::vector<SlamPose> poses = again->trajectory();
  EXPECT_EQ(test::sha256_hex(trajectory_csv(planar_trajectory(poses))),
            "d8770c4f4082c0f7950b41ac7d21167fce78b433f1bcb73630b150fde52588aa");
  // The sensor's view: the base composed with the mount, at z = 0.
  const Pose2 laser = poses.back().base.compose(*mounted.laser_in_base);
  EXPECT_NEAR(poses.back().sensor.translation().x(), laser.x, 1e-12);
  EXPECT_NEAR(poses.back().sensor.translation().y(), laser.y, 1e-12);
  EXPECT_EQ(poses.back().sensor.translation().z(), 0.0);
  EXPECT_EQ(poses.back().stamp_us, mounted.scans.back().stamp_us);
}

// Synthetic frames of a room along an arc (test_graph_slam_3d's), with the truth as odometry.
struct Frames {
  std::vector<double> t;
  std::vector<PointCloud> clouds;
  std::vector<Pose2> odometry;
};
const Pose3 kMount = Pose3::from_rpy(Vec3(0.1, 0.0, 0.55), 0.0, 0.0, 0.0);

Frames synthetic_frames(int n) {
  Frames f;
  Rng rng(7);
  for (int k = 0; k < n; ++k) {
    const double s = 0.1 * k;
    const Rigid3 base = to_rigid(Pose3::from_rpy(Vec3(-3.0 + s, -1.0 + 0.02 * s * s, 0.0), 0, 0, 0.04 * s));
    f.t.push_back(0.1 * k);
    f.clouds.push_back(transform_cloud(test::synthetic_room(rng, 150, 0.005), (base * to_rigid(kMount)).inverse()));
    f.odometry.push_back(to_pose3(base).to_pose2());
  }
  return f;
}

TEST(SlamRole, ThreeDGraphThroughMessagesGivesTheDirectCallsTrajectory) {
  const Frames f = synthetic_frames(30);
  GraphSlam3dConfig c;
  c.prefilter.window.min_range_m = 0.3;
  c.loops = false;
  const ScanMatcher3dDef& ndt = find_scan_matcher_3d("ndt");
  GraphSlam3d direct(c, kMount, [&] { return ndt.make({}, {}); });
  for (std::size_t k = 0; k < f.t.size(); ++k) direct.add(f.t[k], f.clouds[k], f.odometry[k]);
  direct.finish();

  SlamContext ctx;
  ctx.matcher.name = "ndt";
  std::unique_ptr<Slam> slam =
      find_slam("graph3d").make(ctx, std::vector<ParamSetting>{{"min_range_m", "0.3", "", 0, "min_range_m"}, {"loops", "false", "", 0, "loops"}});
  ASSERT_EQ(slam->space(), SlamSpace::ThreeD);
  SensorBus bus;
  bus.subscribe<OdometryMessage>("odom", [&](const OdometryMessage& m) { slam->on_odometry(m); });
  bus.subscribe<CloudMessage>("lidar", [&](const CloudMessage& m) { slam->on_cloud(m); });
  for (std::size_t k = 0; k < f.t.size(); ++k) {
    OdometryMessage o;
    o.header = {f.t[k], "odom"};
    o.pose = f.odometry[k];
    bus.publish(o);
    CloudMessage cloud;
    cloud.header = {f.t[k], "lidar"};
    cloud.mount = kMount;
    cloud.points = f.clouds[k];
    bus.publish(cloud);
    bus.deliver_until(f.t[k]);
  }
  slam->finish();

  const std::vector<Rigid3> expected = direct.sensor_poses();
  const std::vector<SlamPose> got = slam->trajectory();
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_TRUE(got[k].sensor.matrix() == expected[k].matrix()) << "frame " << k;
    EXPECT_EQ(got[k].t_s, f.t[k]);
  }
  ASSERT_EQ(slam->keyframes_3d().size(), direct.keyframes().size());
  ASSERT_GE(direct.keyframes().size(), 3u);
  for (std::size_t k = 0; k < direct.keyframes().size(); ++k) {
    EXPECT_TRUE(slam->keyframes_3d()[k].pose.matrix() == direct.keyframes()[k].pose.matrix());
    EXPECT_EQ(slam->keyframes_3d()[k].floor.has_value(), direct.keyframes()[k].floor.has_value());
  }
  // The planar view is the base under the sensor: sensor * mount^-1, level.
  const Rigid3 base = got.back().sensor * to_rigid(kMount).inverse();
  EXPECT_NEAR(got.back().base.x, base.translation().x(), 1e-12);
  EXPECT_NEAR(got.back().base.y, base.translation().y(), 1e-12);
  // The pose graph: a node per key frame, consecutive key frames joined.
  const SlamGraph g = slam->graph();
  EXPECT_EQ(g.nodes.size(), direct.keyframes().size());
  EXPECT_EQ(g.edges.size(), direct.keyframes().size() - 1);
  EXPECT_EQ(g.closures(), 0u);
}

TEST(SlamRole, EachMethodSaysWhatItMapsAndRefusesTheOther) {
  EXPECT_TRUE(find_slam("graph").info.has(Capability::Planar));
  EXPECT_FALSE(find_slam("graph").info.has(Capability::ThreeD));
  EXPECT_TRUE(find_slam("graph3d").info.has(Capability::ThreeD));
  std::unique_ptr<Slam> planar = registry_slam("graph");
  std::unique_ptr<Slam> spatial = registry_slam("graph3d");
  EXPECT_EQ(planar->space(), SlamSpace::Planar);
  EXPECT_EQ(spatial->space(), SlamSpace::ThreeD);
  CloudMessage cloud;
  cloud.header = {0.0, "lidar"};
  ScanMessage scan;
  scan.header = {0.0, "lidar"};
  EXPECT_THROW(planar->on_cloud(cloud), Error);
  EXPECT_THROW(spatial->on_scan(scan), Error);
  EXPECT_THROW((void)planar->map_3d(OctreeMapConfig{}), Error);
  EXPECT_TRUE(planar->keyframes_3d().empty());
  // A scan before any odometry has nowhere to start from: not placed.
  scan.ranges_m.assign(10, 1.0);
  scan.range_max_m = 5.0;
  EXPECT_FALSE(planar->on_scan(scan));
  EXPECT_TRUE(planar->trajectory().empty());
  // A matcher of the wrong kind, or unknown, is named.
  try {
    registry_slam("graph", {"icp", {}, "--matcher"});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--matcher");
  }
  try {
    registry_slam("graph3d", {"correlative", {}, "--matcher"});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "--matcher");
  }
}

// A reference that never matches, counting its matches.
class CountingReference final : public ScanReference {
 public:
  explicit CountingReference(int& matches) : matches_(matches) {}
  ScanMatch match(std::span<const Vec2> /*scan*/, const Pose2& guess) const override {
    ++matches_;
    ScanMatch m;
    m.transform = guess;
    return m;
  }
  ScanMatch match(std::span<const Vec2> scan, const Pose2& guess, const MatchWindow& /*window*/) const override {
    return match(scan, guess);
  }
  std::size_t bytes() const override { return 1; }

 private:
  int& matches_;
};

// A matcher whose references never match: it records every prepare().
class FakeMatcher final : public ScanMatcher {
 public:
  struct Prepared {
    std::size_t points;
    double margin_m;
    int depth;
  };
  std::string_view name() const override { return "fake"; }
  ScanMatch match(std::span<const Vec2>, std::span<const Vec2>, const Pose2& guess) override {
    ScanMatch m;
    m.transform = guess;
    return m;
  }
  bool supports_reference() const override { return true; }
  std::unique_ptr<ScanReference> prepare(std::span<const Vec2> points, double margin_m, int depth) const override {
    prepared->push_back({points.size(), margin_m, depth});
    return std::make_unique<CountingReference>(*matches);
  }
  MatchWindow window() const override { return {0.25, 0.3, 0.5, 0.0, 0.0}; }

  std::shared_ptr<std::vector<Prepared>> prepared = std::make_shared<std::vector<Prepared>>();
  std::shared_ptr<int> matches = std::make_shared<int>(0);
};

TEST(GraphSlam, CallsTheScanMatcherItIsGiven) {
  std::vector<Pose2> truth;
  RobotLog log = test::ring_drive(truth);
  auto fake = std::make_unique<FakeMatcher>();
  const auto prepared = fake->prepared;
  const auto matches = fake->matches;
  GraphSlamConfig c;
  c.loop_min_score = 0.5;
  GraphSlam slam(c, std::move(fake));
  test::play_log(slam, log);
  // The local map, rebuilt every other node, wide by the matcher's window, two levels deep...
  ASSERT_FALSE(prepared->empty());
  EXPECT_EQ(prepared->front().margin_m, 0.25);
  EXPECT_EQ(prepared->front().depth, 2);
  // ... and the submaps the closures searched, as deep as the graph's search.
  std::size_t submaps = 0;
  for (const FakeMatcher::Prepared& p : *prepared)
    if (p.depth == c.search_depth && p.margin_m == 0.0) ++submaps;
  EXPECT_GT(submaps, 0u);
  const std::vector<std::pair<std::string, double>> stats = slam.statistics();
  double searches = 0, scans = 0;
  for (const auto& [k, v] : stats) {
    if (k == "loop_searches" || k == "global_searches") searches += v;
    if (k == "scans") scans = v;
  }
  // Every scan after the first local map was matched, and every closure search asked the matcher.
  EXPECT_GT(searches, 0.0);
  EXPECT_GE(static_cast<double>(*matches), scans - 2 + searches);
  // Nothing ever matched: no closure, and the trajectory is the odometry's dead reckoning.
  EXPECT_EQ(slam.graph().closures(), 0u);
  const std::vector<SlamPose> t = slam.trajectory();
  ASSERT_EQ(t.size(), log.scans.size());
  for (std::size_t k = 0; k < t.size(); k += 37) {
    const Pose2 odom = *log.scans[k].odometry;
    EXPECT_NEAR(t[k].base.x, odom.x, 1e-9) << k;
    EXPECT_NEAR(t[k].base.y, odom.y, 1e-9) << k;
    EXPECT_NEAR(std::remainder(t[k].base.yaw - odom.yaw, 2 * kPi), 0.0, 1e-9) << k;
  }
  // A matcher that cannot prepare references cannot serve.
  class PairsOnly final : public ScanMatcher {
   public:
    std::string_view name() const override { return "pairs_only"; }
    ScanMatch match(std::span<const Vec2>, std::span<const Vec2>, const Pose2&) override { return {}; }
  };
  EXPECT_THROW(GraphSlam(c, std::make_unique<PairsOnly>()), Error);
  EXPECT_THROW(GraphSlam(c, nullptr), Error);
}

}  // namespace
}  // namespace starnav
