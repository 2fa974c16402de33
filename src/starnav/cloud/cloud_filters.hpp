#pragma once
// The three filters of Ou et al. 2022 (Fig. 9), as hdl_graph_slam's prefilter runs them with PCL:
// a range and height window (ConditionalRemoval), a voxel grid (VoxelGrid: one point per occupied
// voxel, the centroid of the points in it) and radius outlier removal (RadiusOutlierRemoval: keep
// points with at least `min_neighbours` others within `radius`). Output order is deterministic:
// the window and the outlier filter keep input order, the voxel grid sorts by voxel index.
#include <cstddef>
#include <span>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/core/params.hpp"

namespace starnav {

struct RangeWindow {
  double min_range_m = 0.1;    // distance from the sensor's origin
  double max_range_m = 500.0;
  double min_z_m = -kInfinity;  // height in the cloud's frame
  double max_z_m = kInfinity;
};
// Points with min_range <= |p| <= max_range and min_z <= z <= max_z. Throws Error for an empty or
// non-finite window.
PointCloud crop_range_height(std::span<const Vec3> points, const RangeWindow& window);

// One point per voxel of side `leaf_m` (voxel (i, j, k) holds floor(p / leaf)), the centroid of
// its points, in order of (k, j, i). Throws Error for leaf_m not > 0 or a cloud whose extent
// over leaf_m would overflow the voxel index.
PointCloud voxel_downsample(std::span<const Vec3> points, double leaf_m);

// Points with at least `min_neighbours` other points within `radius_m`.
PointCloud remove_radius_outliers(std::span<const Vec3> points, double radius_m, std::size_t min_neighbours);

// The three in the paper's order, with the sizes after each step (Fig. 9).
struct PrefilterConfig {
  RangeWindow window;
  double voxel_leaf_m = 0.1;          // 0: no voxel grid
  double outlier_radius_m = 0.5;      // 0: no outlier removal
  std::size_t outlier_min_neighbours = 2;
  void validate() const;
};
struct PrefilterCounts {
  std::size_t raw = 0, windowed = 0, voxelised = 0, kept = 0;
};
PointCloud prefilter_cloud(std::span<const Vec3> points, const PrefilterConfig& config, PrefilterCounts* counts = nullptr);

// The prefilter's declared parameters: min_range_m, max_range_m, voxel_leaf_m, outlier_radius_m,
// outlier_min_neighbours (3D SLAM's section declares them; the Python bindings' prefilter takes them).
const ParamTable<PrefilterConfig>& prefilter_params();

}  // namespace starnav
