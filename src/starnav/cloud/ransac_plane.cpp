#include "starnav/cloud/ransac_plane.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Eigenvalues>

#include "starnav/core/error.hpp"

namespace starnav {

void RansacPlaneConfig::validate() const {
  require_positive(distance_threshold_m, "distance_threshold_m");
  require(iterations >= 1 && iterations <= 1000000, "iterations", "must be in [1, 1000000]");
  require(min_inliers >= 3, "min_inliers", "must be >= 3");
  require(std::isfinite(axis.norm()) && axis.norm() > 0, "axis", "must be a non-zero vector");
  require(!std::isnan(max_axis_angle_rad) && max_axis_angle_rad >= 0, "max_axis_angle", "must be >= 0");
}

void LeastMedianPlaneConfig::validate() const {
  require(iterations >= 1 && iterations <= 1000000, "iterations", "must be in [1, 1000000]");
  require(stride >= 1, "stride", "must be >= 1");
  require(std::isfinite(axis.norm()) && axis.norm() > 0, "axis", "must be a non-zero vector");
  require(!std::isnan(max_axis_angle_rad) && max_axis_angle_rad >= 0, "max_axis_angle", "must be >= 0");
}

namespace {

bool plane_accepted(const Plane3& p, const Vec3& axis, double max_angle) {
  if (!std::isfinite(max_angle)) return true;
  return std::acos(std::min(1.0, std::abs(p.normal.dot(axis)))) <= max_angle;
}

Plane3 oriented(Plane3 p, const Vec3& axis) {
  if (p.normal.dot(axis) < 0) {
    p.normal = -p.normal;
    p.d = -p.d;
  }
  return p;
}

// The plane through three random points of `points`, unless they are repeated or collinear or
// the plane's normal is further than `max_angle` from +-axis.
std::optional<Plane3> sample_plane(std::span<const Vec3> points, Rng& rng, const Vec3& axis, double max_angle) {
  const auto n = static_cast<std::int64_t>(points.size());
  const Vec3& a = points[static_cast<std::size_t>(rng.uniform_int(0, n - 1))];
  const Vec3& b = points[static_cast<std::size_t>(rng.uniform_int(0, n - 1))];
  const Vec3& c = points[static_cast<std::size_t>(rng.uniform_int(0, n - 1))];
  const Vec3 normal = (b - a).cross(c - a);
  const double len = normal.norm();
  if (!(len > 1e-12)) return std::nullopt;
  Plane3 p{normal / len, 0.0};
  p.d = -p.normal.dot(a);
  if (!plane_accepted(p, axis, max_angle)) return std::nullopt;
  return p;
}

void collect_inliers(std::span<const Vec3> points, const Plane3& plane, double threshold, RansacPlane& out) {
  out.inliers.clear();
  double sq = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double e = plane.signed_distance(points[i]);
    if (std::abs(e) <= threshold) {
      out.inliers.push_back(static_cast<std::uint32_t>(i));
      sq += e * e;
    }
  }
  out.rms_m = out.inliers.empty() ? 0.0 : std::sqrt(sq / static_cast<double>(out.inliers.size()));
}

}  // namespace

RansacPlane fit_plane_tls(std::span<const Vec3> points) {
  RansacPlane r;
  if (points.size() < 3) return r;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d ev = eig.eigenvalues();
  if (!(ev(1) > 1e-12 * std::max(ev(2), 1e-300))) return r;  // collinear
  r.plane.normal = eig.eigenvectors().col(0).normalized();
  r.plane.d = -r.plane.normal.dot(mean);
  r.found = true;
  double sq = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double e = r.plane.signed_distance(points[i]);
    sq += e * e;
    r.inliers.push_back(static_cast<std::uint32_t>(i));
  }
  r.rms_m = std::sqrt(sq / static_cast<double>(points.size()));
  return r;
}

RansacPlane ransac_plane(std::span<const Vec3> points, const RansacPlaneConfig& config, Rng& rng) {
  config.validate();
  const Vec3 axis = config.axis.normalized();
  RansacPlane best;
  if (points.size() < std::max<std::size_t>(3, config.min_inliers)) return best;
  std::size_t best_count = 0;
  Plane3 best_plane;
  for (int it = 0; it < config.iterations; ++it) {
    const std::optional<Plane3> sampled = sample_plane(points, rng, axis, config.max_axis_angle_rad);
    if (!sampled) continue;
    const Plane3& candidate = *sampled;
    std::size_t count = 0;
    for (const Vec3& p : points) count += std::abs(candidate.signed_distance(p)) <= config.distance_threshold_m;
    if (count > best_count) {
      best_count = count;
      best_plane = candidate;
    }
  }
  if (best_count < config.min_inliers) return best;
  // Refit to the inliers (twice: the refitted plane can gather a few more), keeping the sample's
  // plane when the refit would leave the allowed tilt.
  collect_inliers(points, best_plane, config.distance_threshold_m, best);
  for (int round = 0; round < 2; ++round) {
    std::vector<Vec3> in;
    in.reserve(best.inliers.size());
    for (std::uint32_t i : best.inliers) in.push_back(points[i]);
    const RansacPlane refit = fit_plane_tls(in);
    if (!refit.found || !plane_accepted(refit.plane, axis, config.max_axis_angle_rad)) break;
    RansacPlane next;
    collect_inliers(points, refit.plane, config.distance_threshold_m, next);
    if (next.inliers.size() < best.inliers.size()) break;
    best_plane = refit.plane;
    best.inliers = std::move(next.inliers);
    best.rms_m = next.rms_m;
  }
  best.plane = oriented(best_plane, axis);
  best.found = best.inliers.size() >= config.min_inliers;
  return best;
}

namespace {

double median_distance(std::span<const Vec3> points, const Plane3& plane, std::size_t stride, std::vector<double>& scratch) {
  scratch.clear();
  for (std::size_t i = 0; i < points.size(); i += stride) scratch.push_back(std::abs(plane.signed_distance(points[i])));
  const auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  return *mid;
}

}  // namespace

LeastMedianPlane least_median_plane(std::span<const Vec3> points, const LeastMedianPlaneConfig& config, Rng& rng) {
  config.validate();
  LeastMedianPlane best;
  if (points.size() < 3) return best;
  const Vec3 axis = config.axis.normalized();
  std::vector<double> scratch;
  double best_median = kInfinity;
  for (int it = 0; it < config.iterations; ++it) {
    const std::optional<Plane3> sampled = sample_plane(points, rng, axis, config.max_axis_angle_rad);
    if (!sampled) continue;
    const Plane3& candidate = *sampled;
    const double m = median_distance(points, candidate, config.stride, scratch);
    if (m < best_median) {
      best_median = m;
      best.plane = candidate;
      best.found = true;
    }
  }
  if (!best.found) return best;
  best.median_distance_m = median_distance(points, best.plane, 1, scratch);
  // Refit to the better half while that lowers the median.
  for (int round = 0; round < 10; ++round) {
    std::vector<Vec3> half;
    for (const Vec3& p : points)
      if (std::abs(best.plane.signed_distance(p)) <= best.median_distance_m) half.push_back(p);
    const RansacPlane refit = fit_plane_tls(half);
    if (!refit.found || !plane_accepted(refit.plane, axis, config.max_axis_angle_rad)) break;
    const double m = median_distance(points, refit.plane, 1, scratch);
    if (!(m < best.median_distance_m)) break;
    best.plane = refit.plane;
    best.median_distance_m = m;
  }
  best.plane = oriented(best.plane, axis);
  return best;
}

}  // namespace starnav
