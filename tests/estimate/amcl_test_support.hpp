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
#include "support/box_world.hpp"

namespace starnav::amcl_test {

using test::Box;
using test::cast_to_boxes;

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
  r.grid = test::rasterise_boxes(g, r.boxes);
  return r;
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
