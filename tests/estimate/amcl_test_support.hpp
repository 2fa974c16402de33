#pragma once
// Shared pieces of the AMCL tests: a small asymmetric room made of boxes (rasterised into an
// occupancy grid whose cells the boxes cover exactly), scans simulated by exact ray-box
// intersection, independent of the library's grid traversal, and brute-force distances.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/amcl_sensor_model.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav::amcl_test {

struct Box {
  double x0, y0, x1, y1;  // world, axis-aligned
};

struct Room {
  OccupancyGrid grid;
  std::vector<Box> boxes;
};

// An 8 m x 6 m room at 0.05 m (origin (-1, -2)): outer walls, a wall from the bottom with a gap
// above it, three boxes and a pillar, placed so that no pose looks like another.
inline Room make_room() {
  Room r;
  r.boxes = {
      {-1.0, -2.0, 7.0, -1.9}, {-1.0, 3.9, 7.0, 4.0}, {-1.0, -2.0, -0.9, 4.0}, {6.9, -2.0, 7.0, 4.0},  // walls
      {2.0, -1.9, 2.1, 1.0},                                                                           // inner wall
      {4.0, 1.5, 4.6, 2.3}, {0.0, 2.5, 0.3, 3.2}, {5.2, -1.2, 5.5, -0.4}, {3.0, 2.8, 3.2, 3.0}};
  GridGeometry g;
  g.width = 160;
  g.height = 120;
  g.resolution = 0.05;
  g.origin = Pose2(-1.0, -2.0, 0.0);
  r.grid = OccupancyGrid(g, kFreeOccupancy);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Vec2 c = g.cell_center(ix, iy);
      for (const Box& b : r.boxes)
        if (c.x() > b.x0 && c.x() < b.x1 && c.y() > b.y0 && c.y() < b.y1) r.grid(ix, iy) = kOccupiedOccupancy;
    }
  return r;
}

// The exact range from (x, y) along `angle` to the nearest box (slab method); +inf when none
// lies ahead; 0 inside a box.
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

// A full-circle scan of `beams` beams from the laser pose `laser` (world), azimuths decreasing
// with the index as the simulator's (+pi - i * 2 pi / beams), Gaussian range noise, +inf beyond
// range_max.
inline PlanarScan simulate_room_scan(const std::vector<Box>& boxes, const Pose2& laser, int beams, double range_max,
                                     double noise_sigma, Rng& rng) {
  PlanarScan s;
  s.range_min_m = 0.05;
  s.range_max_m = range_max;
  const double delta = 2.0 * kPi / beams;
  for (int i = 0; i < beams; ++i) {
    const double a = kPi - i * delta;
    double r = cast_to_boxes(boxes, laser.x, laser.y, laser.yaw + a);
    if (r < range_max) r += noise_sigma * rng.normal();
    s.ranges.push_back(r < range_max ? r : std::numeric_limits<double>::infinity());
    s.angles_rad.push_back(a);
  }
  return s;
}

// Brute-force distance from a world point to the occupied cells of `grid`: to their centres or
// to their squares. +inf without any occupied cell.
inline double brute_obstacle_distance(const OccupancyGrid& grid, const OccupancyThresholds& t, const Vec2& world,
                                      bool surface) {
  const GridGeometry& g = grid.geometry();
  const Vec2 p = g.world_to_grid(world);
  const double res = g.resolution;
  double best = std::numeric_limits<double>::infinity();
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      if (t.classify(grid(ix, iy)) != CellState::Occupied) continue;
      double d;
      if (surface) {
        const double ex = std::max({0.0, ix * res - p.x(), p.x() - (ix + 1) * res});
        const double ey = std::max({0.0, iy * res - p.y(), p.y() - (iy + 1) * res});
        d = std::hypot(ex, ey);
      } else {
        d = std::hypot(p.x() - (ix + 0.5) * res, p.y() - (iy + 0.5) * res);
      }
      best = std::min(best, d);
    }
  return best;
}

}  // namespace starnav::amcl_test
