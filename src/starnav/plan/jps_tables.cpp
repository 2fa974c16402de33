#include "starnav/plan/jps_tables.hpp"

#include <cstddef>

namespace starnav {

namespace {

// One byte for a distance: `jump` > 0 a jump point that far, else -`jump` free steps.
std::int8_t saturate(std::int32_t v) {
  if (v > kJumpHopSteps || v < -kJumpHopSteps) return kJumpHop;
  return static_cast<std::int8_t>(v);
}

// The value of a cell from the value of its neighbour in the same direction (which is free and
// is not itself a jump point): one step further.
std::int32_t extend(std::int32_t next) { return next > 0 ? next + 1 : next - 1; }

std::int8_t extend_saturated(std::int8_t next) {
  if (next == kJumpHop) return kJumpHop;
  return saturate(extend(next));
}

}  // namespace

JumpTable::JumpTable(const BitGrid& grid) : width_(grid.cols()), height_(grid.rows()) {
  const int w = width_, h = height_;
  const std::size_t cells = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  data_.assign(cells * 8, std::int8_t{0});
  // Exact straight distances first (the diagonal rule needs to know whether a straight jump
  // finds a jump point at any distance), then bytes.
  std::vector<std::int32_t> straight(cells * 4, 0);
  auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };
  // The padded border of the BitGrid makes every neighbour of a map cell addressable.
  auto free = [&](int x, int y) { return grid.free(grid.index(x, y)); };
  // Cell (x, y) entered along straight (dx, dy) has a forced neighbour.
  auto forced = [&](int x, int y, int dx, int dy) {
    const int px = dy, py = dx;  // a perpendicular direction
    return (free(x + px, y + py) && !free(x - dx + px, y - dy + py)) ||
           (free(x - px, y - py) && !free(x - dx - px, y - dy - py));
  };
  auto straight_cell = [&](int x, int y, int dir) {
    if (!free(x, y)) return;
    const int dx = kJpsDx[dir], dy = kJpsDy[dir];
    const int nx = x + dx, ny = y + dy;
    std::int32_t v = 0;
    if (!free(nx, ny)) v = 0;
    else if (forced(nx, ny, dx, dy)) v = 1;
    else v = extend(straight[at(nx, ny) * 4 + static_cast<std::size_t>(dir)]);
    straight[at(x, y) * 4 + static_cast<std::size_t>(dir)] = v;
    data_[at(x, y) * 8 + static_cast<std::size_t>(dir)] = saturate(v);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = w - 1; x >= 0; --x) straight_cell(x, y, kJpsEast);
    for (int x = 0; x < w; ++x) straight_cell(x, y, kJpsWest);
  }
  for (int y = h - 1; y >= 0; --y)
    for (int x = 0; x < w; ++x) straight_cell(x, y, kJpsSouth);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) straight_cell(x, y, kJpsNorth);

  auto diagonal_cell = [&](int x, int y, int dir) {
    if (!free(x, y)) return;
    const int dx = kJpsDx[dir], dy = kJpsDy[dir];
    const std::size_t hdir = dx > 0 ? kJpsEast : kJpsWest;
    const std::size_t vdir = dy > 0 ? kJpsSouth : kJpsNorth;
    const int nx = x + dx, ny = y + dy;
    std::int8_t v = 0;
    if (!free(x + dx, y) || !free(x, y + dy) || !free(nx, ny)) v = 0;  // no corner cutting
    else if (straight[at(nx, ny) * 4 + hdir] > 0 || straight[at(nx, ny) * 4 + vdir] > 0) v = 1;
    else v = extend_saturated(data_[at(nx, ny) * 8 + static_cast<std::size_t>(dir)]);
    data_[at(x, y) * 8 + static_cast<std::size_t>(dir)] = v;
  };
  // North-going diagonals read the row above (already done when rows go top to bottom).
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      diagonal_cell(x, y, kJpsNorthEast);
      diagonal_cell(x, y, kJpsNorthWest);
    }
  for (int y = h - 1; y >= 0; --y)
    for (int x = 0; x < w; ++x) {
      diagonal_cell(x, y, kJpsSouthEast);
      diagonal_cell(x, y, kJpsSouthWest);
    }
}

}  // namespace starnav
