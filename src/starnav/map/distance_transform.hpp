#pragma once
// Exact Euclidean distance transform of a binary obstacle mask (Felzenszwalb & Huttenlocher,
// "Distance Transforms of Sampled Functions", Theory of Computing 8, 2012), in time linear in
// the number of cells.
//
// Distances are between cell centres, in cells (squared) or metres. Obstacle cells have distance
// 0. When the mask holds no obstacle at all every distance is +infinity and there is no nearest
// obstacle (index kNoObstacle).
//
// How it is computed: the 2-D transform separates into two 1-D transforms.
//  1. Along columns: for a binary input the 1-D lower envelope of the parabolas rooted at the
//     obstacle cells reduces to the distance to the nearest obstacle in the same column, which
//     two sweeps (bottom-up, top-down) compute exactly. The sweeps run over whole rows at a time,
//     so the column pass reads and writes memory contiguously (no transpose needed) and
//     vectorises.
//  2. Along rows: the FH lower envelope of the parabolas f(q) + (p - q)^2, f(q) = g(q)^2 with g
//     the column distance. The envelope's breakpoints are kept as integers (the first cell where
//     each parabola is lowest, as in Meijster et al.), so all arithmetic is exact 64-bit integer
//     arithmetic and the result equals brute force bit for bit. Rows are independent, and so
//     are columns in pass 1: both passes split into bands for several threads.
// Ties between equally near obstacles go to the lower column, then to the lower row.
//
// Masks up to 2^31 - 1 cells (the map limit of validate_geometry) are supported; squared
// distances are exact integers stored in doubles (exact below 2^53).
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// "No obstacle" in a nearest-obstacle array (the mask has no obstacle at all).
inline constexpr std::int32_t kNoObstacle = -1;

// A reusable distance transform: the working buffers and the results stay allocated between
// calls, so repeated transforms of same-sized maps allocate nothing. Not thread-safe itself (use
// one object per thread); a single compute() may use several threads.
class DistanceTransform {
 public:
  // Transforms `mask` (row-major, width x height, non-zero = obstacle; row 0 first, whichever
  // way up the rows are). With `with_nearest`, also finds for every cell the index
  // (iy * width + ix) of a nearest obstacle cell. `threads` > 1 splits both passes into bands
  // (0 = one per hardware thread); the result does not depend on it. Throws Error (field "mask")
  // for a non-positive size, more than 2^31 - 1 cells, or a mask whose size is not
  // width * height, and (field "threads") for a negative thread count.
  void compute(std::span<const std::uint8_t> mask, int width, int height, bool with_nearest = false,
               int threads = 1);

  int width() const { return width_; }
  int height() const { return height_; }
  // False when the last mask had no obstacle (then every distance is +infinity).
  bool has_obstacle() const { return has_obstacle_; }

  // Squared distance in cells to the nearest obstacle cell centre, row-major like the mask.
  const std::vector<double>& squared_cells() const { return squared_; }
  double squared_at(int ix, int iy) const {
    return squared_[static_cast<std::size_t>(iy) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(ix)];
  }
  // Index of a nearest obstacle cell per cell, or kNoObstacle; empty unless the last compute()
  // asked for it.
  const std::vector<std::int32_t>& nearest() const { return nearest_; }

  // Hands the results over (the transform keeps only its scratch buffers).
  std::vector<double> take_squared_cells() { return std::move(squared_); }
  std::vector<std::int32_t> take_nearest() { return std::move(nearest_); }

 private:
  struct Envelope {  // one row's lower envelope of parabolas
    std::vector<std::int64_t> site;   // column of each parabola
    std::vector<std::int64_t> value;  // its f = g^2
    std::vector<std::int64_t> start;  // first cell where it is the lowest
  };
  void column_pass(std::span<const std::uint8_t> mask, std::size_t x0, std::size_t x1);
  template <bool kWithNearest>
  void row_pass(std::span<const std::uint8_t> mask, int y0, int y1, Envelope& env);

  int width_ = 0;
  int height_ = 0;
  bool has_obstacle_ = false;
  std::vector<std::int32_t> column_dist_;  // distance to the nearest obstacle in the same column
  std::vector<std::int32_t> columns_;      // the columns that hold an obstacle at all
  std::vector<double> inv_2d_;             // 1 / (2 d) for column gaps d
  std::vector<Envelope> scratch_;          // one per row band
  std::vector<double> squared_;
  std::vector<std::int32_t> nearest_;
};

// One-shot squared distance transform in cells; see DistanceTransform::compute. When `nearest`
// is given it receives the nearest obstacle index per cell.
std::vector<double> squared_distance_transform(std::span<const std::uint8_t> mask, int width, int height,
                                               std::vector<std::int32_t>* nearest = nullptr, int threads = 1);

// Distance in metres from every cell centre of `grid` to the nearest obstacle cell centre:
// obstacles are the cells the thresholds call occupied, plus the unknown cells when
// `unknown_is_obstacle`. +infinity everywhere when there is no obstacle. Rotation (origin yaw)
// does not change distances. When `nearest` is given it receives the nearest obstacle cell
// index (iy * width + ix) per cell, or kNoObstacle.
std::vector<double> obstacle_distance_m(const OccupancyGrid& grid, const OccupancyThresholds& thresholds = {},
                                        bool unknown_is_obstacle = true,
                                        std::vector<std::int32_t>* nearest = nullptr, int threads = 1);

// The one inflation-radius rule, shared by plan/inflation, terrain's obstacle expansion and the
// navigation map: a cell lies within a radius of r cells of an obstacle when its squared distance
// d2 (in cells^2, exact integers from the transforms above) satisfies d2 <= r^2 (1 + 1e-9):
// inclusive, with a relative tolerance for the rounding of radius_m / resolution (0.3 / 0.1 =
// 2.9999999999999996 still includes distance 3). A radius of 0 inflates nothing.
inline double inflation_radius_cells(double radius_m, double resolution) { return radius_m / resolution; }
inline double inflation_limit_squared(double radius_cells) { return radius_cells * radius_cells * (1.0 + 1e-9); }
inline bool within_inflation_radius(double squared_cells, double radius_cells) {
  return radius_cells > 0.0 && squared_cells <= inflation_limit_squared(radius_cells);
}
// How many cells beyond a changed region an incremental update must look to decide every cell
// within the radius exactly.
inline int inflation_margin_cells(double radius_cells) {
  return static_cast<int>(std::floor(radius_cells * (1.0 + 1e-9))) + 1;
}

}  // namespace starnav
