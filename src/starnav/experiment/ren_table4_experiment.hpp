#pragma once
// Ren et al. 2022 Table 4 (docs/papers/ren2022.md): the indoor robot cycles between two goal poses
// with AMCL + A* + DWA (scenarios/ren_table4.yaml: ten cycles, twenty arrivals); at each arrival,
// once the robot is at rest, the error between the true pose and the goal in x, y and heading.
// Per seed the max, min and mean of the absolute errors over its arrivals; over the seeds the
// paper's table: each row the mean over seeds of the seeds' max, min and mean (plus the worst
// arrival of all). A run that does not arrive everywhere, or collides, is a failed seed.
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/experiment/runner.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {

struct RenTable4Config {
  std::string scenario_file = "scenarios/ren_table4.yaml";
  std::vector<ScenarioOverride> overrides;
  std::uint64_t seeds = 20;
  std::uint64_t seed_base = 0;
};

// max, min, mean of |error| over one seed's arrivals: x, y (m), heading (rad).
struct ErrorSpread {
  double max = 0.0, min = 0.0, mean = 0.0;
};

struct RenTable4SeedRecord {
  bool success = false;  // every goal reached, no collision
  std::string outcome;
  int arrivals = 0, goals_total = 0, recoveries = 0;
  std::int64_t collisions = 0;
  ErrorSpread x, y, yaw;
  double sim_s = 0.0, wall_s = 0.0;
  std::vector<NavArrival> arrival_list;
};

struct RenTable4Result {
  RenTable4Config config;
  std::string scenario_name, controller, planner, localizer;
  ExperimentGrid grid;
  std::vector<Trial<RenTable4SeedRecord>> trials;
  // The table over the seeds that succeeded: mean of the per-seed max, min and mean.
  ErrorSpread x, y, yaw;
  double worst_x = 0.0, worst_y = 0.0, worst_yaw = 0.0;  // the largest single arrival error
  int seeds_ok = 0;
  double real_time_factor_median = 0.0;
};

RenTable4Result run_ren_table4(const RenTable4Config& config, const ExperimentProgress& progress = {});
std::string ren_table4_markdown(const RenTable4Result& result);
std::string ren_table4_json(const RenTable4Result& result);
std::string ren_table4_runs_csv(const RenTable4Result& result);      // one row per seed
std::string ren_table4_arrivals_csv(const RenTable4Result& result);  // one row per arrival

}  // namespace starnav
