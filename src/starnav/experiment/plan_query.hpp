#pragma once
// One `starnav plan` query as declared parameters: the options of a planning query on an
// occupancy map (the request of plan_on_grid, plan/plan_pipeline.hpp) and on an elevation map
// (the options of plan_on_terrain, terrain_report.hpp), each declared once with its key, type,
// default, range and one line of doc. The CLI's flags and the Python bindings' keyword arguments
// (docs/python.md) both arrive here as settings, so a bad value reads the same from either,
// naming the setting's field: `--turn-cost: must be a finite number >= 0` on the command line,
// `turn_cost: must be a finite number >= 0` in Python.
//
// Keys are the library's field names, which the CLI spells as flags (turn_cost is --turn-cost);
// the planners' own declared parameters keep their registry names (cost_radius_m is
// --inflate-cost-radius, h_y is --hy-m; plan_query_flag() gives the flag of every key).
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/plan_pipeline.hpp"
#include "starnav/plan/plan_result.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"

namespace starnav {

// ---- occupancy maps ----------------------------------------------------------------------------

// connectivity, unknown, weight, heuristic, inflate, cost_radius_m, cost_scale_per_m, cost_weight
// (the cost band the planners that honour it declare), turn_cost, turn_exact, adaptive_weight,
// smooth, smooth_clearance, start_heading_deg, max_expansions, time_budget, expanded. Defaults are
// `starnav plan`'s; options whose default depends on the planner (ou2022 turns its features on)
// say so. request.planner is not among them.
const ParamTable<PlanRequest>& occupancy_plan_params();

// The request of a query of `planner` (a registry name or deprecated alias of an occupancy planner;
// `warning` gets the deprecation) on a map of `geometry`: `settings` applied to the CLI's defaults
// and checked as the CLI checks them. `index_grid`: MovingAI maps and other y-down grids, whose
// start heading is already in cell axes (on metric maps it is a world yaw, turned into the grid's
// axes here). Errors name the setting's field (its key when the field is empty): an unknown
// planner or one that needs an elevation map names `planner_field` (and `map_name`, the map's file).
PlanRequest occupancy_plan_request(const std::string& planner, std::span<const ParamSetting> settings,
                                   const GridGeometry& geometry, bool index_grid, const OccupancyThresholds& thresholds,
                                   const std::string& map_name, const std::string& planner_field = "planner",
                                   std::string* warning = nullptr);

// plan_on_grid, with an Error of its checks (connectivity, turn_cost, cost band, ...) attributed
// to the setting that gave the value, as occupancy_plan_request does.
PlanOutcome plan_query_on_grid(const OccupancyGrid& grid, Cell start, Cell goal, const PlanRequest& request,
                               std::span<const ParamSetting> settings);

// ---- elevation maps ----------------------------------------------------------------------------

struct TerrainPlanQuery {
  RoughTerrainPlannerKind kind = RoughTerrainPlannerKind::IA;
  RoughTerrainPlannerOptions options;
  SearchLimits limits;
};

// h_y, a_y, s_y (the Liu thresholds), w_s, w_e, w_r, w1, w2 (the weights of g and G), admissible,
// cost_per_metre, and the planners' declared robot_radius_m, reopen, unobserved; max_expansions,
// time_budget, expanded. Defaults are `starnav plan`'s (IA* with the paper's heuristic).
const ParamTable<TerrainPlanQuery>& terrain_plan_params();

// The options of a query of the rough-terrain planners in `planners` (the ones that will run with
// them: a setting none of them uses is an Error naming it) with `settings` applied and checked.
TerrainPlanQuery terrain_plan_query(std::span<const ParamSetting> settings,
                                    std::span<const RoughTerrainPlannerKind> planners);
// The rough-terrain planner named `name` for a query on an elevation map; an occupancy planner's
// name is an Error naming `field` that says which planners plan there.
RoughTerrainPlannerKind terrain_plan_planner(const std::string& name, const std::string& field = "planner");

// ---- both ---------------------------------------------------------------------------------------

// The CLI's flag of a key of either table ("cost_radius_m" -> "--inflate-cost-radius").
std::string plan_query_flag(const std::string& key);

// The cell of a query's endpoint `p`: cell indices when `in_cells` (whole numbers, else an Error
// naming `field` that quotes `text`), otherwise a point in the map frame; a point outside the map
// gives a cell outside it (a result, not an error).
Cell plan_endpoint_cell(const Vec2& p, bool in_cells, const GridGeometry& geometry, const std::string& field,
                        const std::string& text);

// ---- many queries ------------------------------------------------------------------------------

struct PlanEndpoints {
  Cell start{}, goal{};
};
// Every query of `queries` on `threads` threads (0: one per core), each thread with its own planner
// from `make_planner`, built once and used for its share of the queries (so a map's preprocessing
// is paid once per thread, not per query). Results in query order, the same for any number of
// threads.
std::vector<PlanResult> plan_many(std::span<const PlanEndpoints> queries,
                                  const std::function<std::unique_ptr<GridPlanner>()>& make_planner,
                                  const SearchLimits& limits, unsigned threads = 1);
// plan_many with the planner of `request` on `grid`: the planner alone, so gradient smoothing,
// which is per query, is an Error naming "smooth", and so is keeping the expanded cells
// ("expanded"); no path metrics. Errors of the planner's checks name the setting, as
// plan_query_on_grid's.
std::vector<PlanResult> plan_many_on_grid(const OccupancyGrid& grid, std::span<const PlanEndpoints> queries,
                                          const PlanRequest& request, std::span<const ParamSetting> settings,
                                          unsigned threads = 1);
// The same with a rough-terrain planner of `query` on `map` (each thread analyses the map once).
std::vector<PlanResult> plan_many_on_terrain(const ElevationMap& map, std::span<const PlanEndpoints> queries,
                                             const TerrainPlanQuery& query, unsigned threads = 1);

}  // namespace starnav
