#pragma once
// Independent references for the ray-casting tests: inside/outside predicates written from the
// primitives' definitions (not from starnav's intersection code), and a march + bisection root
// finder that turns any such predicate into a first-crossing distance.
#include <cmath>
#include <functional>
#include <limits>
#include <utility>
#include <optional>

#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/sim/primitives.hpp"

namespace starnav::test {

inline Eigen::Matrix3d rpy_rotation(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  Eigen::Matrix3d rx, ry, rz;
  rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  return rz * ry * rx;
}

// Inside-or-on predicate of a primitive, from its definition.
inline bool inside(const Primitive& prim, const Vec3& p) {
  if (const Box* b = std::get_if<Box>(&prim)) {
    const Vec3 l = rpy_rotation(b->roll, b->pitch, b->yaw).transpose() * (p - b->center);
    return std::abs(l.x()) <= 0.5 * b->size.x() && std::abs(l.y()) <= 0.5 * b->size.y() &&
           std::abs(l.z()) <= 0.5 * b->size.z();
  }
  if (const Cylinder* c = std::get_if<Cylinder>(&prim)) {
    const double dx = p.x() - c->base.x(), dy = p.y() - c->base.y(), dz = p.z() - c->base.z();
    return dx * dx + dy * dy <= c->radius * c->radius && dz >= 0.0 && dz <= c->height;
  }
  if (const Prism* q = std::get_if<Prism>(&prim)) {
    const Vec3 l = rpy_rotation(0, 0, q->yaw).transpose() * (p - q->base);
    if (std::abs(l.y()) > 0.5 * q->length || l.z() < 0.0 || l.z() > q->height) return false;
    const double u = l.z() / q->height;  // 0 at the base, 1 at the apex
    const double left = -0.5 * q->base_width + u * (q->apex_offset + 0.5 * q->base_width);
    const double right = 0.5 * q->base_width + u * (q->apex_offset - 0.5 * q->base_width);
    return l.x() >= left && l.x() <= right;
  }
  const Sphere& s = std::get<Sphere>(prim);
  return (p - s.center).squaredNorm() <= s.radius * s.radius;
}

// First s in [0, max_range] where pred(origin + s dir) differs from its value at s = 0,
// found by marching with `step` over [from, max_range] and bisecting to ~1e-13 (`from` > 0 only
// when pred cannot change before it). Nothing when no change is seen.
inline std::optional<double> march_bisect(const std::function<bool(const Vec3&)>& pred, const Vec3& origin,
                                          const Vec3& dir, double max_range, double step, double from = 0.0) {
  const bool start = pred(origin);
  double prev = from;
  for (double s = from + step;; s += step) {
    const double sc = std::min(s, max_range);
    if (pred(origin + sc * dir) != start) {
      double lo = prev, hi = sc;
      for (int i = 0; i < 200 && hi - lo > 1e-13; ++i) {
        const double mid = 0.5 * (lo + hi);
        (pred(origin + mid * dir) != start ? hi : lo) = mid;
      }
      return 0.5 * (lo + hi);
    }
    if (sc >= max_range) return std::nullopt;
    prev = sc;
  }
}

// The part [s0, s1] of the ray origin + s dir inside a box (s0 > s1 when it misses).
inline std::pair<double, double> ray_box(const Vec3& lo, const Vec3& hi, const Vec3& o, const Vec3& d) {
  double s0 = 0.0, s1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return {1.0, 0.0};
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    s0 = std::max(s0, ta);
    s1 = std::min(s1, tb);
  }
  return {s0, s1};
}

inline Vec3 random_unit(Rng& rng) {
  for (;;) {
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const double n = v.norm();
    if (n > 1e-3 && n <= 1.0) return v / n;
  }
}

}  // namespace starnav::test
