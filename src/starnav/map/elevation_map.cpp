#include "starnav/map/elevation_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

ElevationMap::ElevationMap(const GridGeometry& geometry) : geometry_(geometry) {
  validate_geometry(geometry_, "elevation map");
  const std::size_t n = geometry_.cell_count();
  height_.assign(n, 0.0);
  min_.assign(n, 0.0);
  max_.assign(n, 0.0);
  observed_.assign(n, 0);
}

void ElevationMap::check_inside(int ix, int iy) const {
  if (!contains(ix, iy))
    throw std::out_of_range("cell (" + std::to_string(ix) + ", " + std::to_string(iy) + ") outside the map");
}

std::optional<double> ElevationMap::height_checked(int ix, int iy) const {
  check_inside(ix, iy);
  if (!observed_at(ix, iy)) return std::nullopt;
  return height_at(ix, iy);
}

void ElevationMap::set_height(int ix, int iy, double h) { set_cell(ix, iy, h, h, h); }

void ElevationMap::set_cell(int ix, int iy, double h, double min_h, double max_h) {
  check_inside(ix, iy);
  if (!std::isfinite(h) || !std::isfinite(min_h) || !std::isfinite(max_h))
    throw Error("height must be finite (cell " + std::to_string(ix) + ", " + std::to_string(iy) + ")", {}, 0,
                "height");
  if (!(min_h <= h && h <= max_h))
    throw Error("need min <= height <= max (cell " + std::to_string(ix) + ", " + std::to_string(iy) + ")", {}, 0,
                "height");
  const std::size_t i = geometry_.index(ix, iy);
  height_[i] = h;
  min_[i] = min_h;
  max_[i] = max_h;
  observed_[i] = 1;
}

void ElevationMap::clear_cell(int ix, int iy) {
  check_inside(ix, iy);
  const std::size_t i = geometry_.index(ix, iy);
  height_[i] = min_[i] = max_[i] = 0.0;
  observed_[i] = 0;
}

std::optional<HeightRange> ElevationMap::height_range() const {
  HeightRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  bool any = false;
  for (std::size_t i = 0; i < height_.size(); ++i) {
    if (!observed_[i]) continue;
    any = true;
    r.min = std::min(r.min, min_[i]);
    r.max = std::max(r.max, max_[i]);
  }
  if (!any) return std::nullopt;
  return r;
}

std::size_t ElevationMap::observed_count() const {
  return static_cast<std::size_t>(std::count(observed_.begin(), observed_.end(), std::uint8_t{1}));
}

bool operator==(const ElevationMap& a, const ElevationMap& b) {
  const auto& ga = a.geometry_;
  const auto& gb = b.geometry_;
  return ga.width == gb.width && ga.height == gb.height && ga.resolution == gb.resolution &&
         ga.origin.x == gb.origin.x && ga.origin.y == gb.origin.y && ga.origin.yaw == gb.origin.yaw &&
         ga.y_down == gb.y_down && a.height_ == b.height_ && a.min_ == b.min_ && a.max_ == b.max_ && a.observed_ == b.observed_;
}

}  // namespace starnav
