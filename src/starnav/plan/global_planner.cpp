#include "starnav/plan/global_planner.hpp"

#include "starnav/core/error.hpp"

namespace starnav {

GridGlobalPlanner::GridGlobalPlanner(std::string name, const GridPlannerOptions& options)
    : name_(std::move(name)), options_(options) {}

PlanResult GridGlobalPlanner::plan(const PlanningLayers& layers, Cell start, Cell goal,
                                   std::span<const CellChange> changed) {
  if (!layers.occupancy) throw Error("planner '" + name_ + "' needs an occupancy layer", {}, 0, "planner");
  if (planner_ && planner_->incremental() && goal == goal_) return planner_->replan(start, changed);
  planner_ = make_grid_planner(name_, *layers.occupancy, options_);
  goal_ = goal;
  PlanResult r = planner_->plan(start, goal);
  if (!planner_->incremental()) planner_.reset();  // a search per call: nothing to keep
  return r;
}

GlobalPlannerDef grid_global_planner(const std::string& name, std::string summary,
                                     std::vector<std::string> deprecated_aliases) {
  GlobalPlannerDef d;
  d.info.role = Role::GlobalPlanner;
  d.info.name = name;
  d.info.deprecated_aliases = std::move(deprecated_aliases);
  d.info.section = name;
  d.info.summary = std::move(summary);
  {
    const OccupancyGrid probe(GridGeometry{1, 1, 1.0, {}}, 0);
    const auto p = make_grid_planner(name, probe, {});
    if (p->admissible()) d.info.capabilities.push_back("admissible");
    if (p->incremental()) d.info.capabilities.push_back("incremental");
  }
  d.info.capabilities.push_back("occupancy");
  d.make = [name](const GlobalPlannerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<GlobalPlanner> {
    if (!settings.empty())
      throw Error("planner '" + name + "' takes no parameters here", settings.front().file, settings.front().line,
                  settings.front().field);
    return std::make_unique<GridGlobalPlanner>(name, ctx.grid);
  };
  return d;
}

}  // namespace starnav
