// Every 3D scan matcher recovers a known rigid transform between two independent samples of a
// synthetic room; the parallel NDT returns exactly what the single-threaded one does.
#include <gtest/gtest.h>

#include <cmath>

#include "cloud/synthetic_scene.hpp"
#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/gicp.hpp"
#include "starnav/cloud/icp.hpp"
#include "starnav/cloud/ndt.hpp"
#include "starnav/cloud/registration_solver.hpp"
#include "starnav/core/error.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {
namespace {

// The normal equations of one point, written out by blocks, against the dense Jacobian
// dp/dxi = [-[p]x | I] multiplied out: w J^T S J and w J^T v, S not even symmetric.
TEST(RegistrationSolver, OnePointsNormalEquationsMatchTheDenseJacobian) {
  Rng rng(17);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 p(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    Eigen::Matrix3d s;
    for (int i = 0; i < 9; ++i) s.data()[i] = rng.uniform(-2, 2);
    const double w = rng.uniform(0.1, 3.0);
    Eigen::Matrix<double, 3, 6> j;
    j << 0, p.z(), -p.y(), 1, 0, 0,  //
        -p.z(), 0, p.x(), 0, 1, 0,   //
        p.y(), -p.x(), 0, 0, 0, 1;
    registration_detail::NormalEquations eq;
    eq.h.setConstant(0.5);  // it adds to what is there
    eq.g.setConstant(-0.25);
    registration_detail::add_point(eq, p, s, v, w);
    const Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Constant(0.5) + w * j.transpose() * s * j;
    const Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Constant(-0.25) + w * j.transpose() * v;
    EXPECT_LT((eq.h - h).cwiseAbs().maxCoeff(), 1e-11) << "trial " << trial;
    EXPECT_LT((eq.g - g).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
  }
}

Rigid3 known_motion() {
  return to_rigid(Pose3::from_rpy(Vec3(0.30, -0.20, 0.05), 2.0 * kPi / 180, -1.0 * kPi / 180, 6.0 * kPi / 180));
}

struct Pair {
  PointCloud reference, scan;
};

// The scan is a second sample of the room seen from the moved sensor: reference = T * scan.
Pair room_pair(std::uint64_t seed) {
  Rng rng(seed);
  Pair p;
  p.reference = voxel_downsample(test::synthetic_room(rng, 300, 0.005), 0.15);
  const PointCloud second = voxel_downsample(test::synthetic_room(rng, 300, 0.005), 0.15);
  p.scan = transform_cloud(second, known_motion().inverse());
  return p;
}

struct Tolerance {
  const char* name;
  std::vector<ParamSetting> settings;
  double metres, degrees;
};

ParamSetting setting(const std::string& key, const std::string& value) {
  ParamSetting s;
  s.key = key;
  s.value = value;
  s.field = key;
  return s;
}

TEST(Registration, EveryMatcherRecoversAKnownTransform) {
  const Pair pair = room_pair(21);
  const std::vector<Tolerance> cases = {
      {"icp", {}, 0.03, 0.3},
      {"icp", {setting("metric", "point_to_plane")}, 0.01, 0.1},
      {"gicp", {}, 0.01, 0.1},
      {"vgicp", {}, 0.01, 0.1},
      {"ndt", {}, 0.02, 0.2},
      {"ndt_mt", {}, 0.02, 0.2},
  };
  for (const Tolerance& t : cases) {
    SCOPED_TRACE(std::string(t.name) + (t.settings.empty() ? "" : " " + t.settings[0].value));
    auto matcher = find_scan_matcher_3d(t.name).make({}, t.settings);
    const CloudMatch m = register_clouds(*matcher, pair.reference, pair.scan);
    const Rigid3 error = known_motion().inverse() * m.transform;
    EXPECT_TRUE(m.converged);
    EXPECT_LT(translation_norm(error), t.metres);
    EXPECT_LT(rotation_angle(error) * 180 / kPi, t.degrees);
    EXPECT_LT(m.fitness, 0.01);  // aligned: mean squared distance well under (10 cm)^2
    EXPECT_GT(m.iterations, 1);
    EXPECT_GE(m.time_s, 0.0);
  }
}

TEST(Registration, AGoodGuessConvergesAtOnceAndTheFitnessNoticesABadOne) {
  const Pair pair = room_pair(22);
  GicpMatcher gicp(GicpConfig{});
  gicp.set_reference(pair.reference);
  const CloudMatch at_truth = gicp.match(pair.scan, known_motion());
  EXPECT_LT(translation_norm(known_motion().inverse() * at_truth.transform), 0.01);
  EXPECT_LE(at_truth.iterations, 5);
  const KdTree3 tree(pair.reference);
  Rigid3 off = known_motion();
  off.translation() += Vec3(0.5, 0, 0);
  EXPECT_GT(fitness_score(tree, pair.scan, off, 5.0), 10 * at_truth.fitness);
}

TEST(Registration, ParallelNdtReturnsExactlyTheSingleThreadedResult) {
  const Pair pair = room_pair(23);
  NdtConfig c;
  NdtMatcher one(c);
  c.threads = 3;
  NdtMatcher three(c, "ndt_mt");
  EXPECT_EQ(three.threads(), 3u);
  const CloudMatch a = register_clouds(one, pair.reference, pair.scan);
  const CloudMatch b = register_clouds(three, pair.reference, pair.scan);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_TRUE(a.transform.matrix() == b.transform.matrix());
  // GICP and point-to-plane ICP sum the same way.
  GicpConfig g;
  GicpMatcher g1(g);
  g.threads = 2;
  GicpMatcher g2(g);
  EXPECT_TRUE(register_clouds(g1, pair.reference, pair.scan).transform.matrix() ==
              register_clouds(g2, pair.reference, pair.scan).transform.matrix());
}

TEST(Registration, NdtVoxelsHoldTheMeanAndCovarianceOfTheirPoints) {
  // Eight points in one voxel of side 1: the mean and the (m - 1) covariance, regularised.
  PointCloud pts;
  for (int i = 0; i < 8; ++i) pts.emplace_back(0.1 + 0.1 * i, 0.5 + 0.02 * (i % 2), 0.5 + 0.03 * (i % 3));
  const NdtVoxels voxels(pts, 1.0, 6);
  ASSERT_EQ(voxels.size(), 1u);
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : pts) mean += p;
  mean /= 8.0;
  const NdtVoxels::Voxel* v = voxels.find(pts[0]);
  ASSERT_NE(v, nullptr);
  EXPECT_LT((v->mean - mean).norm(), 1e-12);
  EXPECT_EQ(voxels.find(pts[0], 1, 0, 0), nullptr);
  EXPECT_EQ(NdtVoxels(pts, 1.0, 9).size(), 0u);  // too few points
}

TEST(Registration, BadInputGetsClearErrors) {
  IcpMatcher icp(IcpConfig{});
  EXPECT_THROW(icp.match(PointCloud{{0, 0, 0}}, Rigid3::Identity()), Error);  // no reference yet
  EXPECT_THROW(icp.set_reference(PointCloud{{0, 0, 0}, {1, 0, 0}}), Error);
  NdtMatcher ndt(NdtConfig{});
  PointCloud sparse;
  for (int i = 0; i < 10; ++i) sparse.emplace_back(3.0 * i, 0, 0);  // one point per voxel
  try {
    ndt.set_reference(sparse);
    FAIL() << "a reference without a full voxel was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "resolution_m");
  }
  try {
    (void)find_scan_matcher_3d("ndt").make({"x.yaml"}, std::vector<ParamSetting>{setting("resolution_m", "0")});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("resolution_m"), std::string::npos);
  }
  EXPECT_THROW(find_scan_matcher_3d("loam"), Error);
}

}  // namespace
}  // namespace starnav
