#pragma once
// A synthetic indoor scene for the registration tests: a floor, three walls and two boxes,
// sampled uniformly at random on their surfaces (a different sample per call, as two scans of a
// room never hit the same points), with optional range noise.
#include <vector>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/core/rng.hpp"

namespace starnav::test {

inline PointCloud synthetic_room(Rng& rng, int points_per_m2, double noise_sigma_m = 0.0) {
  PointCloud cloud;
  auto patch = [&](const Vec3& origin, const Vec3& u, const Vec3& v) {
    const double area = u.cross(v).norm();
    const int n = static_cast<int>(area * points_per_m2);
    for (int i = 0; i < n; ++i) {
      Vec3 p = origin + rng.uniform() * u + rng.uniform() * v;
      if (noise_sigma_m > 0) p += Vec3(rng.normal(0, noise_sigma_m), rng.normal(0, noise_sigma_m), rng.normal(0, noise_sigma_m));
      cloud.push_back(p);
    }
  };
  auto box = [&](const Vec3& lo, const Vec3& size) {
    const Vec3 ex(size.x(), 0, 0), ey(0, size.y(), 0), ez(0, 0, size.z());
    patch(lo, ex, ez);
    patch(lo + ey, ex, ez);
    patch(lo, ey, ez);
    patch(lo + ex, ey, ez);
    patch(lo + ez, ex, ey);
  };
  patch({-6, -5, 0}, {12, 0, 0}, {0, 10, 0});  // floor
  patch({6, -5, 0}, {0, 10, 0}, {0, 0, 3});    // walls
  patch({-6, 5, 0}, {12, 0, 0}, {0, 0, 3});
  patch({-6, -5, 0}, {12, 0, 0}, {0, 0, 3});
  box({1.0, 1.5, 0.0}, {1.0, 0.8, 1.2});
  box({-2.5, -2.0, 0.0}, {0.6, 1.5, 0.8});
  return cloud;
}

}  // namespace starnav::test
