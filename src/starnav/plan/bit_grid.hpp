#pragma once
// A passability bitmap for Jump Point Search: one bit per cell (1 = free), each row packed into
// 64-bit words, surrounded by a border of blocked cells so scans need no bounds checks.
//
// Layout: logical cell (col, row) lives at bit index (row + 1) * stride + (col + 1), where the
// stride (bits per padded row) is a multiple of 64 and at least cols + 2. Padded row 0 and row
// rows + 1, padded column 0 and columns cols + 1 .. stride - 1 are blocked. A transposed BitGrid
// stores the map's columns as its rows, so vertical jumps scan words too (Harabor & Grastien
// 2014, "Improving Jump Point Search").
//
// Scans implement the straight-jump rule of JPS on 8-connected grids without corner cutting:
// moving along a row, a cell is a jump point when a cell beside it (in the row above or below)
// is free while the cell beside its predecessor is blocked; the scan stops at the first such
// cell, at the first obstacle (no jump point) or at a target cell on the row.
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace starnav {

class BitGrid {
 public:
  BitGrid() = default;
  // `blocked` is row-major, width x height, non-zero = blocked. With `transposed`, logical
  // column c / row r of the BitGrid is map cell (x = r, y = c). Throws Error when the padded
  // grid would not fit 32-bit bit indices.
  BitGrid(std::span<const std::uint8_t> blocked, int width, int height, bool transposed);

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  // Bits per padded row (a multiple of 64).
  std::uint32_t stride() const { return stride_bits_; }
  std::uint32_t index(int col, int row) const {
    return static_cast<std::uint32_t>(row + 1) * stride_bits_ + static_cast<std::uint32_t>(col + 1);
  }
  bool free(std::uint32_t i) const { return (words_[i >> 6] >> (i & 63u)) & 1u; }
  bool free(int col, int row) const {
    return col >= 0 && row >= 0 && col < cols_ && row < rows_ && free(index(col, row));
  }
  // Bits i, i+1, i+2 (bit 0 of the result = cell i); i may be any index of the padded grid.
  std::uint32_t bits3(std::uint32_t i) const {
    std::uint64_t v;
    std::memcpy(&v, reinterpret_cast<const unsigned char*>(words_.data()) + (i >> 3), sizeof v);
    return static_cast<std::uint32_t>(v >> (i & 7u)) & 7u;
  }
  std::size_t memory_bytes() const { return words_.size() * sizeof(std::uint64_t); }

  // Scans from free cell `i` toward increasing columns. Returns the number of steps to the
  // first jump point or to `target` (a bit index; ignored unless it lies ahead on this row),
  // whichever comes first; 0 when an obstacle comes first.
  std::uint32_t scan_forward(std::uint32_t i, std::uint32_t target) const {
    const std::uint64_t* w = words_.data() + (i >> 6);
    const std::size_t s = stride_words_;
    const unsigned b = i & 63u;
    std::uint64_t up = *(w - s), mid = *w, dn = *(w + s);
    // A free bit whose lower neighbour (the cell before it in the direction of travel) is blocked.
    std::uint64_t stop = ((up & ~(up << 1)) | (dn & ~(dn << 1)) | ~mid) & ((~std::uint64_t{0} << b) << 1);
    std::uint32_t base = i - b;
    while (stop == 0) {
      const std::uint64_t cu = up >> 63, cd = dn >> 63;
      ++w;
      base += 64;
      up = *(w - s);
      mid = *w;
      dn = *(w + s);
      stop = (up & ~((up << 1) | cu)) | (dn & ~((dn << 1) | cd)) | ~mid;
    }
    const unsigned pos = static_cast<unsigned>(__builtin_ctzll(stop));
    const std::uint32_t steps = base + pos - i;
    const std::uint32_t to_target = target - i;
    if (to_target - 1u < steps) return to_target;  // target ahead, at or before the stop
    return ((mid >> pos) & 1u) ? steps : 0u;
  }

  // As scan_forward, toward decreasing columns.
  std::uint32_t scan_backward(std::uint32_t i, std::uint32_t target) const {
    const std::uint64_t* w = words_.data() + (i >> 6);
    const std::size_t s = stride_words_;
    const unsigned b = i & 63u;
    std::uint64_t up = *(w - s), mid = *w, dn = *(w + s);
    std::uint64_t stop = ((up & ~(up >> 1)) | (dn & ~(dn >> 1)) | ~mid) & ((std::uint64_t{1} << b) - 1u);
    std::uint32_t base = i - b;
    while (stop == 0) {
      const std::uint64_t cu = up << 63, cd = dn << 63;
      --w;
      base -= 64;
      up = *(w - s);
      mid = *w;
      dn = *(w + s);
      stop = (up & ~((up >> 1) | cu)) | (dn & ~((dn >> 1) | cd)) | ~mid;
    }
    const unsigned pos = 63u - static_cast<unsigned>(__builtin_clzll(stop));
    const std::uint32_t steps = i - (base + pos);
    const std::uint32_t to_target = i - target;
    if (to_target - 1u < steps) return to_target;
    return ((mid >> pos) & 1u) ? steps : 0u;
  }

 private:
  int cols_ = 0;
  int rows_ = 0;
  std::uint32_t stride_bits_ = 0;
  std::uint32_t stride_words_ = 0;
  std::vector<std::uint64_t> words_;
};

}  // namespace starnav
