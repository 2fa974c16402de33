#pragma once
// The navigation experiment of `starnav bench nav` (Li et al. 2019's navigation loop,
// harness/navigation_run.hpp): one scenario over seeds B .. B+N-1, each seed run twice on the
// experiment runner (runner.hpp):
//   dstar_lite  the robot follows D* Lite; at every plan A* from scratch also runs on the same map
//               and start (compare_astar), so expansions are compared on identical queries;
//   astar       the paper's navigation, A* from scratch at every plan.
// Summaries per planner: the success rate and outcomes; median, min, max and mean over the seeds of
// the metrics of metrics.hpp (experiment "nav"); for dstar_lite the expansion ratio A* / D* Lite
// over the replans and whether every compared plan had A*'s cost. Wall-clock figures are kept
// apart (wall_s, real_time_factor, the "wall_clock" objects); everything else is deterministic.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "starnav/experiment/runner.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {

struct NavExperimentConfig {
  std::string scenario_file;            // as given (reports name it)
  ScenarioSpec scenario;                // loaded, with its --set overrides applied
  std::uint64_t seed_base = 0;
  std::uint64_t seeds = 1;              // N >= 1
  std::optional<std::string> motion_mode;
};

struct NavRunRecord {
  std::string planner;
  NavigationMetrics m;
  double wall_s = 0.0;            // wall clock
  double real_time_factor = 0.0;  // wall clock: simulated s per wall s (0 when not measurable)
};
using NavTrial = Trial<NavRunRecord>;

// What one planner did over all seeds.
struct NavSummary {
  std::string planner;
  std::size_t runs = 0, completed = 0, successes = 0;
  std::size_t arrived = 0, no_path = 0, timeout = 0, errors = 0, other = 0;
  std::vector<SampleStats> metrics;  // as nav_summary_metrics()
  std::int64_t collisions_total = 0;
  std::int64_t replans_total = 0;
  // dstar_lite: A* from scratch on the same replans.
  std::uint64_t replan_expanded_total = 0, astar_replan_expanded_total = 0;
  std::uint64_t astar_backward_replan_expanded_total = 0;  // A* from the goal to the robot
  double expansion_ratio = std::numeric_limits<double>::quiet_NaN();           // sum A* / sum D* Lite
  double backward_expansion_ratio = std::numeric_limits<double>::quiet_NaN();  // sum backward A* / sum D* Lite
  SampleStats per_run_ratio;                                                   // runs with replan expansions
  bool costs_match_all = true;
  std::vector<std::uint64_t> costs_differ_seeds;
  // wall clock
  double wall_s_total = 0.0;
  SampleStats wall_s, real_time_factor;
};

struct NavExperimentResult {
  NavExperimentConfig config;
  ExperimentGrid grid;
  std::vector<NavTrial> trials;     // run order: seed, then planner
  std::vector<NavSummary> summaries;  // dstar_lite, astar
};

// The grid of the experiment: the scenario, the two planner variants, the seeds.
ExperimentGrid nav_experiment_grid(const NavExperimentConfig& config);
// Runs it. Errors setting a run up (the scenario's, the motion mode's) propagate; a run that
// throws while running is recorded as that trial's failure.
NavExperimentResult run_nav_experiment(const NavExperimentConfig& config, const ExperimentProgress& progress = {});

// The metrics summarised per planner (names of metrics.hpp, experiment "nav"), in report order.
const std::vector<std::string>& nav_summary_metrics();

// The reports: the JSON document (summary.json), one CSV row per run (runs.csv), the text table.
std::string nav_experiment_json(const NavExperimentResult& result);
std::string nav_runs_csv(const NavExperimentResult& result);
// The wall-clock figures (per run: wall_s, real_time_factor; per planner their statistics): the
// one record that differs between identical runs, kept out of the JSON and CSV above.
std::string nav_timing_json(const NavExperimentResult& result);
std::string nav_experiment_table(const NavExperimentResult& result);

}  // namespace starnav
