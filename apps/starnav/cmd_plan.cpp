// starnav plan: one query on a map with any grid planner (docs/benchmarks.md).
//
//   starnav plan --map FILE --start X,Y --goal X,Y [--planner NAME] [--weight W]
//                [--connectivity 4|8] [--unknown free|blocked] [--cells] [--json]
//                [--out path.csv] [--svg picture.svg] [--expanded] [--force]
//                [--heuristic H] [--inflate R] [--inflate-cost-radius R2] [--inflate-cost SCALE]
//                [--turn-cost K] [--turn-exact] [--adaptive-weight] [--smooth none|los|gradient]
//                [--smooth-clearance M] [--start-heading-deg A]
//   starnav plan --map FILE --planner hybrid_astar --start X,Y --start-yaw-deg A --goal X,Y
//                --goal-yaw-deg B [--set KEY=VALUE ...] [--unknown free|blocked] [--json] [--out poses.csv]
//
// The second group are the features of Ou et al. 2022 (docs/papers/ou2022.md): all of them with
// --planner astar and ou2022, hard inflation and smoothing with the others. The query runs as one
// library call, plan_on_grid (plan/plan_pipeline.hpp); its reports are experiment/plan_report.hpp.
//
// Coordinates are cells on MovingAI maps (x column, y row from the top, as in .scen files) and
// metres in the map frame on metric maps (--cells: cell indices there too). Exit 0 when a path is
// found, 1 when the query has no answer (outside the map, blocked, no path, limit), 2 bad input.
//
// A planner between poses (capability needs_headings: Hybrid-A*) takes the start and goal headings
// and its declared parameters by --set; it reports poses with their driving direction.
//
// On an elevation map plan runs OA*, AOEA* or IA* of Liu et al. 2024 (cmd_plan_terrain.cpp, flags
// --hy-m ... --unobserved); the occupancy planners and their flags (--weight ... --start-heading-deg)
// are refused there, and the Liu flags on occupancy maps.
#include <algorithm>
#include <cmath>
#include <map>
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
#include "starnav/experiment/plan_query.hpp"
#include "starnav/experiment/plan_report.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/plan/gradient_smoothing.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/plan_pipeline.hpp"
#include "starnav/registry/components.hpp"

namespace starnav::cli {

namespace {

// A flag that sets one key of the declared query parameters (experiment/plan_query.hpp), kept as
// the text given so that the library parses and checks it as it does every front end's.
struct QueryFlag {
  std::string key;
  CLI::Option* option = nullptr;
  std::string text;   // options
  bool value = false; // flags
  bool is_flag = false;
};

struct PlanOptions {
  std::string map;
  std::string start;
  std::string goal;
  std::string planner = "astar";
  bool cells = false;
  bool json = false;
  std::string out;
  std::string svg;
  bool force = false;
  // The occupancy planners' options (--weight ... --start-heading-deg) and those of both map kinds
  // (--max-expansions, --time-budget, --expanded), by flag; stable addresses for CLI11.
  std::map<std::string, QueryFlag> query;
  std::vector<std::string> occupancy_only;  // flags of the occupancy planners
  TerrainPlanFlags terrain;  // elevation maps (docs/terrain.md)
  CLI::Option* planner_opt = nullptr;
  // Planners between poses: the headings (degrees, map frame) and the planner's parameters.
  double start_yaw_deg = 0.0;
  double goal_yaw_deg = 0.0;
  CLI::Option* start_yaw_opt = nullptr;
  CLI::Option* goal_yaw_opt = nullptr;
  std::vector<std::string> sets;

  // The query flags given among `flags` (all when empty), as settings naming their flag.
  std::vector<ParamSetting> settings(const std::vector<std::string>& flags = {}) const {
    std::vector<ParamSetting> out;
    for (const auto& [flag, q] : query) {
      if (q.option->count() == 0) continue;
      if (!flags.empty() && std::find(flags.begin(), flags.end(), flag) == flags.end()) continue;
      out.push_back({q.key, q.is_flag ? (q.value ? "true" : "false") : q.text, {}, 0, flag});
    }
    return out;
  }
  bool expanded() const {
    const QueryFlag& e = query.at("--expanded");
    return e.option->count() > 0 && e.value;
  }
};

// The flags both map kinds take.
const std::vector<std::string> kCommonQueryFlags = {"--max-expansions", "--time-budget", "--expanded"};

// Elevation maps: the Liu 2024 planners (cmd_plan_terrain.cpp).
void run_plan_elevation(const PlanOptions& o, const LoadedMap& loaded, Context& ctx) {
  for (const std::string& flag : o.occupancy_only)
    if (o.query.at(flag).option->count() > 0)
      throw Error("applies to occupancy maps only (" + o.map + " is an elevation map)", {}, 0, flag);
  TerrainPlanRequest rq;
  rq.map_path = o.map;
  rq.map = &loaded.elevation();
  rq.start = parse_endpoint_cell(o.start, "--start", o.cells, loaded.geometry());
  rq.goal = parse_endpoint_cell(o.goal, "--goal", o.cells, loaded.geometry());
  if (o.planner_opt->count() > 0) rq.planner = o.planner;
  rq.json = o.json;
  rq.out = o.out;
  rq.svg = o.svg;
  rq.settings = o.terrain.settings();
  for (ParamSetting& s : o.settings(kCommonQueryFlags)) rq.settings.push_back(std::move(s));
  run_plan_terrain(rq, ctx);
}

// The names of the planners between poses, for messages.
std::string pose_planner_names() {
  std::string names;
  for (const GlobalPlannerDef& d : global_planners())
    if (d.info.has(Capability::NeedsHeadings)) names += (names.empty() ? "" : ", ") + d.info.name;
  return names;
}

// A planner between poses (Hybrid-A*) through its role, with its declared parameters from --set.
void run_plan_poses(const PlanOptions& o, const LoadedMap& loaded, const GlobalPlannerDef& def, Context& ctx) {
  for (const auto& [flag, q] : o.query)
    if (q.option->count() > 0 && flag != "--unknown")
      throw Error("applies to the grid planners, not to " + def.info.name + " (its parameters: --set KEY=VALUE)", {}, 0, flag);
  if (!o.svg.empty()) throw Error("no picture of a path of poses yet", {}, 0, "--svg");
  if (o.start_yaw_opt->count() == 0)
    throw Error("'" + def.info.name + "' plans between poses: give the start heading", {}, 0, "--start-yaw-deg");
  if (o.goal_yaw_opt->count() == 0)
    throw Error("'" + def.info.name + "' plans between poses: give the goal heading", {}, 0, "--goal-yaw-deg");
  if (!std::isfinite(o.start_yaw_deg)) throw Error("must be finite", {}, 0, "--start-yaw-deg");
  if (!std::isfinite(o.goal_yaw_deg)) throw Error("must be finite", {}, 0, "--goal-yaw-deg");
  const OccupancyGrid& grid = loaded.occupancy();
  const GridGeometry& geometry = grid.geometry();
  if (loaded.format == MapFormat::MovingAi || geometry.y_down)
    throw Error("'" + def.info.name + "' plans on metric maps (map_server .yaml), in metres", o.map, 0, "--map");
  GlobalPlannerContext pctx;
  pctx.grid.thresholds = loaded.thresholds();
  const QueryFlag& unknown = o.query.at("--unknown");
  if (unknown.option->count() > 0) {
    if (unknown.text != "free" && unknown.text != "blocked")
      throw Error("must be free or blocked, got '" + printable(unknown.text, 40) + "'", {}, 0, "--unknown");
    pctx.grid.unknown_is_free = unknown.text == "free";
  }
  const std::vector<ParamSetting> sets = parse_set_options(o.sets);
  const std::unique_ptr<GlobalPlanner> planner = def.make(pctx, sets);
  const auto endpoint = [&](const std::string& text, const std::string& flag) {
    if (!o.cells) return parse_xy(text, flag);
    const Cell c = parse_endpoint_cell(text, flag, true, geometry);
    return geometry.cell_center(c);
  };
  PlanQuery q;
  const Vec2 start = endpoint(o.start, "--start"), goal = endpoint(o.goal, "--goal");
  q.start_pose = Pose2(start.x(), start.y(), deg_to_rad(o.start_yaw_deg));
  q.goal_pose = Pose2(goal.x(), goal.y(), deg_to_rad(o.goal_yaw_deg));
  q.start = geometry.world_to_cell_unchecked(start);
  q.goal = geometry.world_to_cell_unchecked(goal);
  const PlanResult r = planner->plan_poses(PlanningLayers{&grid, nullptr}, q, {});
  if (!o.out.empty() && r.found()) write_text_file(o.out, pose_plan_csv(r), "--out");
  if (o.json) {
    std::cout << pose_plan_json(def.info.name, r);
  } else {
    std::cout << pose_plan_text(def.info.name, r);
    if (!o.out.empty() && r.found()) std::cout << "wrote " << o.out << "\n";
  }
  ctx.exit_code = r.found() ? 0 : 1;
}

void run_plan(PlanOptions& o, Context& ctx) {
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
  if (const GlobalPlannerDef& def = find_global_planner(o.planner, "--planner"); def.info.has(Capability::NeedsHeadings)) {
    run_plan_poses(o, loaded, def, ctx);
    return;
  }
  for (const CLI::Option* f : {o.start_yaw_opt, o.goal_yaw_opt})
    if (f->count() > 0)
      throw Error("applies to planners between poses (" + pose_planner_names() + ")", {}, 0, f->get_name());
  if (!o.sets.empty()) throw Error("applies to planners between poses (" + pose_planner_names() + ")", {}, 0, "--set");
  // The registry says which map a planner needs and whether it takes a weight; an old spelling
  // works with a warning. The options are the library's declared query parameters.
  const OccupancyGrid& grid = loaded.occupancy();
  const GridGeometry& geometry = grid.geometry();
  const bool index_grid = loaded.format == MapFormat::MovingAi || geometry.y_down;
  const std::vector<ParamSetting> settings = o.settings();
  std::string warning;
  PlanRequest rq =
      occupancy_plan_request(o.planner, settings, geometry, index_grid, loaded.thresholds(), o.map, "--planner", &warning);
  if (!warning.empty()) print_warning("--planner: " + warning);
  const bool in_cells = index_grid || o.cells;
  const Cell start = parse_endpoint_cell(o.start, "--start", in_cells, geometry);
  const Cell goal = parse_endpoint_cell(o.goal, "--goal", in_cells, geometry);
  rq.keep_inflated = !o.svg.empty();  // the picture shows the inflation
  PlanOutcome outcome;
  try {
    outcome = plan_query_on_grid(grid, start, goal, rq, settings);
  } catch (const Error& e) {
    if (e.field().empty() || e.field().rfind("--", 0) == 0) throw;
    throw Error(e.message(), {}, 0, plan_query_flag(e.field()));
  }
  const PlanReportContext report{&grid, start, goal, index_grid, rq.options.record_trace};
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
  o->planner_opt = plan->add_option("--planner", o->planner,
                                    names + " (default astar); on elevation maps " + elevation_names + " (default ia)");
  // A flag of a declared query parameter: an option keeps its text, a flag its value.
  const auto query_option = [&](const std::string& flag, const std::string& key, const std::string& help) {
    QueryFlag& q = o->query[flag];
    q.key = key;
    q.option = plan->add_option(flag, q.text, help);
    return q.option;
  };
  const auto query_flag = [&](const std::string& names, const std::string& flag, const std::string& key, const std::string& help) {
    QueryFlag& q = o->query[flag];
    q.key = key;
    q.is_flag = true;
    q.option = plan->add_flag(names, q.value, help);
    return q.option;
  };
  query_option("--weight", "weight", "wastar: f = g + W*h, W >= 1 (default 1; > 1 is inadmissible)");
  query_option("--connectivity", "connectivity", "4 or 8 (default 8, no corner cutting)");
  query_option("--unknown", "unknown", "unknown cells are free or blocked (default blocked)");
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
  query_flag("--expanded", "--expanded", "expanded", "also report the expanded cells (JSON key expanded_cells; --svg draws them)");
  query_option("--max-expansions", "max_expansions", "stop after this many expansions (0: no limit)");
  query_option("--time-budget", "time_budget", "stop after this many seconds of search (0: no limit)");
  plan->add_flag("--force", o->force, "overwrite existing output files");
  // Ou et al. 2022 (docs/papers/ou2022.md).
  query_option("--heuristic", "heuristic",
               "manhattan|octile|euclidean|zero (default octile on 8-connected grids, manhattan on 4-connected "
               "ones and for ou2022; manhattan on 8-connected grids is inadmissible)");
  query_option("--inflate", "inflate", "block every cell within R of an obstacle (metres; cells on MovingAI maps; default 0)");
  query_option("--inflate-cost-radius", "cost_radius_m",
               "graded cost band from --inflate out to R2 (ROS inflation_radius): moves into a cell at distance "
               "d cost 1 + W*exp(-SCALE*(d - R)) times more (astar, ou2022)");
  query_option("--inflate-cost", "cost_scale_per_m", "SCALE of the band's decay, 1/m (ROS cost_scaling_factor; default 10)");
  query_option("--inflate-cost-weight", "cost_weight", "W, the band's extra cost at the hard edge (default 4)");
  query_option("--turn-cost", "turn_cost",
               "steering cost K: a turn of D degrees costs K*D/45 cells (astar, ou2022; ou2022 "
               "default 1, the paper's k = 10)");
  query_flag("--turn-exact", "--turn-exact", "turn_exact",
             "search (cell, incoming direction) states: optimal for the turn-inclusive cost (the paper's cell "
             "states are not)");
  query_flag("--adaptive-weight,!--no-adaptive-weight", "--adaptive-weight", "adaptive_weight",
             "f = g + (1 + d/D)*h (inadmissible; ou2022 default on)");
  query_option("--smooth", "smooth",
               "none|los|gradient: remove redundant nodes by line of sight (ou2022 default los); "
               "gradient: then smooth the curvature on the inflated map (beyond the paper)");
  query_option("--smooth-clearance", "smooth_clearance",
               "with --smooth gradient: keep at least this clearance (m; cells on "
               "MovingAI maps) where the path had it (default 0)");
  query_option("--start-heading-deg", "start_heading_deg",
               "the robot's initial yaw, so the first move's turn is charged (map frame; "
               "cell axes on MovingAI maps)");
  // Elevation maps (docs/terrain.md, cmd_plan_terrain.cpp): the Liu 2024 flags; the flags above that only
  // the occupancy planners use are refused there.
  add_terrain_plan_flags(plan, o->terrain);
  // Planners between poses (Hybrid-A*, docs/planning.md).
  o->start_yaw_opt = plan->add_option("--start-yaw-deg", o->start_yaw_deg,
                                      "planners between poses (hybrid_astar): the start heading, degrees in the map frame");
  o->goal_yaw_opt = plan->add_option("--goal-yaw-deg", o->goal_yaw_deg, "planners between poses: the goal heading");
  plan->add_option("--set", o->sets, "planners between poses: one of the planner's parameters, KEY=VALUE (repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  for (const auto& [flag, q] : o->query)
    if (std::find(kCommonQueryFlags.begin(), kCommonQueryFlags.end(), flag) == kCommonQueryFlags.end())
      o->occupancy_only.push_back(flag);
  plan->callback([o, &ctx] { run_plan(*o, ctx); });
}

}  // namespace starnav::cli
