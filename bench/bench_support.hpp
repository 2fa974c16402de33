#pragma once
// Helpers the Google Benchmark suites share: the library's thread CPU clock (what a query costs on
// one core, whatever else the machine does), the median of a sample (core/statistics.hpp) and the
// local controllers' room.
#include <cstdint>
#include <utility>
#include <vector>

#include "starnav/core/cpu_time.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav::bench {

using starnav::thread_cpu_s;

// The middle value (the mean of the middle two for an even count); 0 when empty.
inline double median(std::vector<double> v) { return sample_stats(std::move(v)).median; }

// A 12 m x 12 m room at 0.05 m with random boxes (200: cluttered; 0: open) and a 1 m lane kept
// clear from (4.5, 5.5) to (10, 6.5): the local controllers' benchmarks drive along it.
inline OccupancyGrid cluttered_room(std::uint64_t seed, int boxes) {
  GridGeometry g;
  g.resolution = 0.05;
  g.width = 240;
  g.height = 240;
  OccupancyGrid grid(g, kFreeOccupancy);
  Rng rng(seed);
  for (int k = 0; k < boxes; ++k) {
    const int x0 = static_cast<int>(rng.uniform_int(0, 230)), y0 = static_cast<int>(rng.uniform_int(0, 230));
    const int w = static_cast<int>(rng.uniform_int(2, 12)), h = static_cast<int>(rng.uniform_int(2, 12));
    for (int iy = y0; iy < y0 + h; ++iy)
      for (int ix = x0; ix < x0 + w; ++ix) grid(ix, iy) = kOccupiedOccupancy;
  }
  for (int iy = 110; iy < 130; ++iy)
    for (int ix = 90; ix < 200; ++ix) grid(ix, iy) = kFreeOccupancy;
  return grid;
}

}  // namespace starnav::bench
