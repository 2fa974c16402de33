#pragma once
// A plane found by RANSAC among outliers (Fischler and Bolles 1981): planes through three random
// points, scored by their inliers within a distance, the best refitted to its inliers by total
// least squares (the normal is the smallest principal axis). Optionally only planes whose normal
// is within an angle of a direction count (hdl_graph_slam's floor detection: within 20 degrees of
// vertical). The random draws come from the caller's Rng.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"

namespace starnav {

// normal . p + d = 0 with |normal| = 1.
struct Plane3 {
  Vec3 normal = Vec3::UnitZ();
  double d = 0.0;
  double signed_distance(const Vec3& p) const { return normal.dot(p) + d; }
};

struct RansacPlaneConfig {
  double distance_threshold_m = 0.1;
  int iterations = 200;
  std::size_t min_inliers = 3;
  Vec3 axis = Vec3::UnitZ();    // the normal is oriented to have a positive component along it
  double max_axis_angle_rad = kInfinity;  // planes whose normal is further from +-axis are rejected
  void validate() const;
};

struct RansacPlane {
  bool found = false;
  Plane3 plane;
  std::vector<std::uint32_t> inliers;  // indices into the input, ascending
  double rms_m = 0.0;                  // RMS distance of the inliers to the plane
};

RansacPlane ransac_plane(std::span<const Vec3> points, const RansacPlaneConfig& config, Rng& rng);

// The least-median-of-squares plane (Rousseeuw 1984): of `iterations` planes through three random
// points (each within `max_axis_angle_rad` of `axis`), the one whose median distance to the points
// is smallest, then refitted by total least squares to the points within that median while that
// lowers it. The median is taken over every `stride`-th point while searching, over all at the
// end. A measure of how planar a point set is (half its points lie within the median), not a
// detector: it has no threshold.
struct LeastMedianPlaneConfig {
  int iterations = 2000;
  std::size_t stride = 1;
  Vec3 axis = Vec3::UnitZ();
  double max_axis_angle_rad = kInfinity;
  void validate() const;
};
struct LeastMedianPlane {
  bool found = false;
  Plane3 plane;
  double median_distance_m = 0.0;
};
LeastMedianPlane least_median_plane(std::span<const Vec3> points, const LeastMedianPlaneConfig& config, Rng& rng);

// The total-least-squares plane through `points` (at least 3, not collinear); found false otherwise.
RansacPlane fit_plane_tls(std::span<const Vec3> points);

}  // namespace starnav
