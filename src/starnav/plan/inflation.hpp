#pragma once
// Obstacle inflation for the planners (Ou et al. 2022's "safety protection", docs/papers/ou2022.md): one exact
// Euclidean distance transform of the obstacle mask (map/distance_transform.hpp, linear time),
// then a threshold for the hard radius and, optionally, the graded cost band. The formulas are
// documented with InflationOptions (ou2022_options.hpp).
#include <cstdint>
#include <vector>

#include "starnav/map/distance_transform.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/ou2022_options.hpp"

namespace starnav {

// Throws Error naming the field (inflate, inflate_cost_radius, inflate_cost, inflate_cost_weight)
// for negative or non-finite values.
void validate_inflation(const InflationOptions& options);

// The multiplier of a cell at distance `d_m` (metres) from the nearest obstacle: 1 + K exp(-s (d
// - R)) inside the band R < d <= R2, 1 outside it (and 1 when there is no band). Cells with d <= R
// are blocked; this function does not say so.
double inflation_cost_multiplier(double d_m, const InflationOptions& options);

struct InflatedMap {
  int width = 0;
  int height = 0;
  double resolution = 1.0;
  // Row-major width x height, non-zero = blocked: the original obstacles plus every cell within
  // the hard radius of one.
  std::vector<std::uint8_t> blocked;
  // Distance (metres) from each cell centre to the nearest obstacle cell centre of the original
  // map; 0 on obstacles, +infinity everywhere when the map has no obstacle.
  std::vector<double> clearance_m;
  // Cost multiplier per cell (>= 1), empty unless the options ask for a graded band.
  std::vector<double> multiplier;
  std::size_t obstacle_cells = 0;  // blocked in the original map
  std::size_t inflated_cells = 0;  // blocked by the hard radius alone
};

// Obstacles are the cells a planner with these thresholds may not enter (occupied; unknown
// unless unknown_is_free). Throws Error for bad options (validate_inflation).
InflatedMap inflate_obstacles(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, bool unknown_is_free,
                              const InflationOptions& options);

// inflate_obstacles for callers that inflate again and again (a costmap refreshed in a loop): the
// result's buffers and the distance transform's scratch stay allocated between calls, so a
// repeated inflation of a same-sized map allocates nothing. Without this, every call on a map of
// 2000 x 2000 cells or more gets fresh pages from the system and pays a page fault per 4 KB on
// first touch (docs/papers/ou2022.md).
class ObstacleInflator {
 public:
  // The result of inflate_obstacles, written into `out` (whatever it held before is replaced).
  void inflate(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, bool unknown_is_free,
               const InflationOptions& options, InflatedMap& out);

 private:
  DistanceTransform transform_;
};

// The grid with every cell blocked by inflation marked occupied (100); other cells unchanged.
// For planners that take an OccupancyGrid (JPS, JPS+, ...).
OccupancyGrid inflated_grid(const OccupancyGrid& grid, const InflatedMap& inflated);

}  // namespace starnav
