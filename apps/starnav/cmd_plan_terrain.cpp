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
#include <iostream>

#include "cli_util.hpp"
#include "cmd_plan_terrain.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/plan_query.hpp"

namespace starnav::cli {

void run_plan_terrain(const TerrainPlanRequest& rq, Context& ctx) {
  const RoughTerrainPlannerKind kind = terrain_plan_planner(rq.planner, "--planner");
  const TerrainPlanQuery query = terrain_plan_query(rq.settings, std::vector<RoughTerrainPlannerKind>{kind});
  const TerrainPlanOutcome outcome = plan_on_terrain(*rq.map, rq.start, rq.goal, kind, query.options, query.limits);
  const bool found = outcome.result.found();
  if (!rq.out.empty() && found) write_text_file(rq.out, terrain_plan_path_csv(outcome), "--out");
  if (!rq.svg.empty()) write_terrain_plan_picture(outcome, *rq.map, rq.start, rq.goal, rq.svg);
  if (rq.json) {
    std::cout << terrain_plan_json(outcome);
  } else {
    std::cout << terrain_plan_text(outcome);
    if (!rq.out.empty() && found) std::cout << "wrote " << rq.out << "\n";
    if (!rq.svg.empty()) std::cout << "wrote " << rq.svg << "\n";
  }
  ctx.exit_code = found ? 0 : 1;
}

}  // namespace starnav::cli
