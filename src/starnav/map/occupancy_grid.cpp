#include "starnav/map/occupancy_grid.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

void validate_geometry(const GridGeometry& g, const char* what) {
  if (g.width <= 0 || g.height <= 0)
    throw Error(std::string(what) + " size must be positive, got " + std::to_string(g.width) + " x " +
                std::to_string(g.height));
  if (static_cast<double>(g.width) * static_cast<double>(g.height) > 2147483647.0)
    throw Error(std::string(what) + " has too many cells (" + std::to_string(g.width) + " x " +
                std::to_string(g.height) + ")");
  if (!(g.resolution > 0.0) || !std::isfinite(g.resolution))
    throw Error(std::string(what) + " resolution must be positive and finite", {}, 0, "resolution");
  if (!std::isfinite(g.origin.x) || !std::isfinite(g.origin.y) || !std::isfinite(g.origin.yaw))
    throw Error(std::string(what) + " origin must be finite", {}, 0, "origin");
}

OccupancyGrid::OccupancyGrid(const GridGeometry& geometry, std::int8_t fill) : geometry_(geometry) {
  validate_geometry(geometry_, "occupancy grid");
  if (fill < -1 || fill > 100) throw Error("occupancy fill value must be -1..100");
  data_.assign(geometry_.cell_count(), fill);
}

std::int8_t OccupancyGrid::at(int ix, int iy) const {
  if (!contains(ix, iy))
    throw std::out_of_range("cell (" + std::to_string(ix) + ", " + std::to_string(iy) + ") outside the map");
  return (*this)(ix, iy);
}

void OccupancyGrid::set(int ix, int iy, std::int8_t value) {
  if (!contains(ix, iy))
    throw std::out_of_range("cell (" + std::to_string(ix) + ", " + std::to_string(iy) + ") outside the map");
  if (value < -1 || value > 100) throw Error("occupancy value must be -1..100, got " + std::to_string(value));
  (*this)(ix, iy) = value;
}

OccupancyCounts OccupancyGrid::counts(const OccupancyThresholds& t) const {
  OccupancyCounts c;
  for (const std::int8_t v : data_) {
    switch (t.classify(v)) {
      case CellState::Free: ++c.free; break;
      case CellState::Occupied: ++c.occupied; break;
      case CellState::Unknown: ++c.unknown; break;
    }
  }
  return c;
}

std::vector<std::uint8_t> OccupancyGrid::blocked_mask(const OccupancyThresholds& t, bool unknown_is_free) const {
  std::vector<std::uint8_t> mask;
  blocked_mask(mask, t, unknown_is_free);
  return mask;
}

void OccupancyGrid::blocked_mask(std::vector<std::uint8_t>& mask, const OccupancyThresholds& t,
                                 bool unknown_is_free) const {
  mask.resize(data_.size());
  for (std::size_t i = 0; i < data_.size(); ++i) {
    const CellState s = t.classify(data_[i]);
    mask[i] = (s == CellState::Occupied || (s == CellState::Unknown && !unknown_is_free)) ? 1 : 0;
  }
}

}  // namespace starnav
