#pragma once
// A world of axis-aligned boxes for localization tests: rasterised into an occupancy grid whose
// occupied cells the boxes cover exactly (boxes on cell boundaries), and exact ranges by ray-box
// intersection (the slab method), independent of the library's grid traversal.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "starnav/map/occupancy_grid.hpp"

namespace starnav::test {

struct Box {
  double x0, y0, x1, y1;  // world, axis-aligned
};

// A free grid of w_m x h_m at `res` (cell (0, 0) at the origin): the local controllers' tests.
inline OccupancyGrid empty_map(double w_m, double h_m, double res = 0.05) {
  GridGeometry g;
  g.resolution = res;
  g.width = static_cast<int>(std::lround(w_m / res));
  g.height = static_cast<int>(std::lround(h_m / res));
  return OccupancyGrid(g, kFreeOccupancy);
}

// The cells of `m` whose centres lie in [x0, x1] x [y0, y1] (edges included) occupied.
inline void fill_box(OccupancyGrid& m, double x0, double y0, double x1, double y1) {
  const GridGeometry& g = m.geometry();
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const Vec2 c = g.cell_center(x, y);
      if (c.x() >= x0 && c.x() <= x1 && c.y() >= y0 && c.y() <= y1) m(x, y) = kOccupiedOccupancy;
    }
}

// The cells of `geometry` whose centres lie inside a box are occupied, the rest free.
inline OccupancyGrid rasterise_boxes(const GridGeometry& geometry, const std::vector<Box>& boxes) {
  OccupancyGrid grid(geometry, kFreeOccupancy);
  for (int iy = 0; iy < geometry.height; ++iy)
    for (int ix = 0; ix < geometry.width; ++ix) {
      const Vec2 c = geometry.cell_center(ix, iy);
      for (const Box& b : boxes)
        if (c.x() > b.x0 && c.x() < b.x1 && c.y() > b.y0 && c.y() < b.y1) grid(ix, iy) = kOccupiedOccupancy;
    }
  return grid;
}

// The exact range from (x, y) along `angle` to the nearest box; +inf when none lies ahead; 0
// inside a box.
inline double cast_to_boxes(const std::vector<Box>& boxes, double x, double y, double angle) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  double best = std::numeric_limits<double>::infinity();
  for (const Box& b : boxes) {
    double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
    const auto slab = [&](double o, double d, double lo, double hi) {
      if (d == 0.0) {
        if (o < lo || o > hi) t0 = std::numeric_limits<double>::infinity();
        return;
      }
      double a = (lo - o) / d, c = (hi - o) / d;
      if (a > c) std::swap(a, c);
      t0 = std::max(t0, a);
      t1 = std::min(t1, c);
    };
    slab(x, dx, b.x0, b.x1);
    slab(y, dy, b.y0, b.y1);
    if (t0 <= t1 && t1 >= 0.0) best = std::min(best, std::max(t0, 0.0));
  }
  return best;
}

}  // namespace starnav::test
