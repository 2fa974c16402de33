#pragma once
// Helpers of the terrain tests: small random terrains and brute-force references written
// independently of the library's code.
#include <cmath>
#include <cstdint>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/map/elevation_map.hpp"

namespace starnav::terrain_test {

inline GridGeometry geometry(int w, int h, double res = 0.1, Pose2 origin = {}) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = origin;
  return g;
}

// Smooth-ish random terrain: a random walk of heights plus noise, with `unobserved_fraction`
// of the cells left unobserved. Steps are scaled by `roughness` (metres).
inline ElevationMap random_terrain(std::uint64_t seed, int w, int h, double res = 0.1, double roughness = 0.02,
                                   double unobserved_fraction = 0.0) {
  Rng rng(seed);
  ElevationMap m(geometry(w, h, res));
  std::vector<double> z(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double base = 0.0;
      int n = 0;
      if (x > 0) base += z[static_cast<std::size_t>(y) * w + x - 1], ++n;
      if (y > 0) base += z[static_cast<std::size_t>(y - 1) * w + x], ++n;
      z[static_cast<std::size_t>(y) * w + x] = (n ? base / n : 0.0) + roughness * rng.normal();
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (rng.uniform() < unobserved_fraction) continue;
      const double v = z[static_cast<std::size_t>(y) * w + x];
      const double spread = 0.03 * rng.uniform();
      m.set_cell(x, y, v, v - spread, v + spread * rng.uniform());
    }
  return m;
}

// Brute-force 3x3 ruggedness: two-pass mean and variance over the observed cells of the block
// clipped to the map; 0 for an unobserved cell.
inline double brute_ruggedness(const ElevationMap& m, int x, int y) {
  if (!m.observed_at(x, y)) return 0.0;
  long double sum = 0;
  int n = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int i = x + dx, j = y + dy;
      if (!m.contains(i, j) || !m.observed_at(i, j)) continue;
      sum += m.height_at(i, j);
      ++n;
    }
  const long double mean = sum / n;
  long double var = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int i = x + dx, j = y + dy;
      if (!m.contains(i, j) || !m.observed_at(i, j)) continue;
      var += (m.height_at(i, j) - mean) * (m.height_at(i, j) - mean);
    }
  return static_cast<double>(var / n);
}

}  // namespace starnav::terrain_test
