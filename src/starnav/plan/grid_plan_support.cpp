#include "starnav/plan/grid_plan_support.hpp"

#include <cmath>
#include <utility>

namespace starnav {

std::optional<PlanStatus> check_endpoints(const GridSearchMap& map, Cell start, Cell goal) {
  if (!map.contains(start.x, start.y)) return PlanStatus::StartOutsideMap;
  if (!map.contains(goal.x, goal.y)) return PlanStatus::GoalOutsideMap;
  if (!map.passable(start.x, start.y)) return PlanStatus::StartBlocked;
  if (!map.passable(goal.x, goal.y)) return PlanStatus::GoalBlocked;
  return std::nullopt;
}

void set_found_path(PlanResult& result, const GridGeometry& geometry, std::vector<Cell> cells) {
  result.status = PlanStatus::Found;
  result.path_world.clear();
  result.path_world.reserve(cells.size());
  double cells_length = 0.0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    result.path_world.push_back(geometry.cell_center(cells[i]));
    if (i > 0) {
      const double dx = cells[i].x - cells[i - 1].x, dy = cells[i].y - cells[i - 1].y;
      // Exact 1 and sqrt(2) for grid moves; Euclidean for any-angle segments.
      cells_length += (dx == 0.0 || dy == 0.0) ? std::abs(dx + dy) : std::sqrt(dx * dx + dy * dy);
    }
  }
  result.length = cells_length * geometry.resolution;
  result.cost = result.length;
  result.path_cells = std::move(cells);
}

}  // namespace starnav
