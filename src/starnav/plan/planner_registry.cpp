// The planner registry: names -> planners (grid_planner.hpp).
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/plan/dstar_lite.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/grid_planners.hpp"
#include "starnav/plan/jps.hpp"

namespace starnav {

std::vector<std::string> grid_planner_names() {
  return {"dijkstra", "astar", "wastar", "jps", "jpsplus", "thetastar", "dstarlite"};
}

std::unique_ptr<GridPlanner> make_grid_planner(std::string_view name, const OccupancyGrid& grid,
                                               const GridPlannerOptions& options) {
  using Kind = BestFirstGridPlanner::Kind;
  if (name == "dijkstra") return std::make_unique<BestFirstGridPlanner>(Kind::Dijkstra, grid, options);
  if (name == "astar") return std::make_unique<BestFirstGridPlanner>(Kind::AStar, grid, options);
  if (name == "wastar") return std::make_unique<BestFirstGridPlanner>(Kind::WeightedAStar, grid, options);
  if (name == "jps") return make_jps_planner(grid, options, false);
  if (name == "jpsplus") return make_jps_planner(grid, options, true);
  if (name == "thetastar") return std::make_unique<ThetaStarPlanner>(grid, options);
  if (name == "dstarlite") return std::make_unique<DStarLite>(grid, options);
  std::string known;
  for (const auto& n : grid_planner_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown planner '" + std::string(name) + "' (" + known + ")", {}, 0, "planner");
}

}  // namespace starnav
