#include "starnav/map/clearance_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

namespace starnav {

namespace {
constexpr double kUnreached = std::numeric_limits<double>::infinity();
}

void ClearanceWindow::build(const OccupancyGrid& map, const Vec2& centre, double half_m, double pad_m,
                        const OccupancyThresholds& thresholds) {
  const GridGeometry& g = map.geometry();
  const double res = g.resolution;
  const Vec2 c = g.world_to_cell_continuous(centre);
  const int half = static_cast<int>(std::ceil(half_m / res));
  pad_ = static_cast<int>(std::ceil(pad_m / res)) + 1;
  const int ix0 = static_cast<int>(std::floor(c.x())) - half;
  const int iy0 = static_cast<int>(std::floor(c.y())) - half;
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
  row_columns_.clear();
  row_start_.assign(static_cast<std::size_t>(padded_height_) + 1, 0);
  for (int py = 0; py < padded_height_; ++py) {
    const std::uint8_t* row = mask_.data() + static_cast<std::size_t>(py) * static_cast<std::size_t>(padded_width_);
    for (int px = 0; px < padded_width_; ++px)
      if (row[px]) row_columns_.push_back(px);
    row_start_[static_cast<std::size_t>(py) + 1] = row_columns_.size();
  }
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
