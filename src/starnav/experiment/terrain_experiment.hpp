#pragma once
// The rough-terrain experiment of Liu et al. 2024 (paper section 4, Tables 2 and 3, Figs. 6 and 8;
// docs/terrain.md, docs/papers/liu2024.md), behind `starnav bench terrain`, on
// the experiment runner (runner.hpp) with the terrains as instances and OA*, AOEA*, IA* as
// variants.
//
// For every terrain (a map, or N hills terrains of 10 m x 10 m at 0.1 m with seeds S..S+N-1) it
// runs OA*, AOEA* and IA* from start to goal and measures each path
// (terrain/terrain_path_metrics.hpp): lv, av, hv, Sv (Table 2) and the roll, pitch and tilt of the
// 0.6 m x 0.4 m footprint along it (Table 3: |mean| and max, degrees).
//
// Start and goal: (0.5, 0.5) and (9.5, 9.5) m on generated terrains, as the paper; on a map the
// cells nearest (Euclidean, ties to the lower index) to the points 5 % of the map's width and
// height in from its lower-left and upper-right corners that are free in the AOEA* obstacle mask
// (so that every planner may start and end there), or the nearest observed cells when no cell is
// free; the lower-right / upper-left pair instead when it lies farther apart; given endpoints
// override both.
//
// model_resolution R plans on the map as a geometric scale model with R-metre cells: every
// horizontal and vertical distance is multiplied by R / resolution, so slopes are kept and the
// Table 1 thresholds and the robot (sized for 0.1 m cells) keep their proportion to the relief.
// Results are then in model metres (JSON key model_scale).
//
// Summaries (mean, standard deviation, min, max) over the terrains where all three planners found
// a path (the paper's comparison) and over each planner's own successes; pairwise comparisons IA*
// vs OA* and IA* vs AOEA* over the terrains where both found one.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "starnav/map/elevation_map.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"
#include "starnav/terrain/terrain_path_metrics.hpp"

namespace starnav {

struct TerrainExperimentConfig {
  std::string map;            // an elevation map file, or empty to generate terrains
  int generate = 0;           // hills terrains
  std::uint64_t seed = 0;     // of the first generated terrain
  double amplitude = 1.0;     // of the generated hills
  std::optional<Vec2> start_m, goal_m;  // both or neither
  double model_resolution = 0.0;        // > 0: plan on a scale model with these cells (maps only)
  RoughTerrainPlannerOptions options;
  std::size_t figures = 0;  // terrains whose figures are kept (the first ones)
  // Called before each terrain (done of total) and once at the end.
  std::function<void(std::size_t done, std::size_t total, const std::string& terrain)> progress;
};

struct TerrainRun {
  bool found = false;
  std::string reason;
  double cost = 0.0;
  double length_2d_m = 0.0;
  std::uint64_t expanded = 0;
  std::uint64_t generated = 0;
  std::uint64_t reopened = 0;
  double time_ms = 0.0;
  double preprocess_ms = 0.0;
  TerrainPathMetrics metrics;
  std::vector<Cell> path;
  std::vector<AttitudeSample> samples;  // figure terrains only
};

struct TerrainOutcome {
  std::string name;
  std::uint64_t seed = 0;  // generated terrains
  ElevationMap map;
  Cell start{}, goal{};
  Vec2 start_m{0, 0}, goal_m{0, 0};
  double analysis_ms = 0.0;
  // Whether the ruggedness threshold can matter: observed cells with S >= S_y, and the largest S.
  std::size_t observed_cells = 0;
  std::size_t cells_at_sy = 0;
  double max_s_m2 = 0.0;
  TerrainRun runs[3];                  // OA*, AOEA*, IA*
  std::vector<Cell> figure_obstacles;  // figure terrains: the AOEA* obstacles (expanded, observed)
};

struct TerrainExperimentResult {
  TerrainExperimentConfig config;
  double model_scale = 1.0;
  std::vector<TerrainOutcome> terrains;
};

// The planners in result order, and their titles (OA*, AOEA*, IA*).
const RoughTerrainPlannerKind* terrain_experiment_planners();
const char* terrain_planner_title(int index);

// Throws Error (naming the flag) for impossible options or an unreadable or occupancy map.
TerrainExperimentResult run_terrain_experiment(const TerrainExperimentConfig& config);

std::string terrain_markdown(const TerrainExperimentResult& r);       // the report, as printed
// The report, the per-terrain table and links to the figures of the first `figures` terrains.
std::string terrain_full_markdown(const TerrainExperimentResult& r, std::size_t figures);
std::string terrain_json(const TerrainExperimentResult& r);           // deterministic: no times
std::string terrain_timing_json(const TerrainExperimentResult& r);    // search and preprocessing times
// A terrain's name made safe as a file stem.
std::string terrain_file_stem(const std::string& name);
// Terrain i's figures (it must be a figure terrain): STEM_paths.svg (Fig. 6: hillshaded terrain,
// AOEA* obstacles, the three paths) and STEM_{roll,pitch,tilt}.svg (Fig. 8).
void write_terrain_figures(const TerrainExperimentResult& r, std::size_t i, const std::string& stem);

}  // namespace starnav
