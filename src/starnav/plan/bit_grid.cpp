#include "starnav/plan/bit_grid.hpp"

#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

BitGrid::BitGrid(std::span<const std::uint8_t> blocked, int width, int height, bool transposed) {
  if (width <= 0 || height <= 0)
    throw Error("bit grid size must be positive, got " + std::to_string(width) + " x " + std::to_string(height));
  if (blocked.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw Error("bit grid: blocked mask has " + std::to_string(blocked.size()) + " cells, expected " +
                std::to_string(width) + " x " + std::to_string(height));
  cols_ = transposed ? height : width;
  rows_ = transposed ? width : height;
  const std::uint64_t stride = (static_cast<std::uint64_t>(cols_) + 2 + 63) / 64 * 64;
  const std::uint64_t total_bits = stride * (static_cast<std::uint64_t>(rows_) + 2);
  // Scans compute bit indices and their differences in 32 bits.
  if (total_bits + 64 >= (std::uint64_t{1} << 32))
    throw Error("map too large for jump point search (" + std::to_string(width) + " x " + std::to_string(height) +
                " cells)");
  stride_bits_ = static_cast<std::uint32_t>(stride);
  stride_words_ = static_cast<std::uint32_t>(stride / 64);
  // One spare word at the end so bits3() may load 8 bytes from any index of the grid.
  words_.assign(static_cast<std::size_t>(total_bits / 64) + 1, 0);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* src = blocked.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
    for (int x = 0; x < width; ++x) {
      if (src[x]) continue;
      const std::uint32_t i = transposed ? index(y, x) : index(x, y);
      words_[i >> 6] |= std::uint64_t{1} << (i & 63u);
    }
  }
}

}  // namespace starnav
