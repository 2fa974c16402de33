#pragma once
// How the rough-terrain planners of Liu et al. 2024 are reported (docs/terrain.md): their options
// and a path's metrics as JSON, and the pictures (the terrain with paths, the paper's Fig. 6; an
// attitude angle along paths, its Fig. 8). `starnav plan` on elevation maps and `starnav bench
// terrain` both write them.
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "starnav/map/elevation_map.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"
#include "starnav/terrain/terrain_path_metrics.hpp"

namespace starnav {

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

}  // namespace starnav
