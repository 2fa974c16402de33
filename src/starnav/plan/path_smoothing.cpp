#include "starnav/plan/path_smoothing.hpp"

#include "starnav/plan/line_of_sight.hpp"

namespace starnav {

std::vector<Cell> remove_redundant_nodes(const GridSearchMap& map, std::span<const Cell> path) {
  std::vector<Cell> out;
  if (path.empty()) return out;
  out.push_back(path.front());
  const std::size_t last = path.size() - 1;
  std::size_t anchor = 0;
  while (anchor < last) {
    const Cell& a = path[anchor];
    std::size_t next = anchor + 1;  // the next vertex is always in sight
    for (std::size_t j = last; j > anchor + 1; --j)
      if (line_of_sight(map, a.x, a.y, path[j].x, path[j].y)) {
        next = j;
        break;
      }
    out.push_back(path[next]);
    anchor = next;
  }
  return out;
}

}  // namespace starnav
