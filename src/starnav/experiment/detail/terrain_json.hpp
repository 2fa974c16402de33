#pragma once
// The rough-terrain planners' options and a path's metrics as JSON objects, shared by the terrain
// reports (terrain_report.cpp, terrain_experiment.cpp). Not installed: nlohmann-json stays out of
// the public headers.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "starnav/terrain/rough_terrain_planners.hpp"
#include "starnav/terrain/terrain_path_metrics.hpp"

namespace starnav::detail {

// The options as JSON: thresholds, weights, heuristic, cost_per_metre, robot radius, unobserved.
nlohmann::ordered_json terrain_options_json(const RoughTerrainPlannerOptions& o);

// lv_m, av_rad, hv_m, sv_m2, the attitude summaries (roll/pitch/tilt mean and max, degrees, and the
// mean absolute roll and pitch) and the counts behind them; every key null when `m` is null.
void add_terrain_metrics_json(nlohmann::ordered_json& j, const TerrainPathMetrics* m);
// The keys add_terrain_metrics_json writes, in order.
const std::vector<std::string>& terrain_metric_keys();

}  // namespace starnav::detail
