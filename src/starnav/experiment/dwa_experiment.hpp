#pragma once
// DWA's three experiments of the local planning issue (docs/local_planning.md), each a scenario run
// over seeds:
//   doorway   scenarios/dwa_doorway.yaml: through a 0.8 m door; per run whether it arrived and the
//             most sign changes of vx or wz (achieved, beyond 0.01) in any 2 s window
//   sideways  scenarios/dwa_sideways.yaml: a goal straight to the side; the final distance to the
//             goal, the largest |vy| and the largest turn away from the start's heading
//   people    scenarios/dwa_people.yaml: people-like obstacles walking; the seed shifts each
//             moving obstacle's timing by up to +-3 s and scales its speed by 0.8-1.0; a contact
//             (the simulator's collision episodes) counts against the robot when it was moving
//             towards the contact point faster than 0.05 m/s
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/experiment/runner.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {

struct DwaExperimentConfig {
  std::string experiment;  // doorway | sideways | people
  std::string scenario_file;
  std::vector<ScenarioOverride> overrides;
  std::uint64_t seeds = 20;
  std::uint64_t seed_base = 0;
  void validate() const;  // Error naming the flag
};

struct DwaRunRecord {
  bool arrived = false;
  std::string outcome;
  double time_s = 0.0;
  int max_sign_changes_2s = 0;       // vx or wz, any 2 s window
  double goal_distance_m = 0.0;      // at the end
  double max_abs_vy_mps = 0.0;
  double max_turn_deg = 0.0;         // from the start's heading
  int contacts = 0;                  // collision episodes
  int robot_caused_contacts = 0;     // the robot moving towards the contact at > 0.05 m/s
  int recoveries = 0;
};

struct DwaExperimentResult {
  DwaExperimentConfig config;
  std::string scenario_name;
  ExperimentGrid grid;
  std::vector<Trial<DwaRunRecord>> trials;
  int arrived = 0, calm = 0, robot_caused = 0;  // runs: arrived; doorway: arrived with <= 2 changes
};

// The number of sign changes (beyond `deadband`) in the worst window of `window_s`, over the
// samples (t, v) of each series, counted together.
int max_sign_changes(const std::vector<double>& t, const std::vector<std::vector<double>>& series, double window_s,
                     double deadband);

DwaExperimentResult run_dwa_experiment(const DwaExperimentConfig& config, const ExperimentProgress& progress = {});
std::string dwa_experiment_markdown(const DwaExperimentResult& result);
std::string dwa_experiment_json(const DwaExperimentResult& result);
std::string dwa_experiment_csv(const DwaExperimentResult& result);

}  // namespace starnav
