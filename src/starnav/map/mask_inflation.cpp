#include "starnav/map/mask_inflation.hpp"

#include <algorithm>

namespace starnav {

std::vector<std::uint8_t> inflate_mask(const std::vector<std::uint8_t>& mask, int width, int height, double radius_cells) {
  std::vector<std::uint8_t> out(mask.size());
  if (!(radius_cells > 0.0)) {
    for (std::size_t i = 0; i < mask.size(); ++i) out[i] = mask[i] ? 1 : 0;
    return out;
  }
  const std::vector<double> d2 = squared_distance_transform(mask, width, height);
  for (std::size_t i = 0; i < mask.size(); ++i) out[i] = within_inflation_radius(d2[i], radius_cells) ? 1 : 0;
  return out;
}

CellRect IncrementalInflation::update(const std::vector<std::uint8_t>& mask, int width, int height, double radius_cells,
                                      const CellRect& changed, std::vector<std::uint8_t>& out) {
  // Cells within the radius of a changed cell may change; their nearest mask cells within the
  // radius lie within `margin` more cells, so a window of that size decides them exactly.
  const int margin = inflation_margin_cells(radius_cells);
  const CellRect region = changed.grown(margin, width, height);
  const CellRect window = region.grown(margin, width, height);
  const int ww = window.x1 - window.x0, wh = window.y1 - window.y0;
  if (ww <= 0 || wh <= 0) return region;
  const auto row = [width](int x, int y) {
    return static_cast<std::ptrdiff_t>(y) * width + x;
  };
  window_.resize(static_cast<std::size_t>(ww) * static_cast<std::size_t>(wh));
  for (int y = window.y0; y < window.y1; ++y)
    std::copy_n(mask.begin() + row(window.x0, y), ww, window_.begin() + static_cast<std::ptrdiff_t>(y - window.y0) * ww);
  const bool inflate = radius_cells > 0.0;
  if (inflate) transform_.compute(window_, ww, wh);
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const std::size_t k =
          static_cast<std::size_t>(y - window.y0) * static_cast<std::size_t>(ww) + static_cast<std::size_t>(x - window.x0);
      out[static_cast<std::size_t>(row(x, y))] =
          inflate ? (within_inflation_radius(transform_.squared_cells()[k], radius_cells) ? 1 : 0) : (window_[k] ? 1 : 0);
    }
  return region;
}

}  // namespace starnav
