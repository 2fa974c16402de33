#pragma once
// Path metrics shared by every planner, the benchmarks and (later) the simulator (docs/papers/ou2022.md):
// length, vertices, turning points, total and maximum absolute turning angle, minimum and mean
// clearance, smoothness.
//
// Definitions (a path is a polyline of world points, in map units: metres on metric maps, cells
// on index maps such as MovingAI's):
//   length          sum of the segment lengths.
//   vertices        number of points.
//   heading change  at an interior vertex, the absolute difference in [0, pi] between the headings
//                   of the segments before and after it (segments of zero length are skipped).
//   turning_points  interior vertices whose heading change exceeds 1e-9 rad.
//   turn_total_rad  sum of the heading changes; turn_max_rad their maximum.
//   smoothness      sum of squared heading changes (rad^2) divided by the length (per metre, or
//                   per cell on index maps); 0 for a straight path. Lower is smoother.
//   clearance       the distance-transform value (cell centre to the nearest obstacle cell
//                   centre, map units) of the cell under each sample; the path is sampled every
//                   resolution / 4 of arc length from its start, plus its last point. clearance_min
//                   is the minimum over the samples, clearance_mean their average. Without a
//                   clearance field, or when no sample lies on the map, both are NaN; with no
//                   obstacle on the map they are +infinity.
#include <cstddef>
#include <span>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

inline constexpr double kTurnEpsilonRad = 1e-9;

struct PathMetrics {
  double length = 0.0;
  std::size_t vertices = 0;
  std::size_t turning_points = 0;
  double turn_total_rad = 0.0;
  double turn_max_rad = 0.0;
  double clearance_min = 0.0;
  double clearance_mean = 0.0;
  double smoothness = 0.0;
};

// Distance to the nearest obstacle per cell, in map units, with the grid's geometry.
class ClearanceField {
 public:
  ClearanceField() = default;
  // `distance`: one value per cell, row-major (geometry.index order). Throws Error when the size
  // does not match the geometry.
  ClearanceField(const GridGeometry& geometry, std::vector<double> distance);
  // The exact Euclidean distance transform of the grid's obstacles (occupied cells, and unknown
  // cells when unknown_is_obstacle), in metres (cells on index maps).
  static ClearanceField of_grid(const OccupancyGrid& grid, const OccupancyThresholds& thresholds = {},
                                bool unknown_is_obstacle = true);

  const GridGeometry& geometry() const { return geometry_; }
  bool empty() const { return distance_.empty(); }
  // The value of the cell containing a world point; NaN outside the map.
  double at(const Vec2& world) const;
  double at(const Cell& c) const { return distance_[geometry_.index(c.x, c.y)]; }
  const std::vector<double>& values() const { return distance_; }

 private:
  GridGeometry geometry_;
  std::vector<double> distance_;
};

// Metrics of a polyline; clearance figures only with a field (NaN otherwise).
PathMetrics compute_path_metrics(std::span<const Vec2> points, const ClearanceField* clearance = nullptr);

// The same for a path of cells: their centres in the field's (or the given) geometry.
std::vector<Vec2> cell_centres(std::span<const Cell> cells, const GridGeometry& geometry);

}  // namespace starnav
