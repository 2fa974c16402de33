#pragma once
// Keep-out zones (Nav2's keepout costmap filter, from polygons rather than a mask map): areas the
// robot must not enter, given as polygons in the map frame (navigation.keepout.zones). Every cell
// a zone overlaps is an obstacle of the navigation map, expanded by the barrier distance like
// sensed ones, so the planner routes around the zone and the controllers' footprint check keeps
// the whole body out of it, not only its centre (docs/navigation.md, "Keep-out zones"). The zones
// do not count as observed.
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/costmap/costmap_layer.hpp"

namespace starnav {

// The cells of `geometry` that overlap the polygon with some area (even-odd inside; touching an edge or
// a corner only does not count), as a row-major mask (1 = overlapped). Cells outside the grid are dropped.
std::vector<std::uint8_t> rasterize_polygon_cells(const GridGeometry& geometry, std::span<const Vec2> polygon);
// The same cells set to 1 in `mask` (row-major over `geometry`).
void mark_polygon_cells(const GridGeometry& geometry, std::span<const Vec2> polygon, std::vector<std::uint8_t>& mask);
// Rasterizing costs about two visits per grid row an edge spans: Error (field "zones") when the
// polygons' edges span more than kMaxRasterizedEdgeRows / 2 rows in all.
inline constexpr double kMaxRasterizedEdgeRows = 2e8;
void check_rasterizing_cost(const GridGeometry& geometry, std::span<const std::span<const Vec2>> polygons);

class KeepoutLayer final : public CostmapLayer {
 public:
  KeepoutLayer(const GridGeometry& geometry, const std::vector<ParamPolygon>& zones);
  std::string_view name() const override { return "keepout"; }
  void contribute(const CellRect& rect, std::span<std::uint8_t> obstacles, std::span<std::uint8_t> observed) const override;
  const std::vector<std::uint8_t>& mask() const { return mask_; }

 private:
  GridGeometry geometry_;
  std::vector<std::uint8_t> mask_;
};

}  // namespace starnav
