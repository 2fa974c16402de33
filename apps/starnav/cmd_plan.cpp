// starnav plan: one query on a map with any grid planner (docs/benchmarks.md).
//
//   starnav plan --map FILE --start X,Y --goal X,Y [--planner NAME] [--weight W]
//                [--connectivity 4|8] [--unknown free|blocked] [--cells] [--json]
//                [--out path.csv] [--svg picture.svg] [--expanded] [--force]
//                [--heuristic H] [--inflate R] [--inflate-cost-radius R2] [--inflate-cost SCALE]
//                [--turn-cost K] [--turn-exact] [--adaptive-weight] [--smooth none|los|gradient]
//                [--smooth-clearance M] [--start-heading-deg A]
//
// The second group are the features of Ou et al. 2022 (docs/papers/ou2022.md): all of them with
// --planner astar and ou2022, hard inflation and smoothing with the others. The query runs as one
// library call, plan_on_grid (plan/plan_pipeline.hpp); its reports are experiment/plan_report.hpp.
//
// Coordinates are cells on MovingAI maps (x column, y row from the top, as in .scen files) and
// metres in the map frame on metric maps (--cells: cell indices there too). Exit 0 when a path is
// found, 1 when the query has no answer (outside the map, blocked, no path, limit), 2 bad input.
//
// On an elevation map plan runs OA*, AOEA* or IA* of Liu et al. 2024 (cmd_plan_terrain.cpp, flags
// --hy-m ... --unobserved); the occupancy planners and their flags (--weight ... --start-heading-deg)
// are refused there, and the Liu flags on occupancy maps.
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "cmd_plan_terrain.hpp"
#include "commands.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/plan_report.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/plan/gradient_smoothing.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/plan_pipeline.hpp"
#include "starnav/registry/components.hpp"

namespace starnav::cli {

namespace {

struct PlanOptions {
  std::string map;
  std::string start;
  std::string goal;
  PlanRequest request;  // the flags bound to the library's options directly where they can be
  std::string unknown = "blocked";
  bool cells = false;
  bool json = false;
  std::string out;
  std::string svg;
  bool expanded = false;
  bool force = false;
  double max_expansions = 0;
  double time_budget_s = 0;
  // Ou et al. 2022. Options whose absence means "the planner's default" are read through their
  // CLI::Option (count() == 0: not given).
  double turn_cost = 1.0;
  bool adaptive_weight = false;
  std::string smooth;
  double smooth_clearance = 0.0;
  double start_heading_deg = 0.0;
  CLI::Option* turn_cost_opt = nullptr;
  CLI::Option* adaptive_weight_opt = nullptr;
  CLI::Option* smooth_opt = nullptr;
  CLI::Option* smooth_clearance_opt = nullptr;
  CLI::Option* start_heading_opt = nullptr;
  TerrainPlanFlags terrain;  // elevation maps (docs/terrain.md)
  CLI::Option* planner_opt = nullptr;
  std::vector<CLI::Option*> occupancy_only;  // flags of the occupancy planners
};

// Elevation maps: the Liu 2024 planners (cmd_plan_terrain.cpp).
void run_plan_elevation(const PlanOptions& o, const LoadedMap& loaded, Context& ctx) {
  for (const CLI::Option* opt : o.occupancy_only)
    if (opt->count() > 0)
      throw Error("applies to occupancy maps only (" + o.map + " is an elevation map)", {}, 0, opt->get_name());
  TerrainPlanRequest rq;
  rq.map_path = o.map;
  rq.map = &loaded.elevation();
  rq.start = parse_endpoint_cell(o.start, "--start", o.cells, loaded.geometry());
  rq.goal = parse_endpoint_cell(o.goal, "--goal", o.cells, loaded.geometry());
  if (o.planner_opt->count() > 0) rq.planner = o.request.planner;
  rq.json = o.json;
  rq.out = o.out;
  rq.svg = o.svg;
  rq.expanded = o.expanded;
  rq.limits.max_expansions = static_cast<std::uint64_t>(o.max_expansions);
  rq.limits.time_budget_s = o.time_budget_s;
  run_plan_terrain(rq, o.terrain, ctx);
}

void run_plan(PlanOptions& o, Context& ctx) {
  if (!(o.max_expansions >= 0) || o.max_expansions != std::floor(o.max_expansions))
    throw Error("expected a whole number >= 0", {}, 0, "--max-expansions");
  if (!(o.time_budget_s >= 0) || !std::isfinite(o.time_budget_s))
    throw Error("expected a number of seconds >= 0", {}, 0, "--time-budget");
  if (!o.out.empty()) check_output_path(o.out, o.force, "--out");
  if (!o.svg.empty()) check_output_path(o.svg, o.force, "--svg");
  const LoadedMap loaded = load_map(o.map);
  std::vector<CommandFile> files;
  add_map_files(files, loaded, "--map");
  if (!o.out.empty()) files.push_back({o.out, "--out"});
  if (!o.svg.empty()) files.push_back({o.svg, "--svg"});
  check_distinct_files(files);
  if (loaded.is_elevation()) {
    run_plan_elevation(o, loaded, ctx);
    return;
  }
  if (const CLI::Option* f = o.terrain.first_given())
    throw Error("applies to elevation maps only (planners oa, aoea, ia)", {}, 0, f->get_name());
  // The registry says which map a planner needs and whether it takes a weight; an old spelling
  // works with a warning.
  std::string warning;
  const GlobalPlannerDef& def = find_global_planner(o.request.planner, "--planner", &warning);
  if (!warning.empty()) print_warning("--planner: " + warning);
  if (def.info.has(Capability::NeedsElevation))
    throw Error("'" + o.request.planner + "' plans on elevation maps; " + o.map + " is an occupancy map", {}, 0, "--planner");
  if (o.unknown != "free" && o.unknown != "blocked")
    throw Error("expected free or blocked, got '" + o.unknown + "'", {}, 0, "--unknown");
  PlanRequest& rq = o.request;
  GridPlannerOptions& options = rq.options;
  if (options.weight != 1.0 && !def.info.has(Capability::HeuristicWeight)) {
    std::string weighted;
    for (const ComponentInfo& i : all_components())
      if (i.has(Capability::HeuristicWeight)) weighted += (weighted.empty() ? "" : ", ") + i.name;
    throw Error("'" + rq.planner + "' takes no weight (planners that do: " + weighted + ")", {}, 0, "--weight");
  }
  const OccupancyGrid& grid = loaded.occupancy();
  const GridGeometry& geometry = grid.geometry();
  const bool index_grid = loaded.format == MapFormat::MovingAi || geometry.y_down;
  const bool in_cells = index_grid || o.cells;
  const Cell start = parse_endpoint_cell(o.start, "--start", in_cells, geometry);
  const Cell goal = parse_endpoint_cell(o.goal, "--goal", in_cells, geometry);

  options.unknown_is_free = o.unknown == "free";
  options.thresholds = loaded.thresholds();
  options.record_trace = o.expanded;
  if (o.turn_cost_opt->count()) options.ou2022.turn_cost = o.turn_cost;
  if (o.adaptive_weight_opt->count()) options.ou2022.adaptive_weight = o.adaptive_weight;
  if (o.smooth_opt->count()) rq.smoothing = parse_plan_smoothing(o.smooth, "--smooth");
  const bool gradient = rq.smoothing == PlanSmoothing::Gradient;
  if (o.smooth_clearance_opt->count()) {
    if (!gradient) throw Error("only with --smooth gradient", {}, 0, "--smooth-clearance");
    rq.gradient.min_clearance_m = o.smooth_clearance;
    try {
      validate_gradient_smoothing(rq.gradient);
    } catch (const Error& e) {
      throw Error(e.message(), {}, 0, "--smooth-clearance");
    }
  }
  if (o.start_heading_opt->count()) {
    if (!std::isfinite(o.start_heading_deg)) throw Error("expected a finite angle in degrees", {}, 0, "--start-heading-deg");
    // World yaw -> the grid's cell axes (index grids: already in cell axes).
    options.ou2022.start_heading_rad = deg_to_rad(o.start_heading_deg) - (index_grid ? 0.0 : geometry.origin.yaw);
  }
  rq.limits.max_expansions = static_cast<std::uint64_t>(o.max_expansions);
  rq.limits.time_budget_s = o.time_budget_s;
  rq.keep_inflated = !o.svg.empty();  // the picture shows the inflation
  PlanOutcome outcome;
  try {
    outcome = plan_on_grid(grid, start, goal, rq);
  } catch (const Error& e) {
    rethrow_with_flag(e, {{"start_heading", "--start-heading-deg"}});
  }
  const PlanReportContext report{&grid, start, goal, index_grid, o.expanded};
  const PlanResult& r = outcome.result;
  if (!o.out.empty() && r.found()) write_text_file(o.out, plan_path_csv(outcome, report), "--out");
  if (!o.svg.empty()) write_plan_picture(outcome, report, rq.options, o.svg);
  if (o.json) {
    std::cout << plan_json(outcome, report);
  } else {
    std::cout << plan_text(outcome, report);
    if (!o.out.empty() && r.found()) std::cout << "wrote " << o.out << "\n";
    if (!o.svg.empty()) std::cout << "wrote " << o.svg << "\n";
  }
  ctx.exit_code = r.found() ? 0 : 1;
}

}  // namespace

void register_plan_commands(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<PlanOptions>();
  auto* plan = app.add_subcommand("plan", "plan a path on a map");
  plan->add_option("--map", o->map,
                   "map file (MovingAI .map, map_server .yaml; an elevation map runs oa, aoea or ia)")->required();
  plan->add_option("--start", o->start,
                   "start X,Y: cells on MovingAI maps (column, row from the top), metres on metric maps")
      ->required();
  plan->add_option("--goal", o->goal, "goal X,Y (same units as --start)")->required();
  std::string names, elevation_names;
  for (const GlobalPlannerDef& d : global_planners()) {
    std::string& list = d.info.has(Capability::NeedsElevation) ? elevation_names : names;
    list += (list.empty() ? "" : "|") + d.info.name;
  }
  plan->add_option("--planner", o->request.planner,
                   names + " (default astar); on elevation maps " + elevation_names + " (default ia)");
  plan->add_option("--weight", o->request.options.weight, "wastar: f = g + W*h, W >= 1 (default 1; > 1 is inadmissible)");
  plan->add_option("--connectivity", o->request.options.connectivity, "4 or 8 (default 8, no corner cutting)");
  plan->add_option("--unknown", o->unknown, "unknown cells are free or blocked (default blocked)");
  plan->add_flag("--cells", o->cells, "--start/--goal are cell indices on metric maps too");
  plan->add_flag("--json", o->json,
                 "one JSON object: planner, admissible, found, reason, cost, length, units, expanded, generated, "
                 "path, path_cells, metrics {length, vertices, turning_points, turn_total_rad, turn_max_rad, "
                 "clearance_min, clearance_mean, smoothness} (and metrics_before_smoothing when smoothed; with --smooth "
                 "gradient the metrics are the smoothed path's, given as smoothed_path with smoothing {method, "
                 "iterations, energy_input, energy_output, time_ms}), time_ms; on "
                 "elevation maps instead of metrics: heuristic, reopened, lv_m, av_rad, hv_m, sv_m2, roll_mean_deg, "
                 "roll_max_deg, pitch_mean_deg, pitch_max_deg, tilt_mean_deg, tilt_max_deg, roll_mean_abs_deg, "
                 "pitch_mean_abs_deg, moves_measured, cells_measured, attitude_nodes, options");
  plan->add_option("--out", o->out, "write the path as CSV (only when found; the smoothed points with --smooth gradient)");
  plan->add_option("--svg", o->svg, "draw the map, the path and (with --expanded) the expanded cells");
  plan->add_flag("--expanded", o->expanded, "also report the expanded cells (JSON key expanded_cells; --svg draws them)");
  plan->add_option("--max-expansions", o->max_expansions, "stop after this many expansions (0: no limit)");
  plan->add_option("--time-budget", o->time_budget_s, "stop after this many seconds of search (0: no limit)");
  plan->add_flag("--force", o->force, "overwrite existing output files");
  // Ou et al. 2022 (docs/papers/ou2022.md).
  plan->add_option("--heuristic", o->request.options.heuristic,
                   "manhattan|octile|euclidean|zero (default octile on 8-connected grids, manhattan on 4-connected "
                   "ones and for ou2022; manhattan on 8-connected grids is inadmissible)");
  plan->add_option("--inflate", o->request.options.ou2022.inflation.radius_m,
                   "block every cell within R of an obstacle (metres; cells on MovingAI maps; default 0)");
  plan->add_option("--inflate-cost-radius", o->request.options.ou2022.inflation.cost_radius_m,
                   "graded cost band from --inflate out to R2 (ROS inflation_radius): moves into a cell at distance "
                   "d cost 1 + W*exp(-SCALE*(d - R)) times more (astar, ou2022)");
  plan->add_option("--inflate-cost", o->request.options.ou2022.inflation.cost_scale, "SCALE of the band's decay, 1/m (ROS cost_scaling_factor; default 10)");
  plan->add_option("--inflate-cost-weight", o->request.options.ou2022.inflation.cost_weight, "W, the band's extra cost at the hard edge (default 4)");
  o->turn_cost_opt = plan->add_option("--turn-cost", o->turn_cost,
                                      "steering cost K: a turn of D degrees costs K*D/45 cells (astar, ou2022; ou2022 "
                                      "default 1, the paper's k = 10)");
  plan->add_flag("--turn-exact", o->request.options.ou2022.turn_exact,
                 "search (cell, incoming direction) states: optimal for the turn-inclusive cost (the paper's cell "
                 "states are not)");
  o->adaptive_weight_opt = plan->add_flag("--adaptive-weight,!--no-adaptive-weight", o->adaptive_weight,
                                          "f = g + (1 + d/D)*h (inadmissible; ou2022 default on)");
  o->smooth_opt = plan->add_option("--smooth", o->smooth,
                                   "none|los|gradient: remove redundant nodes by line of sight (ou2022 default los); "
                                   "gradient: then smooth the curvature on the inflated map (beyond the paper)");
  o->smooth_clearance_opt = plan->add_option("--smooth-clearance", o->smooth_clearance,
                                             "with --smooth gradient: keep at least this clearance (m; cells on "
                                             "MovingAI maps) where the path had it (default 0)");
  o->start_heading_opt = plan->add_option("--start-heading-deg", o->start_heading_deg,
                                          "the robot's initial yaw, so the first move's turn is charged (map frame; "
                                          "cell axes on MovingAI maps)");
  // Elevation maps (docs/terrain.md, cmd_plan_terrain.cpp): the Liu 2024 flags; the flags above that only
  // the occupancy planners use are refused there.
  add_terrain_plan_flags(plan, o->terrain);
  o->planner_opt = plan->get_option("--planner");
  for (const char* name : {"--weight", "--connectivity", "--unknown", "--heuristic", "--inflate", "--inflate-cost-radius",
                           "--inflate-cost", "--inflate-cost-weight", "--turn-cost", "--turn-exact", "--adaptive-weight",
                           "--smooth", "--smooth-clearance", "--start-heading-deg"})
    o->occupancy_only.push_back(plan->get_option(name));
  plan->callback([o, &ctx] { run_plan(*o, ctx); });
}

}  // namespace starnav::cli
