#pragma once
// Small polyline helpers shared by the simulator's metrics and the navigation loop.
#include <algorithm>
#include <limits>
#include <span>

#include "starnav/core/geometry.hpp"

namespace starnav {

// Distance from a point to a polyline (a single point: the distance to it; empty: +inf).
inline double distance_to_polyline(const Vec2& p, std::span<const Vec2> line) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Vec2 a = line[i], d = line[i + 1] - a;
    const double len2 = d.squaredNorm();
    const double s = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (p - (a + s * d)).norm());
  }
  if (line.size() == 1) best = (p - line[0]).norm();
  return best;
}

}  // namespace starnav
