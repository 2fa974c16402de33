#include "starnav/map/map_layers.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <utility>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

constexpr const char* kInflated = "inflated";

CellRect merged(const CellRect& a, const CellRect& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

}  // namespace

MapLayers::MapLayers(const GridGeometry& geometry) : geometry_(geometry) {
  if (geometry.width <= 0 || geometry.height <= 0 || !(geometry.resolution > 0.0) || geometry.y_down)
    throw Error("map layers need a grid with cells, a positive resolution and rows bottom-up", {}, 0, "geometry");
  inflated_ = OccupancyGrid(geometry, kUnknownOccupancy);
}

MapLayers::Layer* MapLayers::find(const std::string& name) {
  for (Layer& l : layers_)
    if (l.name == name) return &l;
  return nullptr;
}

const MapLayers::Layer* MapLayers::find(const std::string& name) const {
  for (const Layer& l : layers_)
    if (l.name == name) return &l;
  return nullptr;
}

bool MapLayers::has(const std::string& name) const { return name == kInflated ? inflation_set_ : find(name) != nullptr; }

const OccupancyGrid& MapLayers::layer(const std::string& name) const {
  if (name == kInflated && inflation_set_) return inflated_;
  const Layer* l = find(name);
  if (!l) throw Error("no layer '" + one_line(name, 40) + "'", {}, 0, "layer");
  return l->grid;
}

std::vector<std::string> MapLayers::names() const {
  std::vector<std::string> n;
  for (const Layer& l : layers_) n.push_back(l.name);
  if (inflation_set_) n.emplace_back(kInflated);
  return n;
}

bool MapLayers::is_obstacle_layer(const std::string& name) const {
  return std::find(obstacle_layers_.begin(), obstacle_layers_.end(), name) != obstacle_layers_.end();
}

void MapLayers::set_layer(const std::string& name, OccupancyGrid grid) {
  if (name.empty() || name == kInflated) throw Error("a layer needs a name other than 'inflated'", {}, 0, "layer");
  const GridGeometry& g = grid.geometry();
  if (g.width != geometry_.width || g.height != geometry_.height || g.resolution != geometry_.resolution ||
      g.origin.x != geometry_.origin.x || g.origin.y != geometry_.origin.y || g.origin.yaw != geometry_.origin.yaw ||
      g.y_down != geometry_.y_down)
    throw Error("layer '" + one_line(name, 40) + "' has another grid than the map's", {}, 0, "layer");
  if (Layer* l = find(name)) l->grid = std::move(grid);
  else layers_.push_back({name, std::move(grid)});
  if (is_obstacle_layer(name)) dirty_all_ = true;
}

bool MapLayers::set_cell(const std::string& name, Cell cell, std::int8_t value) {
  Layer* l = find(name);
  if (!l) throw Error("no layer '" + one_line(name, 40) + "'", {}, 0, "layer");
  if (!geometry_.contains(cell)) throw Error("cell outside the grid", {}, 0, "cell");
  std::int8_t& v = l->grid.data()[geometry_.index(cell.x, cell.y)];
  if (v == value) return false;
  v = value;
  if (is_obstacle_layer(name)) dirty_ = merged(dirty_, {cell.x, cell.y, cell.x + 1, cell.y + 1});
  return true;
}

void MapLayers::rebuild_masks(const CellRect& r) {
  // The obstacle layers' cells, looked up by name once rather than per cell.
  std::vector<std::span<const std::int8_t>> sources;
  for (const std::string& name : obstacle_layers_) sources.push_back(std::as_const(*find(name)).grid.data());
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const std::size_t i = geometry_.index(x, y);
      std::uint8_t occupied = 0, observed = 0;
      for (const std::span<const std::int8_t>& cells : sources) {
        const CellState s = thresholds_.classify(cells[i]);
        occupied |= s == CellState::Occupied ? 1 : 0;
        observed |= s != CellState::Unknown ? 1 : 0;
      }
      occupied_[i] = occupied;
      observed_[i] = observed;
    }
}

std::int8_t MapLayers::inflated_value(std::size_t i) const {
  if (blocked_[i]) return kOccupiedOccupancy;
  return observed_[i] ? kFreeOccupancy : kUnknownOccupancy;
}

void MapLayers::set_inflation(std::vector<std::string> obstacle_layers, double radius_m, const OccupancyThresholds& thresholds) {
  if (!std::isfinite(radius_m) || radius_m < 0.0) throw Error("must be a finite radius >= 0 (m)", {}, 0, "inflation_radius_m");
  for (const std::string& n : obstacle_layers)
    if (!find(n)) throw Error("no layer '" + one_line(n, 40) + "'", {}, 0, "layer");
  obstacle_layers_ = std::move(obstacle_layers);
  radius_m_ = radius_m;
  thresholds_ = thresholds;
  inflation_set_ = true;
  dirty_all_ = true;
  update_inflation();
}

std::vector<Cell> MapLayers::update_inflation() {
  std::vector<Cell> changed;
  if (!inflation_set_) throw Error("no inflation stage: call set_inflation first", {}, 0, "inflation");
  const int w = geometry_.width, h = geometry_.height;
  const double rc = inflation_radius_cells(radius_m_, geometry_.resolution);
  CellRect region;
  if (dirty_all_ || occupied_.size() != geometry_.cell_count()) {
    occupied_.assign(geometry_.cell_count(), 0);
    observed_.assign(geometry_.cell_count(), 0);
    rebuild_masks({0, 0, w, h});
    blocked_ = inflate_mask(occupied_, w, h, rc);
    region = {0, 0, w, h};
  } else if (!dirty_.empty()) {
    rebuild_masks(dirty_);
    region = inflation_.update(occupied_, w, h, rc, dirty_, blocked_);
    region = merged(region, dirty_);  // observed_ changed there even where blocked_ did not
  }
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const std::size_t i = geometry_.index(x, y);
      const std::int8_t v = inflated_value(i);
      if (inflated_.data()[i] == v) continue;
      inflated_.data()[i] = v;
      changed.push_back({x, y});
    }
  dirty_ = {};
  dirty_all_ = false;
  return changed;
}

}  // namespace starnav
