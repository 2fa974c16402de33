#pragma once
// How the rough-terrain planners of Liu et al. 2024 are reported (docs/terrain.md): one query as
// one library call (plan_on_terrain) and its JSON, text, path CSV and picture, which `starnav plan`
// on an elevation map prints; and the pictures `starnav bench terrain` draws too (the terrain with
// paths, the paper's Fig. 6; an attitude angle along paths, its Fig. 8).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "starnav/map/elevation_map.hpp"
#include "starnav/plan/plan_result.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"
#include "starnav/terrain/terrain_path_metrics.hpp"

namespace starnav {

// One query of a rough-terrain planner and what its reports need.
struct TerrainPlanOutcome {
  RoughTerrainPlannerKind kind = RoughTerrainPlannerKind::IA;
  RoughTerrainPlannerOptions options;
  std::string planner;  // its registry name
  bool admissible = true;
  std::uint64_t reopened = 0;
  PlanResult result;
  TerrainPathMetrics metrics;           // of the path (zero without one)
  std::vector<double> path_z;           // height at each path cell; NaN where unobserved
  std::vector<Cell> trace;              // expanded cells (options.record_trace)
  std::vector<std::uint8_t> blocked;    // the planner's blocked mask, per cell
};

// Plans from start to goal (cells; outside the map: a result, not an error) with `kind` and
// measures the path. Throws Error for impossible options.
TerrainPlanOutcome plan_on_terrain(const ElevationMap& map, Cell start, Cell goal, RoughTerrainPlannerKind kind,
                                   const RoughTerrainPlannerOptions& options, const SearchLimits& limits = {});

// The result as one JSON line: planner, admissible, heuristic (IA*), found, reason, cost, length,
// units, expanded, generated, reopened (IA*), path, path_cells, the path metrics, options, and
// expanded_cells when the trace was kept, time_ms.
std::string terrain_plan_json(const TerrainPlanOutcome& outcome);
std::string terrain_plan_text(const TerrainPlanOutcome& outcome);
// x_m,y_m,z_m,ix,iy per path cell (z empty where unobserved).
std::string terrain_plan_path_csv(const TerrainPlanOutcome& outcome);
// The terrain, the path, start and goal, and the expanded cells when the trace was kept, else the
// planner's obstacles (none for IA*, whose costs replace them).
void write_terrain_plan_picture(const TerrainPlanOutcome& outcome, const ElevationMap& map, Cell start, Cell goal,
                                const std::string& path);

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
