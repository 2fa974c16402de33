#include "starnav/cloud/cloud_filters.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "starnav/cloud/kd_tree.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

PointCloud crop_range_height(std::span<const Vec3> points, const RangeWindow& w) {
  require(std::isfinite(w.min_range_m) && w.min_range_m >= 0 && std::isfinite(w.max_range_m) &&
              w.max_range_m >= w.min_range_m,
          "range", "needs 0 <= min_range <= max_range, both finite");
  require(!std::isnan(w.min_z_m) && !std::isnan(w.max_z_m) && w.max_z_m >= w.min_z_m, "height",
          "needs min_z <= max_z");
  const double lo2 = w.min_range_m * w.min_range_m, hi2 = w.max_range_m * w.max_range_m;
  PointCloud out;
  out.reserve(points.size());
  for (const Vec3& p : points) {
    const double r2 = p.squaredNorm();
    if (r2 >= lo2 && r2 <= hi2 && p.z() >= w.min_z_m && p.z() <= w.max_z_m) out.push_back(p);
  }
  return out;
}

PointCloud voxel_downsample(std::span<const Vec3> points, double leaf_m) {
  require(std::isfinite(leaf_m) && leaf_m > 0, "voxel_leaf_m", "must be > 0");
  if (points.empty()) return {};
  const CloudBounds b = cloud_bounds(points);
  const double inv = 1.0 / leaf_m;
  const Vec3 lo = (b.min * inv).array().floor();
  const Vec3 span = (b.max * inv).array().floor() - lo.array() + 1.0;
  // 21 bits per axis: a key of 63 bits, sortable as one integer.
  constexpr double kAxisVoxels = double(1 << 21);
  require(span.x() <= kAxisVoxels && span.y() <= kAxisVoxels && span.z() <= kAxisVoxels, "voxel_leaf_m",
          "too small for the cloud's extent (more than 2^21 voxels along an axis)");
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 v = (points[i] * inv).array().floor() - lo.array();
    const auto ix = static_cast<std::uint64_t>(v.x()), iy = static_cast<std::uint64_t>(v.y()),
               iz = static_cast<std::uint64_t>(v.z());
    keyed[i] = {(iz << 42) | (iy << 21) | ix, static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  PointCloud out;
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i;
    Vec3 sum = Vec3::Zero();
    while (j < keyed.size() && keyed[j].first == keyed[i].first) sum += points[keyed[j++].second];
    out.push_back(sum / static_cast<double>(j - i));
    i = j;
  }
  return out;
}

PointCloud remove_radius_outliers(std::span<const Vec3> points, double radius_m, std::size_t min_neighbours) {
  require(std::isfinite(radius_m) && radius_m > 0, "outlier_radius_m", "must be > 0");
  if (points.empty()) return {};
  const KdTree3 tree(points);
  PointCloud out;
  out.reserve(points.size());
  for (const Vec3& p : points) {
    // The point itself is within the radius: count one more than the neighbours wanted.
    if (tree.count_within_radius(p, radius_m, min_neighbours + 1) >= min_neighbours + 1) out.push_back(p);
  }
  return out;
}

void PrefilterConfig::validate() const {
  require(std::isfinite(window.min_range_m) && window.min_range_m >= 0, "min_range_m", "must be >= 0");
  require(std::isfinite(window.max_range_m) && window.max_range_m >= window.min_range_m, "max_range_m",
          "must be finite and >= min_range_m");
  require(!std::isnan(window.min_z_m) && !std::isnan(window.max_z_m) && window.max_z_m >= window.min_z_m, "max_z_m",
          "must be >= min_z_m");
  require(std::isfinite(voxel_leaf_m) && voxel_leaf_m >= 0, "voxel_leaf_m", "must be >= 0");
  require(std::isfinite(outlier_radius_m) && outlier_radius_m >= 0, "outlier_radius_m", "must be >= 0");
  require(outlier_min_neighbours <= 1000, "outlier_min_neighbours", "must be <= 1000");
}

PointCloud prefilter_cloud(std::span<const Vec3> points, const PrefilterConfig& config, PrefilterCounts* counts) {
  config.validate();
  PointCloud cloud = crop_range_height(points, config.window);
  const std::size_t windowed = cloud.size();
  if (config.voxel_leaf_m > 0) cloud = voxel_downsample(cloud, config.voxel_leaf_m);
  const std::size_t voxelised = cloud.size();
  if (config.outlier_radius_m > 0 && config.outlier_min_neighbours > 0)
    cloud = remove_radius_outliers(cloud, config.outlier_radius_m, config.outlier_min_neighbours);
  if (counts) *counts = {points.size(), windowed, voxelised, cloud.size()};
  return cloud;
}

const ParamTable<PrefilterConfig>& prefilter_params() {
  static const ParamTable<PrefilterConfig> table = [] {
    using C = PrefilterConfig;
    ParamTable<C> t;
    t.real("min_range_m", [](C& c) -> double& { return c.window.min_range_m; }, closed(0.0, 100.0), "m",
           "prefilter: points nearer the sensor are dropped (the robot's body)");
    t.real("max_range_m", [](C& c) -> double& { return c.window.max_range_m; }, closed(0.1, 1000.0), "m",
           "prefilter: points further away are dropped");
    t.real("voxel_leaf_m", &C::voxel_leaf_m, closed(0.0, 5.0), "m", "prefilter: voxel grid leaf (0: none)");
    t.real("outlier_radius_m", &C::outlier_radius_m, closed(0.0, 10.0), "m",
           "prefilter: radius outlier removal radius (0: none)");
    t.integer("outlier_min_neighbours", &C::outlier_min_neighbours, closed(0, 1000), "",
              "prefilter: neighbours a point needs within the radius");
    return t;
  }();
  return table;
}

}  // namespace starnav
