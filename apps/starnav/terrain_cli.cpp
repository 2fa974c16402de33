#include "terrain_cli.hpp"

#include "cli_util.hpp"
#include "starnav/core/error.hpp"

namespace starnav::cli {

const CLI::Option* TerrainPlanFlags::first_given() const {
  for (const CLI::Option* o : {hy, ay, sy, weights_opt, admissible_opt, cost_per_metre_opt, robot_radius, unobserved_opt})
    if (o && o->count() > 0) return o;
  return nullptr;
}

std::vector<ParamSetting> TerrainPlanFlags::settings() const {
  std::vector<ParamSetting> out;
  const auto given = [](const CLI::Option* o) { return o && o->count() > 0; };
  const auto add = [&](const std::string& key, const std::string& value) {
    out.push_back({key, value, {}, 0, plan_query_flag(key)});
  };
  if (given(hy)) add("h_y", hy_m);
  if (given(ay)) add("a_y", ay_rad);
  if (given(sy)) add("s_y", sy_m2);
  if (given(weights_opt)) {
    const std::vector<double> w = parse_number_list(weights, "--weights", 5, "ws,we,wr,w1,w2 (five numbers)");
    const char* keys[] = {"w_s", "w_e", "w_r", "w1", "w2"};
    for (int i = 0; i < 5; ++i) add(keys[i], format_param_real(w[static_cast<std::size_t>(i)]));
  }
  if (given(admissible_opt)) add("admissible", admissible ? "true" : "false");
  if (given(cost_per_metre_opt)) add("cost_per_metre", cost_per_metre ? "true" : "false");
  if (given(robot_radius)) add("robot_radius_m", robot_radius_m);
  if (given(unobserved_opt)) add("unobserved", unobserved);
  return out;
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
  return terrain_plan_query(f.settings(), planners).options;
}

}  // namespace starnav::cli
