#pragma once
// What `starnav plan` on elevation maps and `starnav bench terrain` share (Liu et al. 2024, docs/terrain.md):
// the planner flags, the options they make, the metrics as JSON, and the pictures (terrain with
// paths, the paper's Fig. 6; attitude along a path, its Fig. 8).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "starnav/terrain/terrain_path_metrics.hpp"
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

// The options as JSON: thresholds, weights, heuristic, cost_per_metre, robot radius, unobserved.
nlohmann::ordered_json terrain_options_json(const RoughTerrainPlannerOptions& o);

// lv_m, av_rad, hv_m, sv_m2, the attitude summaries (roll/pitch/tilt mean and max, degrees, and the
// mean absolute roll and pitch) and the counts behind them; every key null when `m` is null.
void add_terrain_metrics_json(nlohmann::ordered_json& j, const TerrainPathMetrics* m);
// The keys add_terrain_metrics_json writes, in order.
const std::vector<std::string>& terrain_metric_keys();

// A path drawn on a terrain picture.
struct TerrainPathLayer {
  std::string label;
  const std::vector<Cell>* cells = nullptr;  // nullptr or empty: not drawn (kept in the legend order)
};

// The paper's Fig. 6: the hillshaded terrain, optional extra cells (e.g. the AOEA* obstacles,
// translucent), the paths, start and goal.
void write_terrain_paths_svg(const std::string& path, const ElevationMap& map, const std::string& title,
                             const std::vector<TerrainPathLayer>& paths, const std::vector<Cell>& shaded_cells,
                             const std::string& shaded_label, Cell start, Cell goal);

// The paper's Fig. 8: one angle (roll, pitch or tilt, degrees) along each path against the
// horizontal distance from the start.
enum class AttitudeAngle { Roll, Pitch, Tilt };
void write_attitude_profile_svg(const std::string& path, const std::string& title, AttitudeAngle angle,
                                const std::vector<std::pair<std::string, const std::vector<AttitudeSample>*>>& series);

}  // namespace starnav::cli
