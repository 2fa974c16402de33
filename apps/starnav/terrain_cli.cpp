#include "terrain_cli.hpp"

#include <algorithm>
#include <cmath>

#include "cli_util.hpp"
#include "starnav/core/error.hpp"

namespace starnav::cli {

namespace {

bool uses_thresholds(RoughTerrainPlannerKind k) { return k != RoughTerrainPlannerKind::OA; }
bool uses_costs(RoughTerrainPlannerKind k) { return k == RoughTerrainPlannerKind::IA; }

}  // namespace

const CLI::Option* TerrainPlanFlags::first_given() const {
  for (const CLI::Option* o : {hy, ay, sy, weights_opt, admissible_opt, cost_per_metre_opt, robot_radius, unobserved_opt})
    if (o && o->count() > 0) return o;
  return nullptr;
}

void add_terrain_plan_flags(CLI::App* cmd, TerrainPlanFlags& f) {
  f.hy = cmd->add_option("--hy-m", f.hy_m, "elevation maps (aoea, ia): step threshold h_y, metres (default 0.05)");
  f.ay = cmd->add_option("--ay-rad", f.ay_rad, "elevation maps (aoea, ia): slope threshold a_y, radians (default 0.5)");
  f.sy = cmd->add_option("--sy-m2", f.sy_m2,
                         "elevation maps (aoea, ia): ruggedness threshold S_y (3x3 height variance), m^2 (default 0.02)");
  f.weights_opt = cmd->add_option("--weights", f.weights,
                                  "elevation maps (ia): ws,we,wr,w1,w2 (default 0.33,0.33,0.34,0.5,0.5; ws+we+wr = 1)");
  f.admissible_opt = cmd->add_flag("--admissible", f.admissible,
                                   "elevation maps (ia): H = w2 * distance (admissible, optimal) instead of the paper's "
                                   "H = distance (inadmissible, searched with reopening as its Algorithm 1)");
  f.cost_per_metre_opt = cmd->add_flag(
      "--cost-per-metre", f.cost_per_metre,
      "elevation maps (ia): charge g per metre (g * d / resolution) instead of per move, so costs do not depend on "
      "the resolution");
  f.robot_radius = cmd->add_option("--robot-radius-m", f.robot_radius_m,
                                   "elevation maps (aoea): obstacle expansion radius, metres (default 0.36)");
  f.unobserved_opt = cmd->add_option("--unobserved", f.unobserved,
                                     "elevation maps: unobserved cells are blocked (default), free_flat or unknown_cost");
}

RoughTerrainPlannerOptions terrain_planner_options(const TerrainPlanFlags& f,
                                                   const std::vector<RoughTerrainPlannerKind>& planners) {
  const bool thresholds = std::any_of(planners.begin(), planners.end(), uses_thresholds);
  const bool costs = std::any_of(planners.begin(), planners.end(), uses_costs);
  const bool aoea =
      std::find(planners.begin(), planners.end(), RoughTerrainPlannerKind::AOEA) != planners.end();
  auto refuse = [](const CLI::Option* o, const char* who) {
    if (o && o->count() > 0) throw Error(std::string("applies to ") + who + " only", {}, 0, o->get_name());
  };
  if (!thresholds) {
    refuse(f.hy, "--planner aoea and ia");
    refuse(f.ay, "--planner aoea and ia");
    refuse(f.sy, "--planner aoea and ia");
  }
  if (!costs) {
    refuse(f.weights_opt, "--planner ia");
    refuse(f.admissible_opt, "--planner ia");
    refuse(f.cost_per_metre_opt, "--planner ia");
  }
  if (!aoea) refuse(f.robot_radius, "--planner aoea");

  RoughTerrainPlannerOptions o;
  o.cost.h_y = f.hy_m;
  o.cost.a_y = f.ay_rad;
  o.cost.s_y = f.sy_m2;
  if (!f.weights.empty()) {
    const std::vector<double> w = parse_number_list(f.weights, "--weights", 5, "ws,we,wr,w1,w2 (five numbers)");
    o.cost.w_s = w[0];
    o.cost.w_e = w[1];
    o.cost.w_r = w[2];
    o.cost.w1 = w[3];
    o.cost.w2 = w[4];
  }
  o.cost.cost_per_metre = f.cost_per_metre;
  o.heuristic = f.admissible ? LiuHeuristic::Admissible : LiuHeuristic::Paper;
  o.reopen = true;
  o.robot_radius_m = f.robot_radius_m;
  o.unobserved = parse_unobserved_policy(f.unobserved, "--unobserved");
  try {
    o.validate();
  } catch (const Error& e) {
    // Name the flag the user typed.
    const std::string& field = e.field();
    const std::string flag = field == "h_y"              ? "--hy-m"
                             : field == "a_y"            ? "--ay-rad"
                             : field == "s_y"            ? "--sy-m2"
                             : field == "robot_radius_m" ? "--robot-radius-m"
                                                         : "--weights";
    throw Error(e.message(), {}, 0, flag);
  }
  return o;
}

}  // namespace starnav::cli
