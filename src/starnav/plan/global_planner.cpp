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

const ParamTable<InflationOptions>& cost_band_params() {
  static const ParamTable<InflationOptions> table = [] {
    using C = InflationOptions;
    ParamTable<C> t;
    t.real("cost_radius_m", &C::cost_radius_m, closed(0.0, 10.0), "m",
           "moves within this distance of an obstacle cost more (0: off)");
    t.real("cost_scale_per_m", &C::cost_scale, closed(0.0, 100.0), "1/m", "decay of the extra cost with distance");
    t.real("cost_weight", &C::cost_weight, closed(0.0, 1000.0), "",
           "a move next to an obstacle costs 1 + cost_weight times its length");
    return t;
  }();
  return table;
}

namespace {

bool honours_cost_band(const std::string& name) {
  GridPlannerOptions o;
  o.ou2022.inflation.cost_radius_m = 1.0;
  try {
    make_grid_planner(name, OccupancyGrid(GridGeometry{1, 1, 1.0, {}}, 0), o);
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

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
    if (p->admissible()) d.info.capabilities.add(Capability::Admissible);
    if (p->incremental()) d.info.capabilities.add(Capability::Incremental);
    if (p->takes_weight()) d.info.capabilities.add(Capability::HeuristicWeight);
  }
  d.info.capabilities.add(Capability::Occupancy);
  const bool band = honours_cost_band(name);
  if (band) d.info.params = cost_band_params().specs();
  d.make = [name, band](const GlobalPlannerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<GlobalPlanner> {
    if (!band && !settings.empty())
      throw Error("planner '" + name + "' takes no parameters here", settings.front().file, settings.front().line,
                  settings.front().field);
    GridPlannerOptions options = ctx.grid;
    if (band) {
      const InflationOptions declared = configured(cost_band_params(), settings, ctx.file);
      options.ou2022.inflation.cost_radius_m = declared.cost_radius_m;
      options.ou2022.inflation.cost_scale = declared.cost_scale;
      options.ou2022.inflation.cost_weight = declared.cost_weight;
    }
    return std::make_unique<GridGlobalPlanner>(name, options);
  };
  return d;
}

}  // namespace starnav
