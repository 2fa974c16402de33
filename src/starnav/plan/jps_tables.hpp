#pragma once
// Directions and the JPS+ jump tables (Harabor & Grastien 2014; Rabin & Silva 2015) for
// 8-connected grids without corner cutting.
//
// Directions: N is y - 1 (the row above in memory; on MovingAI maps, up on the screen), E is
// x + 1. For every free cell and each of the 8 directions the table holds one signed byte:
//   1..127     the next jump point in that direction is that many steps away;
//   -127..0    there is none before an obstacle: the cell can move that many (absolute value)
//              steps in that direction;
//   kJumpHop   neither a jump point nor an obstacle within kJumpHopSteps steps: continue reading
//              the table kJumpHopSteps cells further on (so one byte serves maps of any size).
// A straight jump point is a cell entered from its predecessor that has a forced neighbour: a
// free cell beside it whose counterpart beside the predecessor is blocked. A diagonal jump point
// is the first cell along a diagonal from which a straight jump along either component of the
// diagonal reaches a straight jump point (at any distance). Goals are not in the table; queries
// check them.
#include <cstdint>
#include <vector>

#include "starnav/plan/bit_grid.hpp"

namespace starnav {

enum JpsDirection : std::uint8_t {
  kJpsNorth = 0,
  kJpsEast = 1,
  kJpsSouth = 2,
  kJpsWest = 3,
  kJpsNorthEast = 4,
  kJpsSouthEast = 5,
  kJpsSouthWest = 6,
  kJpsNorthWest = 7,
};
inline constexpr int kJpsDx[8] = {0, 1, 0, -1, 1, 1, -1, -1};
inline constexpr int kJpsDy[8] = {-1, 0, 1, 0, -1, 1, 1, -1};

inline constexpr std::int8_t kJumpHop = -128;
inline constexpr int kJumpHopSteps = 127;

// Eight signed bytes per cell, cell-major (the 8 directions of one cell share a cache line).
class JumpTable {
 public:
  JumpTable() = default;
  // `grid` is the (non-transposed) BitGrid of the map.
  explicit JumpTable(const BitGrid& grid);

  int width() const { return width_; }
  int height() const { return height_; }
  std::int8_t at(std::uint32_t cell, int dir) const {
    return data_[static_cast<std::size_t>(cell) * 8 + static_cast<std::size_t>(dir)];
  }
  std::size_t memory_bytes() const { return data_.size(); }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<std::int8_t> data_;
};

}  // namespace starnav
