#pragma once
// Cell index <-> world conversions for metric grids (conventions.md, "Grids").
// The origin is the world pose of the lower-left corner of cell (0, 0); a non-zero yaw rotates the
// grid about that corner. MovingAI maps are index grids: resolution 1, origin 0, and y counted
// from the top (y_down), which only matters to pictures and to the units the CLI prints.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "starnav/core/geometry.hpp"

namespace starnav {

// conventions.md: a grid has at most 2^31 - 1 cells (cell indices fit an int).
inline constexpr std::uint64_t kMaxGridCells = 2147483647ULL;

struct Cell {
  int x = 0;
  int y = 0;
  friend bool operator==(const Cell&, const Cell&) = default;
};

struct GridGeometry {
  int width = 0;
  int height = 0;
  double resolution = 1.0;  // metres per cell
  Pose2 origin;             // pose of the lower-left corner of cell (0, 0)
  bool y_down = false;      // true for index grids whose row 0 is the top row (MovingAI)

  std::size_t cell_count() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  bool contains(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width && iy < height; }
  bool contains(const Cell& c) const { return contains(c.x, c.y); }
  std::size_t index(int ix, int iy) const {
    return static_cast<std::size_t>(iy) * static_cast<std::size_t>(width) + static_cast<std::size_t>(ix);
  }
  Cell cell_of_index(std::size_t i) const {
    return {static_cast<int>(i % static_cast<std::size_t>(width)), static_cast<int>(i / static_cast<std::size_t>(width))};
  }

  // Grid-frame (metres, unrotated, relative to the origin corner) <-> world.
  Vec2 grid_to_world(const Vec2& g) const { return origin.transform(g); }
  Vec2 world_to_grid(const Vec2& w) const { return origin.inverse_transform(w); }

  // World position of the centre of a cell.
  Vec2 cell_center(int ix, int iy) const { return grid_to_world({(ix + 0.5) * resolution, (iy + 0.5) * resolution}); }
  Vec2 cell_center(const Cell& c) const { return cell_center(c.x, c.y); }

  // Continuous cell coordinates of a world point (cell (ix, iy) covers [ix, ix+1) x [iy, iy+1)).
  Vec2 world_to_cell_continuous(const Vec2& w) const { return world_to_grid(w) / resolution; }

  // The cell containing a world point, whether or not it lies inside the map. Coordinates beyond
  // the int range are clamped to it and NaN becomes INT_MIN (always outside the map), so a wild
  // point never overflows the conversion.
  Cell world_to_cell_unchecked(const Vec2& w) const {
    const Vec2 c = world_to_cell_continuous(w);
    return {floor_to_int(c.x()), floor_to_int(c.y())};
  }
  // The cell containing a world point, or nothing when it falls outside the map.
  std::optional<Cell> world_to_cell(const Vec2& w) const {
    const Vec2 c = world_to_cell_continuous(w);
    if (!std::isfinite(c.x()) || !std::isfinite(c.y())) return std::nullopt;
    const double fx = std::floor(c.x()), fy = std::floor(c.y());
    if (fx < 0 || fy < 0 || fx >= width || fy >= height) return std::nullopt;
    return Cell{static_cast<int>(fx), static_cast<int>(fy)};
  }
  double width_m() const { return width * resolution; }
  // floor(v) as an int, saturated to the int range; NaN gives INT_MIN.
  static int floor_to_int(double v) {
    constexpr double lo = static_cast<double>(std::numeric_limits<int>::min());
    constexpr double hi = static_cast<double>(std::numeric_limits<int>::max());
    if (!(v >= lo)) return std::numeric_limits<int>::min();  // also NaN
    if (v >= hi) return std::numeric_limits<int>::max();
    return static_cast<int>(std::floor(v));
  }
  double height_m() const { return height * resolution; }
};

// A rectangle of cells [x0, x1) x [y0, y1).
struct CellRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  // Grown by `margin` cells on every side and clipped to a width x height map.
  CellRect grown(int margin, int width, int height) const {
    return {x0 - margin < 0 ? 0 : x0 - margin, y0 - margin < 0 ? 0 : y0 - margin,
            x1 + margin > width ? width : x1 + margin, y1 + margin > height ? height : y1 + margin};
  }
};

}  // namespace starnav
