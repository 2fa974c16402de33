// The voxelised GICP: its voxel hash and per-voxel statistics against brute force, a known rigid
// transform recovered, the same answer on one thread and on two, and its parameters checked.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

#include "cloud/synthetic_scene.hpp"
#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/gicp.hpp"
#include "starnav/cloud/local_shape.hpp"
#include "starnav/cloud/vgicp.hpp"
#include "starnav/cloud/voxel_hash.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {
namespace vgicp_test {  // named: the unity build joins this file with the other registration tests

using Cell = std::tuple<long long, long long, long long>;

Cell cell_of(const Vec3& p, double res) {
  return {static_cast<long long>(std::floor(p.x() / res)), static_cast<long long>(std::floor(p.y() / res)),
          static_cast<long long>(std::floor(p.z() / res))};
}

ParamSetting setting(const std::string& key, const std::string& value) {
  ParamSetting s;
  s.key = key;
  s.value = value;
  s.field = key;
  return s;
}

TEST(VoxelHash, GivesTheIndicesOfFirstInsertionAsAMapDoes) {
  Rng rng(5);
  VoxelHash hash(0.5);
  std::map<std::uint64_t, std::uint32_t> truth;
  for (int i = 0; i < 5000; ++i) {
    // Few distinct cells among many points, so most inserts meet an existing voxel.
    const Vec3 p(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-2, 2));
    const std::uint64_t key = hash.key_of(p);
    ASSERT_NE(key, VoxelHash::kNoKey);
    const auto [c0, c1, c2] = cell_of(p, 0.5);
    ASSERT_EQ(key, VoxelHash::key_of_coords(c0, c1, c2));
    const auto expected = truth.emplace(key, static_cast<std::uint32_t>(truth.size())).first->second;
    ASSERT_EQ(hash.insert(key), expected);
  }
  EXPECT_EQ(hash.size(), truth.size());
  EXPECT_GT(truth.size(), 1000u);  // the table grew many times
  for (const auto& [key, index] : truth) EXPECT_EQ(hash.find(key), index);
  // Cells never inserted: beyond the sampled box, and a neighbour key of every inserted one.
  EXPECT_EQ(hash.find(hash.key_of(Vec3(0, 0, 3.1))), VoxelHash::kNone);
  std::size_t absent = 0;
  for (const auto& [key, index] : truth) {
    const std::uint64_t up = key + (std::uint64_t{1} << 42);  // one voxel up in z
    absent += truth.count(up) == 0;
    EXPECT_EQ(hash.find(up), truth.count(up) ? truth.at(up) : VoxelHash::kNone);
  }
  EXPECT_GT(absent, 0u);
  // Out of range and not finite: no key.
  EXPECT_EQ(hash.key_of(Vec3(0.5 * 2.0e6, 0, 0)), VoxelHash::kNoKey);
  EXPECT_EQ(hash.key_of(Vec3(std::nan(""), 0, 0)), VoxelHash::kNoKey);
  EXPECT_EQ(hash.find(VoxelHash::kNoKey), VoxelHash::kNone);
  EXPECT_THROW(hash.insert(VoxelHash::kNoKey), Error);
  EXPECT_EQ(hash.key_of(Vec3(-0.1, 0.2, 0.7)), VoxelHash::key_of_coords(-1, 0, 1));
}

TEST(Vgicp, VoxelsHoldTheMeanPointAndTheMeanCovarianceOfTheirPoints) {
  Rng rng(6);
  std::vector<Vec3> pts;
  std::vector<Eigen::Matrix3d> covs;
  for (int i = 0; i < 3000; ++i) {
    pts.emplace_back(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-1, 1));
    Eigen::Matrix3d a;
    for (int j = 0; j < 9; ++j) a.data()[j] = rng.uniform(-1, 1);
    covs.push_back(a * a.transpose());
  }
  const double res = 0.7;
  const GaussianVoxels voxels(pts, covs, res);
  // Brute force: sum by cell in an ordered map.
  struct Sum {
    Vec3 p = Vec3::Zero();
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    int n = 0;
  };
  std::map<Cell, Sum> sums;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Sum& s = sums[cell_of(pts[i], res)];
    s.p += pts[i];
    s.c += covs[i];
    ++s.n;
  }
  ASSERT_EQ(voxels.size(), sums.size());
  for (const Vec3& p : pts) {
    const Sum& s = sums.at(cell_of(p, res));
    const GaussianVoxels::Voxel* v = voxels.find(p);
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->points, static_cast<std::uint32_t>(s.n));
    EXPECT_LT((v->mean - s.p / s.n).norm(), 1e-12);
    EXPECT_LT((v->covariance - s.c / s.n).norm(), 1e-12);
    // A face neighbour is there exactly when the brute force has points in it.
    auto [x, y, z] = cell_of(p, res);
    EXPECT_EQ(voxels.find(p, 0, 0, 1) != nullptr, sums.count({x, y, z + 1}) == 1);
  }
}

Rigid3 known_motion() {
  return to_rigid(Pose3::from_rpy(Vec3(0.30, -0.20, 0.05), 2.0 * kPi / 180, -1.0 * kPi / 180, 6.0 * kPi / 180));
}

struct Pair {
  PointCloud reference, scan;
};

// Two independent samples of the room; the scan seen from the moved sensor: reference = T * scan.
Pair room_pair(std::uint64_t seed) {
  Rng rng(seed);
  Pair p;
  p.reference = voxel_downsample(test::synthetic_room(rng, 300, 0.005), 0.15);
  p.scan = transform_cloud(voxel_downsample(test::synthetic_room(rng, 300, 0.005), 0.15), known_motion().inverse());
  return p;
}

TEST(Vgicp, RecoversAKnownRigidTransform) {
  const Pair pair = room_pair(31);
  for (const char* neighbours : {"direct1", "direct7"}) {
    SCOPED_TRACE(neighbours);
    auto matcher = find_scan_matcher_3d("vgicp").make({}, std::vector<ParamSetting>{setting("neighbours", neighbours)});
    const CloudMatch m = register_clouds(*matcher, pair.reference, pair.scan);
    const Rigid3 error = known_motion().inverse() * m.transform;
    EXPECT_TRUE(m.converged);
    EXPECT_GT(m.iterations, 1);
    EXPECT_LT(translation_norm(error), 0.01);
    EXPECT_LT(rotation_angle(error) * 180 / kPi, 0.1);
    EXPECT_LT(m.fitness, 0.01);
  }
}

TEST(Vgicp, TwoThreadsGiveWhatOneDoes) {
  const Pair pair = room_pair(32);
  VgicpConfig c;
  VgicpMatcher one(c);
  c.threads = 2;
  VgicpMatcher two(c);
  EXPECT_EQ(two.threads(), 2u);
  const CloudMatch a = register_clouds(one, pair.reference, pair.scan);
  const CloudMatch b = register_clouds(two, pair.reference, pair.scan);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_LT((a.transform.matrix() - b.transform.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(a.fitness, b.fitness);
  GicpConfig g;
  GicpMatcher g1(g);
  g.threads = 2;
  GicpMatcher g2(g);
  EXPECT_EQ(g2.threads(), 2u);
  const CloudMatch ga = register_clouds(g1, pair.reference, pair.scan);
  const CloudMatch gb = register_clouds(g2, pair.reference, pair.scan);
  EXPECT_LT((ga.transform.matrix() - gb.transform.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(ga.fitness, gb.fitness);
}

TEST(Vgicp, DiscCovariancesAreTheRegularisedLocalShapesOnAnyPool) {
  Rng rng(7);
  const PointCloud cloud = voxel_downsample(test::synthetic_room(rng, 100, 0.01), 0.2);
  const KdTree3 tree(cloud);
  const std::vector<LocalShape> shapes = local_shapes(tree, 20);
  ThreadPool pool(2);
  const std::vector<Eigen::Matrix3d> serial = disc_covariances(tree, 20, 1e-3);
  const std::vector<Eigen::Matrix3d> parallel = disc_covariances(tree, 20, 1e-3, &pool);
  ASSERT_EQ(serial.size(), cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Matrix3d expected =
        shapes[i].valid ? plane_regularised(shapes[i].covariance, 1e-3) : Eigen::Matrix3d::Identity();
    // One pass against local_shapes' two: the same matrix to rounding.
    EXPECT_LT((serial[i] - expected).cwiseAbs().maxCoeff(), 1e-9) << i;
    EXPECT_TRUE(parallel[i] == serial[i]) << i;
  }
}

TEST(Vgicp, BadParametersGetOneClearError) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"voxel_resolution_m", "0"}, {"voxel_resolution_m", "nan"}, {"neighbours", "direct27"},
      {"max_correspondence_distance_m", "-1"}, {"covariance_neighbours", "2"}, {"threads", "-1"}, {"epsilon", "2"}};
  for (const auto& [key, value] : bad) {
    SCOPED_TRACE(key + "=" + value);
    try {
      (void)find_scan_matcher_3d("vgicp").make({"m.yaml"}, std::vector<ParamSetting>{setting(key, value)});
      FAIL() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  VgicpMatcher m{VgicpConfig{}};
  EXPECT_THROW(m.match(PointCloud{{0, 0, 0}}, Rigid3::Identity()), Error);  // no reference yet
  EXPECT_THROW(m.set_reference(PointCloud{{0, 0, 0}, {1, 0, 0}}), Error);
  PointCloud far;
  for (int i = 0; i < 10; ++i) far.emplace_back(1e5 * i, 0, 0);  // beyond 2^20 voxels of 0.01 m
  VgicpConfig fine;
  fine.voxel_resolution_m = 0.01;
  VgicpMatcher f(fine);
  try {
    f.set_reference(far);
    FAIL() << "a reference beyond the hash's range was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "voxel_resolution_m");
  }
}

}  // namespace vgicp_test
}  // namespace starnav
