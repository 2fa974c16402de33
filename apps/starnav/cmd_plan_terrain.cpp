// starnav plan on an elevation map: OA*, AOEA* or IA* of Liu et al. 2024 (docs/terrain.md; docs/terrain.md).
//
//   starnav plan --map ELEVATION_FILE --start X,Y --goal X,Y [--planner oa|aoea|ia (default ia)]
//                [--hy-m H] [--ay-rad A] [--sy-m2 S] [--weights ws,we,wr,w1,w2] [--admissible]
//                [--cost-per-metre] [--robot-radius-m R] [--unobserved blocked|free_flat|unknown_cost]
//                [--cells] [--json] [--out path.csv] [--svg picture.svg] [--expanded] [--force]
//                [--max-expansions N] [--time-budget S]
//
// Coordinates in metres in the map frame (--cells: cell indices). The occupancy planners (astar,
// jps, ...) and their flags are refused on elevation maps, and the Liu flags on occupancy maps
// (cmd_plan.cpp): oa is A* on the elevation map's own obstacles, which is what an occupancy
// planner could do there. IA* runs the paper's H with reopening unless --admissible.
//
// --json prints the planning result object of occupancy maps (planner, admissible, found, reason,
// cost, length, units, expanded, generated, path, path_cells, time_ms) with, for elevation maps,
// heuristic, reopened, options {...} and the path metrics lv_m, av_rad, hv_m, sv_m2,
// roll/pitch/tilt _mean_deg and _max_deg, roll/pitch _mean_abs_deg, moves_measured,
// cells_measured, attitude_nodes (null when no path). `cost` is the planner's own: metres for OA*
// and AOEA*, the sum of Liu move costs for IA*; `length` is the horizontal length in metres.
#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cli_util.hpp"
#include "cmd_plan_terrain.hpp"
#include "starnav/core/error.hpp"
#include "starnav/plan/grid_planner.hpp"

namespace starnav::cli {

namespace {

using json = nlohmann::ordered_json;

RoughTerrainPlannerKind planner_kind(const std::string& name) {
  const std::vector<std::string> occupancy = grid_planner_names();
  if (std::find(occupancy.begin(), occupancy.end(), name) != occupancy.end())
    throw Error("'" + name + "' plans on occupancy maps; on an elevation map use oa (A* on the map's own obstacles), "
                "aoea or ia",
                {}, 0, "--planner");
  return parse_rough_terrain_planner(name, "--planner");
}

}  // namespace

void run_plan_terrain(const TerrainPlanRequest& rq, const TerrainPlanFlags& flags, Context& ctx) {
  const RoughTerrainPlannerKind kind = planner_kind(rq.planner);
  RoughTerrainPlannerOptions options = terrain_planner_options(flags, {kind});
  options.record_trace = rq.expanded;
  const ElevationMap& map = *rq.map;
  RoughTerrainPlanner planner(kind, map, options);
  const PlanResult r = planner.plan(rq.start, rq.goal, rq.limits);
  const TerrainAnalysis& analysis = planner.analysis();
  TerrainPathMetrics metrics;
  if (r.found()) metrics = terrain_path_metrics(analysis, r.path_cells);
  const GridGeometry& g = map.geometry();

  if (!rq.out.empty() && r.found()) {
    std::ofstream out(rq.out, std::ios::binary);
    if (!out) throw Error("cannot write", rq.out, 0, "--out");
    out << std::setprecision(10) << "x_m,y_m,z_m,ix,iy\n";
    for (std::size_t i = 0; i < r.path_cells.size(); ++i) {
      const Cell c = r.path_cells[i];
      out << r.path_world[i].x() << "," << r.path_world[i].y() << ",";
      if (analysis.observed(c.x, c.y)) out << analysis.z(c.x, c.y);
      out << "," << c.x << "," << c.y << "\n";
    }
    if (!out) throw Error("write failed", rq.out, 0, "--out");
  }

  if (!rq.svg.empty()) {
    std::vector<Cell> shaded;
    if (kind != RoughTerrainPlannerKind::IA)
      for (std::size_t i = 0; i < planner.blocked_mask().size(); ++i)
        if (planner.blocked_mask()[i]) shaded.push_back(g.cell_of_index(i));
    std::vector<Cell> expanded_cells;
    if (rq.expanded) expanded_cells = planner.trace();
    const std::string title = std::string(planner.name()) + ": " +
                              (r.found() ? "lv " + format_number(metrics.lv_m) + " m, cost " + format_number(r.cost)
                                         : plan_status_reason(r.status));
    // Expanded cells (when asked) take the place of the obstacle band: one translucent layer.
    write_terrain_paths_svg(rq.svg, map, title, {{std::string(planner.name()), r.found() ? &r.path_cells : nullptr}},
                            rq.expanded ? expanded_cells : shaded,
                            rq.expanded ? "expanded" : (kind == RoughTerrainPlannerKind::OA ? "blocked" : "obstacles"),
                            rq.start, rq.goal);
  }

  if (rq.json) {
    json j;
    j["planner"] = std::string(planner.name());
    j["admissible"] = planner.admissible();
    if (kind == RoughTerrainPlannerKind::IA) j["heuristic"] = liu_heuristic_name(options.heuristic);
    j["found"] = r.found();
    if (!r.found()) j["reason"] = plan_status_reason(r.status);
    j["cost"] = r.found() ? json(r.cost) : json(nullptr);
    j["length"] = r.found() ? json(r.length) : json(nullptr);
    j["units"] = "m";
    j["expanded"] = r.expanded;
    j["generated"] = r.generated;
    if (kind == RoughTerrainPlannerKind::IA) j["reopened"] = planner.reopened();
    json path = json::array(), path_cells = json::array();
    for (std::size_t i = 0; i < r.path_cells.size(); ++i) {
      path_cells.push_back({r.path_cells[i].x, r.path_cells[i].y});
      path.push_back({r.path_world[i].x(), r.path_world[i].y()});
    }
    j["path"] = path;
    j["path_cells"] = path_cells;
    add_terrain_metrics_json(j, r.found() ? &metrics : nullptr);
    j["options"] = terrain_options_json(options);
    if (rq.expanded) {
      json cells = json::array();
      for (const Cell& c : planner.trace()) cells.push_back({c.x, c.y});
      j["expanded_cells"] = cells;
    }
    j["time_ms"] = r.time_ms;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "planner:    " << planner.name() << (planner.admissible() ? "" : " (inadmissible)");
    if (kind == RoughTerrainPlannerKind::IA)
      std::cout << ", " << liu_heuristic_name(options.heuristic) << " H"
                << (options.cost.cost_per_metre ? ", g per metre" : ", g per move");
    std::cout << "\n";
    if (r.found()) {
      std::cout << "found:      yes, " << r.path_cells.size() << " points\n";
      std::cout << "cost:       " << format_number(r.cost) << "\n";
      std::cout << "length:     " << format_number(r.length) << " m horizontal, lv " << format_number(metrics.lv_m) << " m\n";
      std::cout << "terrain:    av " << format_number(metrics.av_rad) << " rad, hv " << format_number(metrics.hv_m) << " m, Sv "
                << format_number(metrics.sv_m2) << " m^2\n";
      std::cout << "attitude:   roll " << format_number(metrics.roll_mean_deg) << " / " << format_number(metrics.roll_max_deg)
                << " deg, pitch " << format_number(metrics.pitch_mean_deg) << " / " << format_number(metrics.pitch_max_deg)
                << " deg, tilt " << format_number(metrics.tilt_mean_deg) << " / " << format_number(metrics.tilt_max_deg)
                << " deg (|mean| / max)\n";
    } else {
      std::cout << "found:      no (" << plan_status_reason(r.status) << ")\n";
    }
    std::cout << "expanded:   " << r.expanded << "\ngenerated:  " << r.generated << "\n";
    if (kind == RoughTerrainPlannerKind::IA && planner.reopened() > 0)
      std::cout << "reopened:   " << planner.reopened() << "\n";
    std::cout << "time:       " << format_number(r.time_ms) << " ms\n";
    if (!rq.out.empty() && r.found()) std::cout << "wrote " << rq.out << "\n";
    if (!rq.svg.empty()) std::cout << "wrote " << rq.svg << "\n";
  }
  ctx.exit_code = r.found() ? 0 : 1;
}

}  // namespace starnav::cli
