#pragma once
// The 3D mapping experiment of Ou et al. 2022 section 4.1 (docs/mapping3d.md), on
// the simulated indoor run of scenarios/ou2022_mapping3d.yaml over seeds: per seed the scenario is
// simulated once and every SLAM variant (each 3D matcher with the floor constraint, and one matcher
// without it) maps the same scans in process, as they come (no clouds written). Reported: points
// per frame after each filter (Fig. 9), time per registration per matcher (Fig. 10), ATE,
// elevation drift and final error against the truth (Figs. 12-13; slam3d_run.hpp says how), the
// mapping time against real time; pictures of the first seed's XYZ trajectories and errors.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "starnav/sim/scenario.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/geometry.hpp"

namespace starnav {

struct Mapping3dVariant {
  std::string label;    // "gicp", "gicp_no_floor"
  std::string matcher;  // registry name
  bool floor = true;
};

struct Mapping3dExperimentConfig {
  std::string scenario = "scenarios/ou2022_mapping3d.yaml";
  std::vector<ScenarioOverride> overrides;
  std::uint64_t seeds = 10, seed_base = 0;
  std::vector<std::string> matchers = {"icp", "gicp", "ndt", "ndt_mt"};
  std::string no_floor_matcher = "gicp";  // also run without the floor constraint ("" for none)
  // The variant whose map is built and judged on every seed: the octree, its 2D grid against the
  // world's true occupancy, and the improved A* on the grid from the start to `plan_goal` ("" none).
  std::string map_variant = "gicp";
  Vec2 plan_goal = Vec2(11.0, 8.5);  // in the simulator's frame (the route's last waypoint)
  double plan_inflation_m = 0.35;
  std::vector<ParamSetting> slam_settings;  // graph3d's (docs/parameters.md); each variant sets `floor` itself
  void validate() const;  // Error naming the flag
  std::vector<Mapping3dVariant> variants() const;
};

struct Mapping3dRun {
  std::uint64_t seed = 0;
  std::string variant, matcher;
  bool floor = true;
  std::size_t frames = 0, keyframes = 0, loops = 0, floor_edges = 0;
  double ate_rmse_m = 0.0, elevation_drift_m = 0.0, final_error_m = 0.0, driven_m = 0.0;
  double recording_s = 0.0, mapping_s = 0.0;  // the recording's length; this variant's CPU-bound mapping time (wall)
  double mean_match_s = 0.0, median_match_s = 0.0;
  double raw_points = 0.0, windowed_points = 0.0, voxelised_points = 0.0, kept_points = 0.0;  // per frame, mean
  // The map variant only: the grid against the true occupancy (docs/mapping3d.md has the formula)
  // and the improved A* on it.
  bool mapped = false;
  double occupied_iou = 0.0;
  std::size_t occupied_cells = 0, true_occupied_cells = 0;
  std::size_t occupied_matched = 0, true_missed = 0;  // within one cell of a true / estimated occupied cell
  bool goal_mapped = false;  // the map observed the cell of the route's end (plan_goal)
  bool path_found = false, path_collision_free = false;
  double path_length_m = 0.0;
};

struct Mapping3dSummary {
  std::string variant;
  int runs = 0;
  double ate_mean_m = 0.0, ate_max_m = 0.0, drift_mean_m = 0.0, drift_max_m = 0.0;
  double median_match_ms = 0.0, real_time_factor = 0.0;  // median over seeds
};

// The first seed's trajectories for the figures: per frame t, truth and each variant's estimate
// (aligned as for the errors).
struct Mapping3dTrace {
  std::vector<double> t;
  std::vector<Vec3> truth;
  std::vector<std::vector<Vec3>> estimates;  // per variant
  std::vector<std::array<double, 4>> filter_counts;  // raw, windowed, voxelised, kept per frame
};

struct Mapping3dResult {
  Mapping3dExperimentConfig config;
  std::vector<Mapping3dVariant> variants;
  std::vector<Mapping3dRun> runs;
  std::vector<Mapping3dSummary> summaries;
  Mapping3dTrace trace;
};

using Mapping3dProgress = std::function<void(std::size_t done, std::size_t total, const std::string& what)>;
Mapping3dResult run_mapping3d_experiment(const Mapping3dExperimentConfig& config, const Mapping3dProgress& progress = {});
std::string mapping3d_markdown(const Mapping3dResult& result);
std::string mapping3d_json(const Mapping3dResult& result);
std::string mapping3d_csv(const Mapping3dResult& result);
// xyz.svg (Fig. 12: x, y and z over time, truth and each variant), error.svg (Fig. 13: position
// error over time), filters.svg (Fig. 9: points per frame after each filter) into `dir`.
void write_mapping3d_figures(const Mapping3dResult& result, const std::string& dir);

}  // namespace starnav
