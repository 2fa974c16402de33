#include "starnav/map/clearance_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {
constexpr double kUnreached = std::numeric_limits<double>::infinity();
}

namespace {

// The window's lattice around `centre` on grid `g`: its first cell (ix0, iy0) in the grid, and
// its half size in cells.
struct WindowPlacement {
  int ix0 = 0, iy0 = 0, half = 0;
};
WindowPlacement place_window(const GridGeometry& g, const Vec2& centre, double half_m, double pad_m) {
  const double cells = clearance_window_cells(half_m, pad_m, g.resolution);
  if (!(cells <= kMaxClearanceWindowCells))
    throw Error("a clearance window " + format_readable(half_m) + " m each way, padded by " + format_readable(pad_m) + " m, on cells of " +
                    format_readable(g.resolution) + " m takes " + format_number(cells) + " cells, more than " +
                    format_number(kMaxClearanceWindowCells) + ": coarsen the map",
                "", 0, "navigation.map.resolution_m");
  const Vec2 c = g.world_to_cell_continuous(centre);
  WindowPlacement p;
  p.half = static_cast<int>(std::ceil(half_m / g.resolution));
  p.ix0 = static_cast<int>(std::floor(c.x())) - p.half;
  p.iy0 = static_cast<int>(std::floor(c.y())) - p.half;
  return p;
}

}  // namespace

double clearance_window_cells(double half_m, double pad_m, double resolution) {
  const double side = 2.0 * std::ceil(half_m / resolution) + 1.0 + 2.0 * (std::ceil(pad_m / resolution) + 1.0);
  return side * side;
}

void ClearanceWindow::set_lattice(const GridGeometry& g, int ix0, int iy0, int half, double pad_m) {
  const double res = g.resolution;
  pad_ = static_cast<int>(std::ceil(pad_m / res)) + 1;
  geometry_ = GridGeometry{};
  geometry_.resolution = res;
  geometry_.width = 2 * half + 1;
  geometry_.height = 2 * half + 1;
  const Vec2 corner = g.grid_to_world({ix0 * res, iy0 * res});
  geometry_.origin = Pose2(corner.x(), corner.y(), g.origin.yaw);
  cos_ = std::cos(g.origin.yaw);
  sin_ = std::sin(g.origin.yaw);
  inv_resolution_ = 1.0 / res;
  padded_width_ = geometry_.width + 2 * pad_;
  padded_height_ = geometry_.height + 2 * pad_;
}

void ClearanceWindow::index_obstacles() {
  row_columns_.clear();
  row_start_.assign(static_cast<std::size_t>(padded_height_) + 1, 0);
  for (int py = 0; py < padded_height_; ++py) {
    const std::uint8_t* row = mask_.data() + static_cast<std::size_t>(py) * static_cast<std::size_t>(padded_width_);
    for (int px = 0; px < padded_width_; ++px)
      if (row[px]) row_columns_.push_back(px);
    row_start_[static_cast<std::size_t>(py) + 1] = row_columns_.size();
  }
}

void ClearanceWindow::build(const OccupancyGrid& map, const Vec2& centre, double half_m, double pad_m,
                        const OccupancyThresholds& thresholds) {
  const GridGeometry& g = map.geometry();
  const double res = g.resolution;
  const WindowPlacement at = place_window(g, centre, half_m, pad_m);
  set_lattice(g, at.ix0, at.iy0, at.half, pad_m);
  const int ix0 = at.ix0, iy0 = at.iy0;

  mask_.assign(static_cast<std::size_t>(padded_width_) * static_cast<std::size_t>(padded_height_), 0);
  const std::span<const std::int8_t> data = map.data();
  for (int py = 0; py < padded_height_; ++py) {
    const int my = iy0 - pad_ + py;
    std::uint8_t* row = mask_.data() + static_cast<std::size_t>(py) * static_cast<std::size_t>(padded_width_);
    if (my < 0 || my >= g.height) {
      std::fill(row, row + padded_width_, std::uint8_t{1});
      continue;
    }
    for (int px = 0; px < padded_width_; ++px) {
      const int mx = ix0 - pad_ + px;
      row[px] = (mx < 0 || mx >= g.width || thresholds.classify(data[g.index(mx, my)]) == CellState::Occupied) ? 1 : 0;
    }
  }
  index_obstacles();
  transform_.compute(mask_, padded_width_, padded_height_, true);
  const std::vector<double>& sq = transform_.squared_cells();
  const std::vector<std::int32_t>& near = transform_.nearest();
  clearance_.resize(geometry_.cell_count());
  nearest_.resize(geometry_.cell_count());
  for (int y = 0; y < geometry_.height; ++y)
    for (int x = 0; x < geometry_.width; ++x) {
      const std::size_t i = geometry_.index(x, y);
      const std::size_t j = padded_index(x, y);
      clearance_[i] = std::sqrt(sq[j]) * res;
      nearest_[i] = near[j];
    }
}

void ClearanceWindow::build(const ObstacleDistanceField& field, const Vec2& centre, double half_m, double pad_m) {
  const GridGeometry& g = field.geometry();
  if (field.range_m() + 1e-9 < pad_m + g.resolution)
    throw Error("the map's distance field reaches " + format_readable(field.range_m()) + " m, the controller needs " +
                    format_readable(pad_m + g.resolution) + " m (raise navigation.map.clearance_range_m)",
                "", 0, "navigation.map.clearance_range_m");
  const double res = g.resolution;
  const WindowPlacement at = place_window(g, centre, half_m, pad_m);
  set_lattice(g, at.ix0, at.iy0, at.half, pad_m);
  const int ix0 = at.ix0, iy0 = at.iy0;
  field.refresh({ix0, iy0, ix0 + geometry_.width, iy0 + geometry_.height});
  mask_.assign(static_cast<std::size_t>(padded_width_) * static_cast<std::size_t>(padded_height_), 0);
  for (int py = 0; py < padded_height_; ++py) {
    std::uint8_t* row = mask_.data() + static_cast<std::size_t>(py) * static_cast<std::size_t>(padded_width_);
    for (int px = 0; px < padded_width_; ++px) row[px] = field.obstacle(ix0 - pad_ + px, iy0 - pad_ + py) ? 1 : 0;
  }
  index_obstacles();
  clearance_.resize(geometry_.cell_count());
  nearest_.resize(geometry_.cell_count());
  for (int y = 0; y < geometry_.height; ++y)
    for (int x = 0; x < geometry_.width; ++x) {
      const std::size_t i = geometry_.index(x, y);
      clearance_[i] = kUnreached;
      nearest_[i] = kNoObstacle;
      const int mx = ix0 + x, my = iy0 + y;
      if (!g.contains(mx, my)) {
        clearance_[i] = 0.0;  // outside the map: an obstacle itself
        nearest_[i] = static_cast<std::int32_t>(padded_index(x, y));
        continue;
      }
      const std::size_t k = g.index(mx, my);
      if (!std::isfinite(field.squared_cells(k))) continue;
      const Cell n = field.nearest_cell(k);
      const int px = n.x - ix0 + pad_, py = n.y - iy0 + pad_;
      if (px < 0 || py < 0 || px >= padded_width_ || py >= padded_height_) continue;  // beyond the padded window
      clearance_[i] = field.distance_m(k);
      nearest_[i] = py * padded_width_ + px;
    }
  (void)res;
}

Vec2 ClearanceWindow::nearest_obstacle(std::size_t i) const {
  const std::int32_t j = nearest_[i];
  const int px = j % padded_width_, py = j / padded_width_;
  return cell_center(px - pad_, py - pad_);
}

void ClearanceWindow::wavefront(std::span<const Cell> seeds, double pass_clearance_m, std::vector<double>& out) const {
  out.assign(geometry_.cell_count(), kUnreached);
  using Entry = std::pair<double, std::int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  for (const Cell& s : seeds) {
    if (!contains(s.x, s.y)) continue;
    const std::size_t i = index(s.x, s.y);
    if (out[i] > 0.0) {
      out[i] = 0.0;
      open.emplace(0.0, static_cast<std::int32_t>(i));
    }
  }
  const double res = geometry_.resolution;
  const double diag = res * std::sqrt(2.0);
  const int w = geometry_.width, h = geometry_.height;
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > out[static_cast<std::size_t>(i)]) continue;
    const int x = i % w, y = i / w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const std::size_t n = index(nx, ny);
        if (!(clearance_[n] > 0.0 && clearance_[n] >= pass_clearance_m)) continue;  // obstacles never pass
        const double nd = d + (dx != 0 && dy != 0 ? diag : res);
        if (nd < out[n]) {
          out[n] = nd;
          open.emplace(nd, static_cast<std::int32_t>(n));
        }
      }
  }
}

}  // namespace starnav
