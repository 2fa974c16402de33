#pragma once
// What `starnav plan` on elevation maps and `starnav bench terrain` share (Liu et al. 2024,
// docs/terrain.md): the planner flags and the options they make. The reports and pictures are
// the library's (experiment/terrain_report.hpp).
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "starnav/experiment/terrain_report.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"

namespace starnav::cli {

// The Liu 2024 flags (read through their CLI::Option: count() == 0 means "not given").
struct TerrainPlanFlags {
  double hy_m = LiuCostParams{}.h_y;
  double ay_rad = LiuCostParams{}.a_y;
  double sy_m2 = LiuCostParams{}.s_y;
  std::string weights;  // ws,we,wr,w1,w2
  bool admissible = false;
  bool cost_per_metre = false;
  double robot_radius_m = RoughTerrainPlannerOptions{}.robot_radius_m;
  std::string unobserved = "blocked";
  CLI::Option* hy = nullptr;
  CLI::Option* ay = nullptr;
  CLI::Option* sy = nullptr;
  CLI::Option* weights_opt = nullptr;
  CLI::Option* admissible_opt = nullptr;
  CLI::Option* cost_per_metre_opt = nullptr;
  CLI::Option* robot_radius = nullptr;
  CLI::Option* unobserved_opt = nullptr;

  // The first flag given on the command line, or nullptr.
  const CLI::Option* first_given() const;
};

// Registers --hy-m, --ay-rad, --sy-m2, --weights, --admissible, --cost-per-metre,
// --robot-radius-m and --unobserved on `cmd`.
void add_terrain_plan_flags(CLI::App* cmd, TerrainPlanFlags& flags);

// Planner options from the flags (Error naming the flag for bad values). `planners` are the
// planners that will run: a flag none of them uses is an error naming it (thresholds: aoea, ia;
// weights, --admissible, --cost-per-metre: ia; --robot-radius-m: aoea). Without --admissible IA*
// runs the paper's H with reopening (its Algorithm 1).
RoughTerrainPlannerOptions terrain_planner_options(const TerrainPlanFlags& flags,
                                                   const std::vector<RoughTerrainPlannerKind>& planners);

}  // namespace starnav::cli
