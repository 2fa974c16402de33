#pragma once
// A square window of an obstacle map around the robot on the map's own cell lattice, with per cell
// the distance to the nearest obstacle cell: what a local controller scores its samples against
// and what the footprint checker (map/footprint_checker.hpp) tests a pose against.
//
// Obstacles are the map's occupied cells (unknown cells are free: the sensed map of an unexplored
// room is mostly unknown); cells outside the map are obstacles (the robot cannot leave it). The
// distances are exact (map/distance_transform.hpp) between cell centres; the window is padded so
// that they are exact out to `pad_m` beyond its edge.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/obstacle_distance_field.hpp"
#include "starnav/map/distance_transform.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// The most cells of a clearance window with its padding (a local controller's window, a
// recovery's look ahead): it is rebuilt at every command, about 40 bytes a cell (the mask, the
// transform, the distances and nearest obstacles).
inline constexpr double kMaxClearanceWindowCells = 4e6;
// The cells of the padded window build() makes for `half_m` and `pad_m` on cells of `resolution`:
// (2 ceil(half / resolution) + 1 + 2 (ceil(pad / resolution) + 1)) squared, in double (no
// integer is formed before it is known to fit).
double clearance_window_cells(double half_m, double pad_m, double resolution);

class ClearanceWindow {
 public:
  // The window of `map` covering at least `half_m` around `centre` in x and y (rounded out to
  // whole cells), its distances exact for obstacles up to `pad_m` outside it. Reuses its buffers.
  // Either build refuses (Error, field navigation.map.resolution_m) a window of more than
  // kMaxClearanceWindowCells before anything is allocated.
  void build(const OccupancyGrid& map, const Vec2& centre, double half_m, double pad_m,
             const OccupancyThresholds& thresholds = {});
  // The same window read off a map's distance field (map/obstacle_distance_field.hpp, refreshed), without
  // a transform of its own: the obstacles are the field's, the distances the field's (exact out to
  // its range, which must reach `pad_m`: Error otherwise). An obstacle the field finds nearest but
  // that lies beyond the padded window counts as none, as it would for the window's own transform.
  void build(const ObstacleDistanceField& field, const Vec2& centre, double half_m, double pad_m);

  // The window's own grid: the map's lattice, shifted (cell (0, 0) is the window's first cell).
  const GridGeometry& geometry() const { return geometry_; }
  int width() const { return geometry_.width; }
  int height() const { return geometry_.height; }
  double resolution() const { return geometry_.resolution; }
  bool contains(int ix, int iy) const { return geometry_.contains(ix, iy); }
  std::size_t index(int ix, int iy) const { return geometry_.index(ix, iy); }
  // The window cell holding a world point (may lie outside: check contains()). Inner loops call
  // these: the origin's rotation is cached rather than recomputed by GridGeometry.
  Vec2 continuous_cell(const Vec2& w) const {
    const double dx = w.x() - geometry_.origin.x, dy = w.y() - geometry_.origin.y;
    return {(cos_ * dx + sin_ * dy) * inv_resolution_, (-sin_ * dx + cos_ * dy) * inv_resolution_};
  }
  Cell cell_of(const Vec2& w) const {
    const Vec2 g = continuous_cell(w);
    // Far outside (or NaN): a cell that contains() refuses.
    if (!(std::abs(g.x()) < 1e9 && std::abs(g.y()) < 1e9)) return {-1, -1};
    return {static_cast<int>(std::floor(g.x())), static_cast<int>(std::floor(g.y()))};
  }
  Vec2 cell_center(int ix, int iy) const {
    const double gx = (ix + 0.5) * geometry_.resolution, gy = (iy + 0.5) * geometry_.resolution;
    return {geometry_.origin.x + cos_ * gx - sin_ * gy, geometry_.origin.y + sin_ * gx + cos_ * gy};
  }

  bool occupied(int ix, int iy) const { return mask_[padded_index(ix, iy)] != 0; }
  // Distance (m) from the cell's centre to the nearest obstacle cell's centre (+inf: none).
  double clearance_m(std::size_t i) const { return clearance_[i]; }
  // Centre of a nearest obstacle cell of window cell i (only when clearance_m(i) is finite).
  Vec2 nearest_obstacle(std::size_t i) const;
  // Occupied cells of the padded window within the square of half side `r` around `p`, by their
  // centres (for exact footprint tests).
  template <class F>
  void for_each_obstacle_near(const Vec2& p, double r, F&& f) const;
  // Whether `f(centre)` holds for an occupied cell of window row `iy` (padding included: from
  // -pad) with a column in [ix0, ix1], stopping at the first; rows and columns beyond the padded
  // window hold none.
  template <class F>
  bool any_obstacle_in_row(int iy, int ix0, int ix1, F&& f) const;

  // Shortest 8-connected distance (m; steps of one cell and sqrt(2) cells) from the seed cells to
  // every window cell through free cells whose clearance is at least `pass_clearance_m` (the seeds
  // themselves always count), +inf where it cannot go. `out` is resized to the window.
  void wavefront(std::span<const Cell> seeds, double pass_clearance_m, std::vector<double>& out) const;

 private:
  void set_lattice(const GridGeometry& g, int ix0, int iy0, int half, double pad_m);
  void index_obstacles();
  std::size_t padded_index(int ix, int iy) const {
    return static_cast<std::size_t>(iy + pad_) * static_cast<std::size_t>(padded_width_) + static_cast<std::size_t>(ix + pad_);
  }

  GridGeometry geometry_;
  double cos_ = 1.0, sin_ = 0.0, inv_resolution_ = 1.0;  // of the origin's yaw; 1 / resolution
  int pad_ = 0;  // cells of padding on every side
  int padded_width_ = 0, padded_height_ = 0;
  std::vector<std::uint8_t> mask_;    // padded window, 1 = obstacle
  std::vector<std::int32_t> row_columns_;  // padded columns of the obstacle cells, row by row
  std::vector<std::size_t> row_start_;     // row y's columns: row_columns_[row_start_[y] .. row_start_[y + 1])
  std::vector<double> clearance_;     // window cells
  std::vector<std::int32_t> nearest_;  // window cells: padded index of a nearest obstacle
  DistanceTransform transform_;
  std::vector<double> padded_squared_;
};

template <class F>
void ClearanceWindow::for_each_obstacle_near(const Vec2& p, double r, F&& f) const {
  const Vec2 lo = continuous_cell(p) - Vec2::Constant(r * inv_resolution_);
  const Vec2 hi = lo + Vec2::Constant(2.0 * r * inv_resolution_);
  const auto clamp_floor = [](double v, int lo, int hi) {
    return static_cast<int>(std::clamp(std::floor(v), static_cast<double>(lo), static_cast<double>(hi)));
  };
  const int x0 = clamp_floor(lo.x(), -pad_, padded_width_ - pad_ - 1) + pad_;
  const int y0 = clamp_floor(lo.y(), -pad_, padded_height_ - pad_ - 1) + pad_;
  const int x1 = clamp_floor(hi.x(), -pad_, padded_width_ - pad_ - 1) + pad_;
  const int y1 = clamp_floor(hi.y(), -pad_, padded_height_ - pad_ - 1) + pad_;
  // Walk the obstacle cells of each row (sorted columns), not every cell of the square.
  for (int y = y0; y <= y1; ++y) {
    const auto first = row_columns_.begin() + row_start_[static_cast<std::size_t>(y)];
    const auto last = row_columns_.begin() + row_start_[static_cast<std::size_t>(y) + 1];
    for (auto it = std::lower_bound(first, last, x0); it != last && *it <= x1; ++it) f(cell_center(*it - pad_, y - pad_));
  }
}

template <class F>
bool ClearanceWindow::any_obstacle_in_row(int iy, int ix0, int ix1, F&& f) const {
  const int y = iy + pad_;
  if (y < 0 || y >= padded_height_) return false;
  const int x0 = std::max(ix0 + pad_, 0), x1 = std::min(ix1 + pad_, padded_width_ - 1);
  if (x0 > x1) return false;
  const auto first = row_columns_.begin() + static_cast<std::ptrdiff_t>(row_start_[static_cast<std::size_t>(y)]);
  const auto last = row_columns_.begin() + static_cast<std::ptrdiff_t>(row_start_[static_cast<std::size_t>(y) + 1]);
  for (auto it = std::lower_bound(first, last, x0); it != last && *it <= x1; ++it)
    if (f(cell_center(*it - pad_, iy))) return true;
  return false;
}

}  // namespace starnav
