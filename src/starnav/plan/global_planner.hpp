#pragma once
// The global-planner role: a path on a map layer from the robot's cell to the goal's cell. The
// grid planners (A*, JPS, D* Lite, the improved A* of Ou et al. 2022, ...) plan on an occupancy
// layer; the rough-terrain planners of Liu et al. 2024 on an elevation layer (capability
// "needs_elevation"). An incremental planner (capability "incremental", D* Lite) keeps its
// search between calls and is given the cells that changed since the previous call; the others
// plan from scratch every time. A planner that plans between poses (capability "needs_headings",
// Hybrid-A*) is given the start and goal poses through plan_poses() and returns a path of poses
// with a direction per pose. Built by name from the component registry.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "starnav/core/component.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/footprint_checker.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/plan_result.hpp"

namespace starnav {

// The layers a global planner may read; the ones a planner needs must be set.
struct PlanningLayers {
  const OccupancyGrid* occupancy = nullptr;
  const ElevationMap* elevation = nullptr;
};

// A query between poses (map frame, headings in radians): the cells are what every planner
// plans between; a planner with capability "needs_headings" uses the poses.
struct PlanQuery {
  Cell start{};
  Cell goal{};
  Pose2 start_pose;
  Pose2 goal_pose;
  bool goal_heading = true;  // false: the goal's heading is free (goal_pose.yaw means nothing)
};

class GlobalPlanner {
 public:
  virtual ~GlobalPlanner() = default;
  virtual std::string_view name() const = 0;
  // Plans on the layers as they are now. `changed`: the occupancy cells that changed since the
  // previous call, with their new values (an incremental planner repairs its search with them;
  // the others ignore them). Throws Error when a layer the planner needs is missing.
  virtual PlanResult plan(const PlanningLayers& layers, Cell start, Cell goal, std::span<const CellChange> changed) = 0;
  // Plans between the query's poses. Planners that do not use headings plan between its cells
  // (this default); the others override it.
  virtual PlanResult plan_poses(const PlanningLayers& layers, const PlanQuery& query,
                                std::span<const CellChange> changed) {
    return plan(layers, query.start, query.goal, changed);
  }
};

// What a global planner is built from: the grid search options (connectivity, unknown cells),
// the scenario file its settings came from, and in navigation the robot: its body's outline in
// base_link and, for a robot that cannot turn on the spot, its smallest turning radius (0: it can).
struct GlobalPlannerContext {
  GridPlannerOptions grid;
  std::string file;
  std::optional<FootprintModel> robot_footprint;
  double robot_min_turning_radius_m = 0.0;
};
using GlobalPlannerDef = ComponentDef<GlobalPlanner, GlobalPlannerContext>;

// A grid planner of make_grid_planner as a GlobalPlanner: a new search per call, or for an
// incremental planner one search repaired while the goal stays the same.
class GridGlobalPlanner final : public GlobalPlanner {
 public:
  GridGlobalPlanner(std::string name, const GridPlannerOptions& options);
  std::string_view name() const override { return name_; }
  PlanResult plan(const PlanningLayers& layers, Cell start, Cell goal, std::span<const CellChange> changed) override;

 private:
  std::string name_;
  GridPlannerOptions options_;
  std::unique_ptr<GridPlanner> planner_;  // kept by incremental planners
  Cell goal_{};
};

// The graded cost band of GridPlannerOptions::ou2022.inflation as the planners that honour it
// declare it (cost_radius_m, cost_scale_per_m, cost_weight): moves near obstacles cost more, so
// paths keep to the middle of corridors (ROS costmap_2d's inflation costs, ou2022_options.hpp).
const ParamTable<InflationOptions>& cost_band_params();

// The registry entry of grid planner `name` (capabilities from a planner built on a 1 x 1 grid).
GlobalPlannerDef grid_global_planner(const std::string& name, std::string summary,
                                     std::vector<std::string> deprecated_aliases = {});

}  // namespace starnav
