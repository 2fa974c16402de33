#pragma once
// Line of sight on a grid, with the same rule as 8-connected moves without corner cutting.
//
// The rule: the segment between two cell centres is free when every cell whose closed square it
// touches is passable. A centre-to-centre segment can never run along a grid line, so this means:
//   - it passes through no blocked cell, and
//   - where it passes exactly through a grid corner, all four cells meeting there are passable
//     (so it can neither squeeze between two blocked cells touching at that corner nor graze the
//     corner of one).
// For a one-cell diagonal step this is exactly "both orthogonally adjacent cells free", so every
// 8-connected move is in sight and any-angle paths never beat the grid by cutting a corner.
// Exact integer arithmetic (cell centres doubled to odd integers): no floating-point edge cases.
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/search_memory.hpp"

namespace starnav {

namespace detail {
// The walk behind line_of_sight; with kReport, *blocker receives the padded state of the first
// blocked cell met (path smoothing uses it to reject later segments in O(1)).
template <bool kReport>
inline bool line_of_sight_walk(const GridSearchMap& map, int x0, int y0, int x1, int y1, std::int64_t* blocker) {
  const std::uint8_t* pass = map.data();
  const std::int64_t stride = map.stride();
  std::int64_t id = map.state(x0, y0);
  const std::int64_t goal = map.state(x1, y1);
  auto blocked_at = [&](std::int64_t cell) {
    if constexpr (kReport) *blocker = cell;
    return false;
  };
  if (!pass[id]) return blocked_at(id);
  const int dx = std::abs(x1 - x0), dy = std::abs(y1 - y0);
  const std::int64_t sx = x1 > x0 ? 1 : -1;
  const std::int64_t sy = y1 > y0 ? stride : -stride;
  // Leaving the current cell across its next vertical boundary happens at parameter
  // (2i + 1) / (2 dx), across its next horizontal boundary at (2j + 1) / (2 dy); compare
  // next_x = (2i + 1) * dy with next_y = (2j + 1) * dx for the crossings still ahead.
  std::int64_t next_x = dy, next_y = dx;
  while (id != goal) {
    if (dy == 0 || (dx != 0 && next_x < next_y)) {  // across a vertical boundary
      id += sx;
      next_x += 2 * static_cast<std::int64_t>(dy);
    } else if (dx == 0 || next_y < next_x) {  // across a horizontal boundary
      id += sy;
      next_y += 2 * static_cast<std::int64_t>(dx);
    } else {  // exactly through a corner: the two side cells must be passable too
      if (!pass[id + sx]) return blocked_at(id + sx);
      if (!pass[id + sy]) return blocked_at(id + sy);
      id += sx + sy;
      next_x += 2 * static_cast<std::int64_t>(dy);
      next_y += 2 * static_cast<std::int64_t>(dx);
    }
    if (!pass[id]) return blocked_at(id);
  }
  return true;
}
}  // namespace detail

// Cells (x0, y0) and (x1, y1) must be inside the map.
inline bool line_of_sight(const GridSearchMap& map, int x0, int y0, int x1, int y1) {
  return detail::line_of_sight_walk<false>(map, x0, y0, x1, y1, nullptr);
}

// As line_of_sight; when the segment is not free, *blocker receives the padded state of the first
// blocked cell met (a cell whose closed square the segment touches).
inline bool line_of_sight(const GridSearchMap& map, int x0, int y0, int x1, int y1, std::int64_t* blocker) {
  return detail::line_of_sight_walk<true>(map, x0, y0, x1, y1, blocker);
}

// Straight-line distance between two cell centres, in cells.
inline double cell_distance(int x0, int y0, int x1, int y1) {
  const double dx = x1 - x0, dy = y1 - y0;
  return std::sqrt(dx * dx + dy * dy);
}

// The graph of Theta* (Nash et al. 2007): the moves of a 4- or 8-connected grid, and for each
// successor v of u, when the parent p of u sees v, the straight segment p -> v instead (v then
// gets p as its parent). Costs are lengths in cells (double).
template <int Connectivity>
class AnyAngleGridGraph {
 public:
  using cost_type = double;
  AnyAngleGridGraph() = default;
  explicit AnyAngleGridGraph(const GridSearchMap& map) : map_(&map), moves_(map) {}
  std::size_t state_count() const { return map_->state_count(); }

  template <class Visit>
  void for_each_successor(std::uint32_t u, Visit& visit) const {
    const std::uint32_t p = visit.parent_of(u);
    if (p == kNoState) {
      moves_.for_each_successor(u, visit);
      return;
    }
    const Cell pc = map_->cell(p);
    moves_.for_each_successor(u, [&](std::uint32_t v, double step) {
      if (visit.closed(v)) return;
      const Cell vc = map_->cell(v);
      if (line_of_sight(*map_, pc.x, pc.y, vc.x, vc.y)) visit.via(v, p, cell_distance(pc.x, pc.y, vc.x, vc.y));
      else visit(v, step);
    });
  }

 private:
  const GridSearchMap* map_ = nullptr;
  GridGraph<Connectivity, UniformGridCostDouble> moves_;
};

}  // namespace starnav
