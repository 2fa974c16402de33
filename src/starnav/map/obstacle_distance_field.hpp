#pragma once
// The distance from every cell of a grid to its nearest obstacle cell (exact Euclidean, between
// cell centres), out to a range, with a nearest obstacle per cell, kept up to date as the obstacle
// mask changes: the one distance field of the navigation map that the controllers, the recoveries'
// footprint check and the cost band read (costmap/layered_costmap.hpp owns it). Cells outside the
// grid count as obstacles (the robot cannot leave its map).
//
// Incremental and lazy: a change (mark_changed) makes the tiles within the range of it stale, and a
// reader refreshes the region it reads (refresh(region)) before reading it: the stale tiles there
// are re-derived from a window wide enough to decide them exactly, so every refreshed cell equals a
// whole-grid transform capped at the range (a test checks it). A map costs what its readers read:
// the local window a controller reads, not the scan's whole reach.
#include <cstdint>
#include <limits>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/distance_transform.hpp"

namespace starnav {

class ObstacleDistanceField {
 public:
  ObstacleDistanceField() = default;
  // A field over `geometry` of the obstacle mask `mask` (row-major, non-zero = obstacle; it must
  // outlive the field and keep its size), exact out to `range_m`.
  ObstacleDistanceField(const GridGeometry& geometry, const std::vector<std::uint8_t>* mask, double range_m);

  const GridGeometry& geometry() const { return geometry_; }
  double range_m() const { return range_m_; }
  // The mask moved (its owner moved): the same cells, now there.
  void rebind(const std::vector<std::uint8_t>* mask) { mask_ = mask; }
  // The mask changed inside `changed` (cells of the grid).
  void mark_changed(const CellRect& changed);
  // Brings the cells of `region` (clipped to the grid) up to date; the distances are derived data,
  // so a reader holding the field const may refresh what it reads.
  void refresh(const CellRect& region) const;
  // ... every cell.
  void refresh() const { refresh({0, 0, geometry_.width, geometry_.height}); }
  // No cell of `region` is stale.
  bool up_to_date(const CellRect& region) const;

  bool obstacle(int x, int y) const {
    return !geometry_.contains(x, y) || (*mask_)[geometry_.index(x, y)] != 0;
  }
  // Squared distance in cells from cell i to its nearest obstacle cell (a cell outside the grid
  // counts); +inf beyond the range. Valid once a refresh covered the cell.
  double squared_cells(std::size_t i) const { return squared_[i]; }
  double distance_m(std::size_t i) const;
  // The nearest obstacle cell of cell i (it may lie just outside the grid); only when
  // squared_cells(i) is finite.
  Cell nearest_cell(std::size_t i) const;

 private:
  // Re-derives every cell of `cells` (a window of them and their range around).
  void update_cells(const CellRect& cells) const;
  CellRect tile_cells(int tx0, int ty0, int tx1, int ty1) const;

  GridGeometry geometry_;
  const std::vector<std::uint8_t>* mask_ = nullptr;
  double range_m_ = 0.0;
  int range_cells_ = 0;
  static constexpr int kTile = 32;  // cells per tile side: the unit of staleness
  int tiles_x_ = 0, tiles_y_ = 0;
  // Derived state (refreshed through const readers).
  mutable std::vector<double> squared_;        // per cell
  mutable std::vector<std::int32_t> nearest_;  // per cell: index in the grid padded by one cell on every side
  mutable std::vector<std::uint8_t> stale_;    // per tile
  mutable std::vector<std::uint8_t> window_;
  mutable DistanceTransform transform_;
};

}  // namespace starnav
