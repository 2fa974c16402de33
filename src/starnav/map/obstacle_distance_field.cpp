#include "starnav/map/obstacle_distance_field.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {
constexpr double kFar = std::numeric_limits<double>::infinity();
}

ObstacleDistanceField::ObstacleDistanceField(const GridGeometry& geometry, const std::vector<std::uint8_t>* mask, double range_m)
    : geometry_(geometry), mask_(mask), range_m_(range_m) {
  if (!mask_ || mask_->size() != geometry_.cell_count()) throw Error("the obstacle mask does not cover the grid", "", 0, "mask");
  if (!(range_m_ > 0.0) || !std::isfinite(range_m_)) throw Error("must be > 0", "", 0, "clearance_range_m");
  range_cells_ = static_cast<int>(std::ceil(range_m_ / geometry_.resolution));
  squared_.assign(geometry_.cell_count(), kFar);
  nearest_.assign(geometry_.cell_count(), kNoObstacle);
  tiles_x_ = (geometry_.width + kTile - 1) / kTile;
  tiles_y_ = (geometry_.height + kTile - 1) / kTile;
  stale_.assign(static_cast<std::size_t>(tiles_x_) * static_cast<std::size_t>(tiles_y_), 1);
}

void ObstacleDistanceField::mark_changed(const CellRect& changed) {
  if (changed.empty()) return;
  // Every cell within the range of a changed cell may change.
  const CellRect r = changed.grown(range_cells_ + 1, geometry_.width, geometry_.height);
  if (r.empty()) return;
  for (int ty = r.y0 / kTile; ty <= (r.y1 - 1) / kTile; ++ty)
    for (int tx = r.x0 / kTile; tx <= (r.x1 - 1) / kTile; ++tx)
      stale_[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x_) + static_cast<std::size_t>(tx)] = 1;
}

CellRect ObstacleDistanceField::tile_cells(int tx0, int ty0, int tx1, int ty1) const {
  return {tx0 * kTile, ty0 * kTile, std::min(geometry_.width, tx1 * kTile), std::min(geometry_.height, ty1 * kTile)};
}

bool ObstacleDistanceField::up_to_date(const CellRect& region) const {
  const CellRect r = region.grown(0, geometry_.width, geometry_.height);
  if (r.empty()) return true;
  for (int ty = r.y0 / kTile; ty <= (r.y1 - 1) / kTile; ++ty)
    for (int tx = r.x0 / kTile; tx <= (r.x1 - 1) / kTile; ++tx)
      if (stale_[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x_) + static_cast<std::size_t>(tx)]) return false;
  return true;
}

void ObstacleDistanceField::refresh(const CellRect& region) const {
  const CellRect r = region.grown(0, geometry_.width, geometry_.height);
  if (r.empty()) return;
  // The stale tiles of the region, re-derived together (one window around their bounding box: the
  // windows' overlap would cost more than the clean tiles inside it).
  int tx0 = tiles_x_, ty0 = tiles_y_, tx1 = -1, ty1 = -1;
  for (int ty = r.y0 / kTile; ty <= (r.y1 - 1) / kTile; ++ty)
    for (int tx = r.x0 / kTile; tx <= (r.x1 - 1) / kTile; ++tx)
      if (stale_[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x_) + static_cast<std::size_t>(tx)]) {
        tx0 = std::min(tx0, tx), ty0 = std::min(ty0, ty), tx1 = std::max(tx1, tx), ty1 = std::max(ty1, ty);
      }
  if (tx1 < 0) return;
  update_cells(tile_cells(tx0, ty0, tx1 + 1, ty1 + 1));
  for (int ty = ty0; ty <= ty1; ++ty)
    for (int tx = tx0; tx <= tx1; ++tx)
      stale_[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x_) + static_cast<std::size_t>(tx)] = 0;
}

void ObstacleDistanceField::update_cells(const CellRect& region) const {
  const int w = geometry_.width, h = geometry_.height, reach = range_cells_ + 1;
  // The window (the grid and its frame of outside cells) that holds every obstacle within the
  // range of the region's cells.
  if (region.empty()) return;
  const int wx0 = std::max(-1, region.x0 - reach), wy0 = std::max(-1, region.y0 - reach);
  const int wx1 = std::min(w + 1, region.x1 + reach), wy1 = std::min(h + 1, region.y1 + reach);
  const int ww = wx1 - wx0, wh = wy1 - wy0;
  window_.resize(static_cast<std::size_t>(ww) * static_cast<std::size_t>(wh));
  for (int y = wy0; y < wy1; ++y) {
    std::uint8_t* row = window_.data() + static_cast<std::size_t>(y - wy0) * static_cast<std::size_t>(ww);
    for (int x = wx0; x < wx1; ++x) row[x - wx0] = obstacle(x, y) ? 1 : 0;
  }
  transform_.compute(window_, ww, wh, true);
  const double range_squared = (range_m_ / geometry_.resolution) * (range_m_ / geometry_.resolution) + 1e-9;
  const std::vector<double>& sq = transform_.squared_cells();
  const std::vector<std::int32_t>& near = transform_.nearest();
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const std::size_t k = static_cast<std::size_t>(y - wy0) * static_cast<std::size_t>(ww) + static_cast<std::size_t>(x - wx0);
      const std::size_t i = geometry_.index(x, y);
      if (sq[k] <= range_squared) {
        squared_[i] = sq[k];
        const int nx = wx0 + near[k] % ww, ny = wy0 + near[k] / ww;
        nearest_[i] = (ny + 1) * (w + 2) + (nx + 1);
      } else {
        squared_[i] = kFar;
        nearest_[i] = kNoObstacle;
      }
    }
}

double ObstacleDistanceField::distance_m(std::size_t i) const { return std::sqrt(squared_[i]) * geometry_.resolution; }

Cell ObstacleDistanceField::nearest_cell(std::size_t i) const {
  const int w = geometry_.width + 2;
  return {nearest_[i] % w - 1, nearest_[i] / w - 1};
}

}  // namespace starnav
