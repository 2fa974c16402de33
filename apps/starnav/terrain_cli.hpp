#pragma once
// What `starnav plan` on elevation maps and `starnav bench terrain` share (Liu et al. 2024,
// docs/terrain.md): the planner flags and the options they make. The flags are the command line's
// spelling of the library's declared query parameters (experiment/plan_query.hpp), which parse
// and check them; the reports and pictures are the library's (experiment/terrain_report.hpp).
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/experiment/plan_query.hpp"
#include "starnav/experiment/terrain_report.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"

namespace starnav::cli {

// The Liu 2024 flags, as given (read through their CLI::Option: count() == 0 means "not given").
struct TerrainPlanFlags {
  std::string hy_m, ay_rad, sy_m2;
  std::string weights;  // ws,we,wr,w1,w2
  bool admissible = false;
  bool cost_per_metre = false;
  std::string robot_radius_m;
  std::string unobserved;
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
  // The flags given, as settings of terrain_plan_params() (each naming its flag).
  std::vector<ParamSetting> settings() const;
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
