// The point-cloud building blocks against brute force and closed forms: the k-d tree, the three
// filters, local shapes, RANSAC, the thread pool.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <set>

#include "cloud/synthetic_scene.hpp"
#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/kd_tree.hpp"
#include "starnav/cloud/local_shape.hpp"
#include "starnav/cloud/ransac_plane.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav {
namespace {

PointCloud random_cloud(Rng& rng, int n, double extent) {
  PointCloud c;
  for (int i = 0; i < n; ++i) c.emplace_back(rng.uniform(-extent, extent), rng.uniform(-extent, extent), rng.uniform(-extent, extent));
  return c;
}

TEST(KdTree3, NearestKNearestAndRadiusAgreeWithBruteForce) {
  Rng rng(7);
  const PointCloud cloud = random_cloud(rng, 2000, 5.0);
  const KdTree3 tree(cloud);
  std::vector<Neighbour> got;
  for (int q = 0; q < 200; ++q) {
    const Vec3 query(rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-6, 6));
    std::vector<std::pair<double, std::uint32_t>> all;
    for (std::size_t i = 0; i < cloud.size(); ++i) all.emplace_back((cloud[i] - query).squaredNorm(), static_cast<std::uint32_t>(i));
    std::sort(all.begin(), all.end());
    Neighbour nn;
    ASSERT_TRUE(tree.nearest(query, nn));
    EXPECT_EQ(nn.index, all[0].second);
    EXPECT_DOUBLE_EQ(nn.squared_distance, all[0].first);
    tree.k_nearest(query, 7, got);
    ASSERT_EQ(got.size(), 7u);
    for (int k = 0; k < 7; ++k) EXPECT_EQ(got[static_cast<std::size_t>(k)].index, all[static_cast<std::size_t>(k)].second);
    const double r = rng.uniform(0.2, 1.5);
    tree.within_radius(query, r, got);
    std::size_t expected = 0;
    while (expected < all.size() && all[expected].first <= r * r) ++expected;
    ASSERT_EQ(got.size(), expected);
    for (std::size_t k = 0; k < expected; ++k) EXPECT_EQ(got[k].index, all[k].second);
    EXPECT_EQ(tree.count_within_radius(query, r), expected);
    EXPECT_EQ(tree.count_within_radius(query, r, 3), std::min<std::size_t>(expected, 3));
  }
}

TEST(KdTree3, RadiusIsInclusiveAndEmptyTreesAnswerNothing) {
  const PointCloud cloud = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const KdTree3 tree(cloud);
  EXPECT_EQ(tree.count_within_radius({0, 0, 0}, 1.0), 2u);  // the point at exactly 1 m counts
  const KdTree3 empty(PointCloud{});
  Neighbour nn;
  EXPECT_FALSE(empty.nearest({0, 0, 0}, nn));
  std::vector<Neighbour> got;
  empty.k_nearest({0, 0, 0}, 3, got);
  EXPECT_TRUE(got.empty());
}

TEST(CloudFilters, RangeHeightWindowKeepsExactlyThePointsInside) {
  Rng rng(3);
  const PointCloud cloud = random_cloud(rng, 3000, 10.0);
  RangeWindow w;
  w.min_range_m = 2.0;
  w.max_range_m = 8.0;
  w.min_z_m = -1.0;
  w.max_z_m = 3.0;
  const PointCloud out = crop_range_height(cloud, w);
  PointCloud expected;
  for (const Vec3& p : cloud)
    if (p.norm() >= 2.0 && p.norm() <= 8.0 && p.z() >= -1.0 && p.z() <= 3.0) expected.push_back(p);
  EXPECT_EQ(out, expected);
  w.max_range_m = 1.0;
  EXPECT_THROW(crop_range_height(cloud, w), Error);
}

TEST(CloudFilters, VoxelGridGivesTheCentroidOfEveryOccupiedVoxel) {
  Rng rng(5);
  const PointCloud cloud = random_cloud(rng, 5000, 3.0);
  const double leaf = 0.7;
  std::map<std::tuple<long, long, long>, std::pair<Vec3, int>> voxels;
  for (const Vec3& p : cloud) {
    auto& v = voxels[{std::lround(std::floor(p.x() / leaf)), std::lround(std::floor(p.y() / leaf)), std::lround(std::floor(p.z() / leaf))}];
    if (v.second == 0) v.first = Vec3::Zero();
    v.first += p;
    ++v.second;
  }
  const PointCloud out = voxel_downsample(cloud, leaf);
  ASSERT_EQ(out.size(), voxels.size());
  // Same set of centroids (the output is ordered by z, y, x voxel index).
  std::vector<Vec3> expected;
  for (const auto& [key, v] : voxels) expected.push_back(v.first / v.second);
  auto less = [](const Vec3& a, const Vec3& b) { return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z()); };
  std::vector<Vec3> got(out.begin(), out.end());
  std::sort(expected.begin(), expected.end(), less);
  std::sort(got.begin(), got.end(), less);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_LT((got[i] - expected[i]).norm(), 1e-12);
  EXPECT_THROW(voxel_downsample(cloud, 0.0), Error);
  EXPECT_THROW(voxel_downsample(PointCloud{{0, 0, 0}, {1e9, 0, 0}}, 1e-4), Error);  // index overflow refused
}

TEST(CloudFilters, RadiusOutlierRemovalAgreesWithBruteForce) {
  Rng rng(11);
  const PointCloud cloud = random_cloud(rng, 1500, 4.0);
  const double r = 0.45;
  const std::size_t k = 2;
  PointCloud expected;
  for (const Vec3& p : cloud) {
    std::size_t n = 0;
    for (const Vec3& q : cloud) n += (&p != &q) && (p - q).norm() <= r;
    if (n >= k) expected.push_back(p);
  }
  EXPECT_EQ(remove_radius_outliers(cloud, r, k), expected);
  EXPECT_GT(expected.size(), 100u);
  EXPECT_LT(expected.size(), cloud.size());
}

TEST(CloudFilters, PrefilterCountsEachStage) {
  Rng rng(2);
  const PointCloud cloud = test::synthetic_room(rng, 400);
  PrefilterConfig c;
  c.window.max_range_m = 6.0;
  PrefilterCounts counts;
  const PointCloud out = prefilter_cloud(cloud, c, &counts);
  EXPECT_EQ(counts.raw, cloud.size());
  EXPECT_LT(counts.windowed, counts.raw);
  EXPECT_LT(counts.voxelised, counts.windowed);
  EXPECT_LE(counts.kept, counts.voxelised);
  EXPECT_EQ(counts.kept, out.size());
}

TEST(LocalShape, NormalsOfAPlaneAreItsNormalTowardsTheOrigin) {
  Rng rng(4);
  PointCloud plane;
  const Vec3 n = Vec3(0.2, -0.1, 1.0).normalized();
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  for (int i = 0; i < 500; ++i) plane.push_back(Vec3(0, 0, -2) + rng.uniform(-3, 3) * u + rng.uniform(-3, 3) * v);
  const KdTree3 tree(plane);
  for (const LocalShape& s : local_shapes(tree, 10)) {
    ASSERT_TRUE(s.valid);
    EXPECT_GT(s.normal.dot(n), 1 - 1e-9);  // the plane lies below the origin: the normal points up
  }
  const Eigen::Matrix3d reg = plane_regularised(Eigen::Vector3d(4.0, 2.0, 0.01).asDiagonal(), 1e-3);
  EXPECT_NEAR(reg(2, 2), 1e-3, 1e-12);
  EXPECT_NEAR(reg(0, 0), 1.0, 1e-12);
}

TEST(RansacPlane, FindsAKnownPlaneAmongOutliers) {
  Rng rng(9);
  PointCloud cloud;
  const Vec3 n = Vec3(0.05, 0.03, 1.0).normalized();
  const double d = 1.7;
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  for (int i = 0; i < 600; ++i)
    cloud.push_back(-d * n + rng.uniform(-10, 10) * u + rng.uniform(-10, 10) * v + rng.normal(0, 0.01) * n);
  for (int i = 0; i < 900; ++i) cloud.emplace_back(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-1.5, 5));
  RansacPlaneConfig c;
  c.distance_threshold_m = 0.05;
  c.max_axis_angle_rad = 20 * kPi / 180;
  const RansacPlane r = ransac_plane(cloud, c, rng);
  ASSERT_TRUE(r.found);
  EXPECT_GT(r.plane.normal.dot(n), std::cos(0.2 * kPi / 180));
  EXPECT_NEAR(r.plane.d, d, 0.01);
  std::size_t true_inliers = 0;
  for (std::uint32_t i : r.inliers) true_inliers += i < 600;
  EXPECT_GE(true_inliers, 590u);
  EXPECT_LT(r.inliers.size(), 700u);  // few of the outliers lie within 5 cm
  // A plane tilted beyond the allowed angle is not taken.
  c.max_axis_angle_rad = 0.5 * kPi / 180;
  PointCloud wall;
  for (int i = 0; i < 300; ++i) wall.emplace_back(3.0, rng.uniform(-5, 5), rng.uniform(0, 3));
  EXPECT_FALSE(ransac_plane(wall, c, rng).found);
}

TEST(RansacPlane, SameSeedSameAnswer) {
  Rng a(1), b(1), scene_rng(1);
  const PointCloud cloud = test::synthetic_room(scene_rng, 50, 0.01);
  RansacPlaneConfig c;
  const RansacPlane x = ransac_plane(cloud, c, a), y = ransac_plane(cloud, c, b);
  EXPECT_EQ(x.inliers, y.inliers);
  EXPECT_EQ(x.plane.d, y.plane.d);
}

TEST(LeastMedianPlane, RecoversTheMajorityPlaneAndItsMedianDistance) {
  // 60 % of the points on a tilted plane with uniform noise of +-2 cm (so the median distance of
  // those is 1 cm), 40 % on a parallel plane 0.3 m above: the least median is the first plane's,
  // about the 5/6 quantile of its noise (half of all points are 5/6 of the plane's), 1.67 cm.
  Rng rng(4);
  const Vec3 n = Vec3(0.02, -0.04, 1.0).normalized();
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  PointCloud cloud;
  for (int i = 0; i < 3000; ++i) cloud.push_back(-1.5 * n + rng.uniform(-8, 8) * u + rng.uniform(-8, 8) * v + rng.uniform(-0.02, 0.02) * n);
  for (int i = 0; i < 2000; ++i) cloud.push_back(-1.2 * n + rng.uniform(-8, 8) * u + rng.uniform(-8, 8) * v + rng.uniform(-0.02, 0.02) * n);
  LeastMedianPlaneConfig c;
  c.stride = 3;
  const LeastMedianPlane p = least_median_plane(cloud, c, rng);
  ASSERT_TRUE(p.found);
  EXPECT_GT(p.plane.normal.dot(n), std::cos(0.3 * kPi / 180));
  EXPECT_NEAR(p.plane.d, 1.5, 0.005);
  EXPECT_NEAR(p.median_distance_m, 0.02 * 5.0 / 6.0, 0.002);
  // Its median is a bound: the true plane's own median over all the points is no lower.
  std::vector<double> e;
  for (const Vec3& q : cloud) e.push_back(std::abs(n.dot(q) + 1.5));
  std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
  EXPECT_LE(p.median_distance_m, e[e.size() / 2] + 1e-3);
  // Same seed, same plane; a tilt limit that excludes the plane finds nothing.
  Rng a(7), b(7);
  EXPECT_EQ(least_median_plane(cloud, c, a).plane.d, least_median_plane(cloud, c, b).plane.d);
  PointCloud wall;
  for (int i = 0; i < 300; ++i) wall.emplace_back(3.0, rng.uniform(-5, 5), rng.uniform(0, 3));
  c.max_axis_angle_rad = 10 * kPi / 180;
  EXPECT_FALSE(least_median_plane(wall, c, rng).found);
}

TEST(ThreadPool, RunsEveryTaskOnceAndRethrows) {
  for (unsigned threads : {1U, 2U, 4U}) {
    ThreadPool pool(threads);
    for (int round = 0; round < 50; ++round) {
      std::vector<std::atomic<int>> hits(97);
      pool.run(hits.size(), [&](std::size_t i) { hits[i].fetch_add(1); });
      for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
    }
    EXPECT_THROW(pool.run(10, [](std::size_t i) { if (i == 7) throw Error("task 7"); }), Error);
    std::atomic<int> after{0};
    pool.run(5, [&](std::size_t) { after.fetch_add(1); });
    EXPECT_EQ(after.load(), 5);
  }
}

}  // namespace
}  // namespace starnav
