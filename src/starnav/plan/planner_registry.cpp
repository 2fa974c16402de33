// The planner registry: names -> planners (grid_planner.hpp).
#include <algorithm>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/plan/dstar_lite.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/grid_planners.hpp"
#include "starnav/plan/jps.hpp"
#include "starnav/plan/ou2022.hpp"

namespace starnav {

std::vector<std::string> grid_planner_names() {
  return {"dijkstra", "astar", "wastar", "jps", "jpsplus", "thetastar", "dstar_lite", "ou2022"};
}

PlanResult GridPlanner::replan(Cell /*start*/, std::span<const CellChange> /*changed*/) {
  throw Error("planner '" + std::string(name()) + "' is not incremental: plan again from scratch", {}, 0, "planner");
}

std::unique_ptr<GridPlanner> make_grid_planner(std::string_view name, const OccupancyGrid& grid,
                                               const GridPlannerOptions& options) {
  using Kind = BestFirstGridPlanner::Kind;
  // The improved A* of Ou et al. 2022, and its features on astar (all of them) and on
  // every other planner (hard inflation and smoothing only; ou2022.hpp).
  if (name == "ou2022") return std::make_unique<ImprovedAStarPlanner>(grid, options, true);
  if (options.ou2022.any()) {
    if (name == "astar") return std::make_unique<ImprovedAStarPlanner>(grid, options, false);
    const auto names = grid_planner_names();
    if (std::find(names.begin(), names.end(), name) != names.end() || name == "dstarlite")
      return make_inflated_smoothed_planner(name, grid, options, &make_grid_planner);
  }
  if (name == "dijkstra") return std::make_unique<BestFirstGridPlanner>(Kind::Dijkstra, grid, options);
  if (name == "astar") return std::make_unique<BestFirstGridPlanner>(Kind::AStar, grid, options);
  if (name == "wastar") return std::make_unique<BestFirstGridPlanner>(Kind::WeightedAStar, grid, options);
  if (name == "jps") return make_jps_planner(grid, options, false);
  if (name == "jpsplus") return make_jps_planner(grid, options, true);
  if (name == "thetastar") return std::make_unique<ThetaStarPlanner>(grid, options);
  if (name == "dstar_lite" || name == "dstarlite") return std::make_unique<DStarLite>(grid, options);
  std::string known;
  for (const auto& n : grid_planner_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown planner '" + std::string(name) + "' (" + known + ")", {}, 0, "planner");
}

}  // namespace starnav
