#pragma once
// The one inflation stage: a binary mask grown by a radius with the inflation-radius rule
// (distance_transform.hpp), over the whole grid or incrementally over the window a change can
// affect. Shared by terrain's obstacle expansion and the navigation map; plan/inflation applies the
// same rule to its clearance field.
#include <cstdint>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/distance_transform.hpp"

namespace starnav {

// Every cell whose centre is within `radius_cells` (cell units, inclusive up to rounding) of a
// non-zero cell of `mask` (row-major, width x height), with the exact Euclidean distance
// transform. A radius <= 0 returns the mask (as 0/1).
std::vector<std::uint8_t> inflate_mask(const std::vector<std::uint8_t>& mask, int width, int height, double radius_cells);

// The same, kept up to date as the mask changes: after the mask changed inside `changed`, update()
// recomputes exactly the cells within the radius of the change, over a window wide enough to
// decide them, so `out` equals inflate_mask(mask, ...) afterwards (a test checks it against the
// whole-grid version). The transform's buffers are kept between calls.
class IncrementalInflation {
 public:
  // Returns the rectangle of `out` that was recomputed.
  CellRect update(const std::vector<std::uint8_t>& mask, int width, int height, double radius_cells,
                  const CellRect& changed, std::vector<std::uint8_t>& out);

 private:
  std::vector<std::uint8_t> window_;
  DistanceTransform transform_;
};

}  // namespace starnav
