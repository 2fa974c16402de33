#pragma once
// Independent polygon geometry for tests of layers built from polygons (keep-out, speed limits):
// Sutherland-Hodgman clipping by a convex polygon, the shoelace area, random simple polygons.
#include <algorithm>
#include <cmath>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"

namespace starnav::test {

// The part of `subject` inside the half-plane left of a -> b (one Sutherland-Hodgman step).
inline std::vector<Vec2> clip_left_of(const std::vector<Vec2>& subject, const Vec2& a, const Vec2& b) {
  const auto side = [&](const Vec2& p) { return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x()); };
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < subject.size(); ++i) {
    const Vec2 p = subject[i], q = subject[(i + 1) % subject.size()];
    const double sp = side(p), sq = side(q);
    if (sp >= 0) out.push_back(p);
    if ((sp >= 0) != (sq >= 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
  }
  return out;
}

inline double shoelace_area(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 p = poly[i], q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return std::abs(a) / 2.0;
}

// `subject` (simple) clipped by the convex counter-clockwise `box`.
inline std::vector<Vec2> clip_by_convex(const std::vector<Vec2>& subject, const std::vector<Vec2>& box) {
  std::vector<Vec2> part = subject;
  for (std::size_t k = 0; k < box.size() && !part.empty(); ++k) part = clip_left_of(part, box[k], box[(k + 1) % box.size()]);
  return part;
}

// The area of `zone` (simple) inside the convex counter-clockwise `box`.
inline double overlap_area(const std::vector<Vec2>& zone, const std::vector<Vec2>& box) {
  const std::vector<Vec2> part = clip_by_convex(zone, box);
  return part.size() >= 3 ? shoelace_area(part) : 0.0;
}

// A simple polygon: vertices at increasing angles round a centre, at random radii (star-shaped,
// often concave).
inline std::vector<Vec2> random_star_polygon(Rng& rng, const Vec2& centre, double r_max) {
  const int n = 3 + static_cast<int>(rng.uniform(0.0, 9.0));
  std::vector<double> angles;
  for (int i = 0; i < n; ++i) angles.push_back(rng.uniform(0.0, 2.0 * M_PI));
  std::sort(angles.begin(), angles.end());
  std::vector<Vec2> poly;
  for (const double a : angles) poly.push_back(centre + rng.uniform(0.1 * r_max, r_max) * Vec2(std::cos(a), std::sin(a)));
  return poly;
}

}  // namespace starnav::test
