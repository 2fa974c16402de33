#include "starnav/plan/grid_graph.hpp"

#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

void GridSearchMap::allocate(int width, int height) {
  if (width <= 0 || height <= 0)
    throw Error("grid size must be positive, got " + std::to_string(width) + " x " + std::to_string(height));
  // Padded states must stay below 2^31 (FastDivider) and leave room for the kNoState marks.
  if ((static_cast<double>(width) + 2.0) * (static_cast<double>(height) + 2.0) >= 2147483647.0)
    throw Error("grid too large to search (" + std::to_string(width) + " x " + std::to_string(height) + ")");
  width_ = width;
  height_ = height;
  stride_ = static_cast<std::uint32_t>(width) + 2;
  row_divider_ = FastDivider(stride_);
  passable_.assign(static_cast<std::size_t>(stride_) * (static_cast<std::size_t>(height) + 2), 0);
}

GridSearchMap::GridSearchMap(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, bool unknown_is_free) {
  allocate(grid.width(), grid.height());
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const CellState s = thresholds.classify(grid(x, y));
      set_passable(x, y, s == CellState::Free || (s == CellState::Unknown && unknown_is_free));
    }
}

GridSearchMap::GridSearchMap(int width, int height, const std::vector<std::uint8_t>& blocked) {
  allocate(width, height);
  if (blocked.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw Error("blocked mask has " + std::to_string(blocked.size()) + " cells, expected " +
                std::to_string(static_cast<std::size_t>(width) * static_cast<std::size_t>(height)));
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) set_passable(x, y, blocked[static_cast<std::size_t>(y) * width + x] == 0);
}

}  // namespace starnav
