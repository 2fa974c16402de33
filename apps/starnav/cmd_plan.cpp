// starnav plan: one query on a map with any grid planner (docs/benchmarks.md).
//
//   starnav plan --map FILE --start X,Y --goal X,Y [--planner NAME] [--weight W]
//                [--connectivity 4|8] [--unknown free|blocked] [--cells] [--json]
//                [--out path.csv] [--svg picture.svg] [--expanded] [--force]
//                [--heuristic H] [--inflate R] [--inflate-cost-radius R2] [--inflate-cost SCALE]
//                [--turn-cost K] [--turn-exact] [--adaptive-weight] [--smooth none|los|gradient]
//                [--smooth-clearance M] [--start-heading-deg A]
//
// The second group are the features of Ou et al. 2022 (docs/papers/ou2022.md, plan/ou2022_options.hpp): all of
// them with --planner astar and ou2022 (whose defaults are the paper's), hard inflation and
// smoothing with the others; --json adds the path metrics (plan/path_metrics.hpp) under `metrics`.
// --smooth gradient goes beyond the paper: line of sight, then the gradient smoother of
// plan/gradient_smoothing.hpp on the inflated map (--smooth-clearance: the clearance to keep).
//
// Coordinates are cells on MovingAI maps (x column, y row from the top, as in .scen files) and
// metres in the map frame on metric maps (--cells: cell indices there too). Exit 0 when a path is
// found, 1 when the query has no answer (outside the map, blocked, no path, limit), 2 bad input.
//
// On an elevation map plan runs OA*, AOEA* or IA* of Liu et al. 2024 (cmd_plan_terrain.cpp, flags
// --hy-m ... --unobserved); the occupancy planners and their flags (--weight ... --start-heading-deg)
// are refused there, and the Liu flags on occupancy maps.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_util.hpp"
#include "cmd_plan_terrain.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/plan/gradient_smoothing.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/path_metrics.hpp"
#include "starnav/plan/plan_pipeline.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav::cli {

namespace {

struct PlanOptions {
  std::string map;
  std::string start;
  std::string goal;
  std::string planner = "astar";
  double weight = 1.0;
  int connectivity = 8;
  std::string unknown = "blocked";
  bool cells = false;
  bool json = false;
  std::string out;
  std::string svg;
  bool expanded = false;
  bool force = false;
  double max_expansions = 0;
  double time_budget_s = 0;
  // Ou et al. 2022. Options whose absence means "the planner's default" are read
  // through their CLI::Option (count() == 0: not given).
  std::string heuristic;
  double inflate = 0.0;
  double inflate_cost_radius = 0.0;
  double inflate_cost = InflationOptions{}.cost_scale;
  double inflate_cost_weight = InflationOptions{}.cost_weight;
  double turn_cost = 1.0;
  bool turn_exact = false;
  bool adaptive_weight = false;
  std::string smooth;
  double smooth_clearance = 0.0;
  double start_heading_deg = 0.0;
  CLI::Option* turn_cost_opt = nullptr;
  CLI::Option* adaptive_weight_opt = nullptr;
  CLI::Option* smooth_opt = nullptr;
  CLI::Option* smooth_clearance_opt = nullptr;
  CLI::Option* start_heading_opt = nullptr;
  // Elevation maps (docs/terrain.md).
  TerrainPlanFlags terrain;
  CLI::Option* planner_opt = nullptr;
  std::vector<CLI::Option*> occupancy_only;  // flags of the occupancy planners
};

// The path metrics as JSON (non-finite clearances, e.g. on a map without obstacles, are null).
nlohmann::ordered_json metrics_json(const PathMetrics& m) {
  nlohmann::ordered_json j;
  j["length"] = m.length;
  j["vertices"] = m.vertices;
  j["turning_points"] = m.turning_points;
  j["turn_total_rad"] = m.turn_total_rad;
  j["turn_max_rad"] = m.turn_max_rad;
  j["clearance_min"] = std::isfinite(m.clearance_min) ? nlohmann::ordered_json(m.clearance_min) : nullptr;
  j["clearance_mean"] = std::isfinite(m.clearance_mean) ? nlohmann::ordered_json(m.clearance_mean) : nullptr;
  j["smoothness"] = m.smoothness;
  return j;
}

// A query endpoint as a cell. In cell mode X,Y must be integers; in metric mode a world point
// outside the map gives a cell outside it (a result, not an error).
Cell endpoint_cell(const std::string& text, const std::string& flag, bool in_cells, const GridGeometry& g) {
  const Vec2 p = parse_xy(text, flag);
  if (in_cells) {
    const double lim = static_cast<double>(std::numeric_limits<int>::max());
    if (p.x() != std::floor(p.x()) || p.y() != std::floor(p.y()) || std::abs(p.x()) > lim || std::abs(p.y()) > lim)
      throw Error("expected cell indices X,Y (two integers), got '" + text + "'", {}, 0, flag);
    return {static_cast<int>(p.x()), static_cast<int>(p.y())};
  }
  const Vec2 c = g.world_to_cell_continuous(p);
  const double lim = 1e9;
  if (std::abs(c.x()) > lim || std::abs(c.y()) > lim) return {-1, -1};  // far outside the map
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

// Elevation maps: the Liu 2024 planners (cmd_plan_terrain.cpp).
void run_plan_elevation(const PlanOptions& o, const LoadedMap& loaded, Context& ctx) {
  for (const CLI::Option* opt : o.occupancy_only)
    if (opt->count() > 0)
      throw Error("applies to occupancy maps only (" + o.map + " is an elevation map)", {}, 0, opt->get_name());
  TerrainPlanRequest rq;
  rq.map_path = o.map;
  rq.map = &loaded.elevation();
  rq.start = endpoint_cell(o.start, "--start", o.cells, loaded.geometry());
  rq.goal = endpoint_cell(o.goal, "--goal", o.cells, loaded.geometry());
  if (o.planner_opt->count() > 0) rq.planner = o.planner;
  rq.json = o.json;
  rq.out = o.out;
  rq.svg = o.svg;
  rq.expanded = o.expanded;
  rq.limits.max_expansions = static_cast<std::uint64_t>(o.max_expansions);
  rq.limits.time_budget_s = o.time_budget_s;
  run_plan_terrain(rq, o.terrain, ctx);
}

void run_plan(const PlanOptions& o, Context& ctx) {
  if (!(o.max_expansions >= 0) || o.max_expansions != std::floor(o.max_expansions))
    throw Error("expected a whole number >= 0", {}, 0, "--max-expansions");
  if (!(o.time_budget_s >= 0) || !std::isfinite(o.time_budget_s))
    throw Error("expected a number of seconds >= 0", {}, 0, "--time-budget");
  if (!o.out.empty()) check_output_path(o.out, o.force, "--out");
  if (!o.svg.empty()) check_output_path(o.svg, o.force, "--svg");
  const LoadedMap loaded = load_map(o.map);
  if (loaded.is_elevation()) {
    run_plan_elevation(o, loaded, ctx);
    return;
  }
  if (const CLI::Option* f = o.terrain.first_given())
    throw Error("applies to elevation maps only (planners oa, aoea, ia)", {}, 0, f->get_name());
  {
    // The registry says which map a planner needs; an old spelling works with a warning.
    std::string warning;
    const GlobalPlannerDef& def = find_global_planner(o.planner, "--planner", &warning);
    if (!warning.empty()) std::cerr << "starnav: warning: --planner: " << warning << "\n";
    if (def.info.has("needs_elevation"))
      throw Error("'" + o.planner + "' plans on elevation maps; " + o.map + " is an occupancy map", {}, 0, "--planner");
  }
  if (o.unknown != "free" && o.unknown != "blocked")
    throw Error("expected free or blocked, got '" + o.unknown + "'", {}, 0, "--unknown");
  if (o.weight != 1.0 && o.planner != "wastar") throw Error("only --planner wastar takes a weight", {}, 0, "--weight");
  const OccupancyGrid& grid = loaded.occupancy();
  const GridGeometry& geometry = grid.geometry();
  const bool index_grid = loaded.format == MapFormat::MovingAi || geometry.y_down;
  const bool in_cells = index_grid || o.cells;
  const Cell start = endpoint_cell(o.start, "--start", in_cells, geometry);
  const Cell goal = endpoint_cell(o.goal, "--goal", in_cells, geometry);

  PlanRequest rq;
  rq.planner = o.planner;
  GridPlannerOptions& options = rq.options;
  options.connectivity = o.connectivity;
  options.unknown_is_free = o.unknown == "free";
  options.thresholds = loaded.thresholds();
  options.weight = o.weight;
  options.record_trace = o.expanded;
  options.heuristic = o.heuristic;
  options.ou2022.inflation.radius_m = o.inflate;
  options.ou2022.inflation.cost_radius_m = o.inflate_cost_radius;
  options.ou2022.inflation.cost_scale = o.inflate_cost;
  options.ou2022.inflation.cost_weight = o.inflate_cost_weight;
  if (o.turn_cost_opt->count()) options.ou2022.turn_cost = o.turn_cost;
  options.ou2022.turn_exact = o.turn_exact;
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
    // Name the flag the user typed.
    const std::string flag = e.field() == "connectivity" ? "--connectivity"
                             : e.field() == "weight"     ? "--weight"
                             : e.field() == "planner"    ? "--planner"
                             : e.field() == "heuristic"  ? "--heuristic"
                             : e.field() == "inflate"    ? "--inflate"
                             : e.field() == "inflate_cost_radius" ? "--inflate-cost-radius"
                             : e.field() == "inflate_cost"        ? "--inflate-cost"
                             : e.field() == "inflate_cost_weight" ? "--inflate-cost-weight"
                             : e.field() == "turn_cost"           ? "--turn-cost"
                             : e.field() == "turn_exact"          ? "--turn-exact"
                             : e.field() == "adaptive_weight"     ? "--adaptive-weight"
                             : e.field() == "start_heading"       ? "--start-heading-deg"
                                                         : e.field();
    throw Error(e.message(), {}, 0, flag);
  }
  const GridPlanner* planner = outcome.planner.get();
  const PlanResult& r = outcome.result;
  const std::optional<InflatedMap>& inflated = outcome.inflated;
  const std::optional<GradientSmoothingResult>& smoothed = outcome.smoothed;
  const double smoothing_ms = outcome.smoothing_ms;
  const PathMetrics& metrics = outcome.metrics;
  const std::vector<Cell>& unsmoothed = planner->unsmoothed_path();
  const PathMetrics& unsmoothed_metrics = outcome.unsmoothed_metrics;

  // Points in the map's units: cells on index grids, metres (cell centres, any-angle vertices)
  // on metric maps.
  nlohmann::ordered_json path = nlohmann::ordered_json::array(), path_cells = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.path_cells.size(); ++i) {
    path_cells.push_back({r.path_cells[i].x, r.path_cells[i].y});
    if (index_grid) path.push_back({r.path_cells[i].x, r.path_cells[i].y});
    else path.push_back({r.path_world[i].x(), r.path_world[i].y()});
  }
  // Smoothed points in the map's units; on index grids in cells, a cell's centre at its indices.
  auto map_units = [&](const Vec2& w) { return index_grid ? Vec2(w - Vec2(0.5, 0.5)) : w; };
  nlohmann::ordered_json smoothed_path = nlohmann::ordered_json::array();
  if (smoothed)
    for (const Vec2& w : smoothed->points) smoothed_path.push_back({map_units(w).x(), map_units(w).y()});

  if (!o.out.empty() && r.found()) {
    std::ofstream out(o.out, std::ios::binary);
    if (!out) throw Error("cannot write", o.out, 0, "--out");
    out << std::setprecision(10);
    if (smoothed) {
      out << (index_grid ? "x_cell,y_cell\n" : "x_m,y_m\n");
      for (const Vec2& w : smoothed->points) out << map_units(w).x() << "," << map_units(w).y() << "\n";
    } else if (index_grid) {
      out << "x_cell,y_cell\n";
      for (const Cell& c : r.path_cells) out << c.x << "," << c.y << "\n";
    } else {
      out << "x_m,y_m,ix,iy\n";
      for (std::size_t i = 0; i < r.path_cells.size(); ++i)
        out << r.path_world[i].x() << "," << r.path_world[i].y() << "," << r.path_cells[i].x << ","
            << r.path_cells[i].y << "\n";
    }
    if (!out) throw Error("write failed", o.out, 0, "--out");
  }

  if (!o.svg.empty()) {
    // The map, the expanded cells (--expanded) and the path; world coordinates (cell centres
    // on index grids).
    viz::PictureOptions picture_options;
    picture_options.title =
        std::string(planner->name()) + ": " + (r.found() ? "cost " + format_number(r.cost) : plan_status_reason(r.status));
    viz::MapPicture picture(grid, picture_options);
    if (options.ou2022.inflation.hard()) {
      // The cells blocked by hard inflation alone.
      std::vector<Cell> cells;
      for (std::size_t i = 0; i < inflated->blocked.size(); ++i)
        if (inflated->blocked[i] && inflated->clearance_m[i] > 0.0) cells.push_back(geometry.cell_of_index(i));
      picture.add_cells(cells, viz::parse_colour("orange"), 0.35, "inflation");
    }
    if (o.expanded) picture.add_cells(planner->trace(), viz::parse_colour("sky"), 0.45, "expanded");
    auto point_of = [&](const Cell& c) { return index_grid ? Vec2(c.x + 0.5, c.y + 0.5) : geometry.cell_center(c); };
    if (r.found() && !unsmoothed.empty()) {
      std::vector<Vec2> points;
      for (const Cell& c : unsmoothed) points.push_back(point_of(c));
      viz::LineStyle line;
      line.colour = viz::categorical_colour(0);
      line.width_px = 1.5;
      line.dashed = true;
      picture.add_polyline(points, line, "before smoothing");
    }
    if (r.found()) {
      std::vector<Vec2> points;
      for (std::size_t i = 0; i < r.path_cells.size(); ++i)
        points.push_back(index_grid ? point_of(r.path_cells[i]) : r.path_world[i]);
      viz::LineStyle line;
      line.colour = viz::categorical_colour(0);
      line.width_px = smoothed ? 1.2 : 2.5;
      picture.add_polyline(points, line, smoothed ? "line of sight" : "path");
      if (smoothed) {
        line.colour = viz::categorical_colour(3);
        line.width_px = 2.5;
        picture.add_polyline(smoothed->points, line, "path (gradient smoothing)");
      }
    }
    viz::MarkerStyle marker;
    marker.radius_px = 4.5;
    marker.fill = viz::categorical_colour(2);
    if (geometry.contains(start)) picture.add_points({point_of(start)}, marker, "start");
    marker.fill = viz::categorical_colour(1);
    if (geometry.contains(goal)) picture.add_points({point_of(goal)}, marker, "goal");
    picture.write_svg(o.svg);
  }

  if (o.json) {
    nlohmann::ordered_json j;
    j["planner"] = std::string(planner->name());
    j["admissible"] = planner->admissible();
    j["found"] = r.found();
    if (!r.found()) j["reason"] = plan_status_reason(r.status);
    j["cost"] = r.found() ? nlohmann::ordered_json(r.cost) : nlohmann::ordered_json(nullptr);
    j["length"] = r.found() ? nlohmann::ordered_json(r.length) : nlohmann::ordered_json(nullptr);
    j["units"] = index_grid ? "cells" : "m";
    j["expanded"] = r.expanded;
    j["generated"] = r.generated;
    j["path"] = path;
    j["path_cells"] = path_cells;
    if (smoothed) {
      j["smoothed_path"] = smoothed_path;
      j["smoothing"] = {{"method", "gradient"},
                        {"iterations", smoothed->iterations},
                        {"energy_input", smoothed->energy_input},
                        {"energy_output", smoothed->energy_output},
                        {"time_ms", smoothing_ms}};
    }
    if (r.found()) {
      j["metrics"] = metrics_json(metrics);
      if (!unsmoothed.empty()) j["metrics_before_smoothing"] = metrics_json(unsmoothed_metrics);
    }
    if (o.expanded) {
      nlohmann::ordered_json cells = nlohmann::ordered_json::array();
      for (const Cell& c : planner->trace()) cells.push_back({c.x, c.y});
      j["expanded_cells"] = cells;
    }
    j["time_ms"] = r.time_ms;
    std::cout << j.dump() << "\n";
  } else {
    const char* unit = index_grid ? "cells" : "m";
    std::cout << "planner:    " << planner->name() << (planner->admissible() ? "" : " (inadmissible)") << "\n";
    if (r.found()) {
      std::cout << "found:      yes, " << r.path_cells.size() << " points\n";
      std::cout << "cost:       " << format_number(r.cost) << "\n";
      std::cout << "length:     " << format_number(r.length) << " " << unit << "\n";
      if (smoothed)
        std::cout << "gradient:   " << smoothed->points.size() << " points, " << format_number(metrics.length) << " " << unit
                  << " long, energy " << format_number(smoothed->energy_input) << " -> " << format_number(smoothed->energy_output)
                  << " in " << smoothed->iterations << " sweeps\n";
      if (!unsmoothed.empty())
        std::cout << "smoothing:  " << unsmoothed_metrics.vertices << " -> " << metrics.vertices << " vertices, "
                  << unsmoothed_metrics.turning_points << " -> " << metrics.turning_points << " turning points\n";
      else std::cout << "turns:      " << metrics.turning_points << " turning points\n";
      std::cout << "turning:    " << format_number(metrics.turn_total_rad) << " rad total, " << format_number(metrics.turn_max_rad)
                << " rad max\n";
      std::cout << "clearance:  " << format_number(metrics.clearance_min) << " min, " << format_number(metrics.clearance_mean)
                << " mean (" << unit << ")\n";
    } else {
      std::cout << "found:      no (" << plan_status_reason(r.status) << ")\n";
    }
    std::cout << "expanded:   " << r.expanded << "\ngenerated:  " << r.generated << "\n";
    std::cout << "time:       " << format_number(r.time_ms) << " ms\n";
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
    std::string& list = d.info.has("needs_elevation") ? elevation_names : names;
    list += (list.empty() ? "" : "|") + d.info.name;
  }
  plan->add_option("--planner", o->planner,
                   names + " (default astar); on elevation maps " + elevation_names + " (default ia)");
  plan->add_option("--weight", o->weight, "wastar: f = g + W*h, W >= 1 (default 1; > 1 is inadmissible)");
  plan->add_option("--connectivity", o->connectivity, "4 or 8 (default 8, no corner cutting)");
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
  plan->add_option("--heuristic", o->heuristic,
                   "manhattan|octile|euclidean|zero (default octile on 8-connected grids, manhattan on 4-connected "
                   "ones and for ou2022; manhattan on 8-connected grids is inadmissible)");
  plan->add_option("--inflate", o->inflate,
                   "block every cell within R of an obstacle (metres; cells on MovingAI maps; default 0)");
  plan->add_option("--inflate-cost-radius", o->inflate_cost_radius,
                   "graded cost band from --inflate out to R2 (ROS inflation_radius): moves into a cell at distance "
                   "d cost 1 + W*exp(-SCALE*(d - R)) times more (astar, ou2022)");
  plan->add_option("--inflate-cost", o->inflate_cost, "SCALE of the band's decay, 1/m (ROS cost_scaling_factor; default 10)");
  plan->add_option("--inflate-cost-weight", o->inflate_cost_weight, "W, the band's extra cost at the hard edge (default 4)");
  o->turn_cost_opt = plan->add_option("--turn-cost", o->turn_cost,
                                      "steering cost K: a turn of D degrees costs K*D/45 cells (astar, ou2022; ou2022 "
                                      "default 1, the paper's k = 10)");
  plan->add_flag("--turn-exact", o->turn_exact,
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
