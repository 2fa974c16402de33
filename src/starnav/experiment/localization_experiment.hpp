#pragma once
// The localization experiments (docs/localization.md).
//
// EKF square (Ren et al. 2022 Fig. 5; docs/papers/ren2022.md): a scenario whose localization
// section names the EKF with the bias state (scenarios/ekf_square.yaml) is run once per seed with
// three localizers fed the same encoders and IMU (so they see the same noise): dead reckoning
// (`odometry`), the paper's three-state EKF (the scenario's EKF settings with bias_state false and
// the yaw noise `plain_imu_yaw_sigma_deg`) and the scenario's EKF. Per seed and localizer: the end
// drift (position error at the end), the position RMSE over every odometry sample, the final and
// RMS heading errors; for the bias EKF the NEES of (x, y, yaw) at every odometry sample, averaged
// over the seeds and checked against the 95 % interval of chi-square(3 seeds) / seeds.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/experiment/runner.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {

struct EkfSquareConfig {
  std::string scenario_file;
  std::vector<ScenarioOverride> overrides;
  std::uint64_t seeds = 20;
  std::uint64_t seed_base = 0;
  double plain_imu_yaw_sigma_deg = 0.5;  // the three-state EKF's yaw noise (it has no drift model)
};

inline constexpr int kEkfSquareLocalizers = 3;  // odometry, ekf, ekf_bias
const std::vector<std::string>& ekf_square_localizer_names();

struct EkfSquareErrors {
  double end_drift_m = 0.0;
  double rmse_m = 0.0;
  double final_heading_error_deg = 0.0;
  double heading_rmse_deg = 0.0;
};

struct EkfSquareSeedRecord {
  std::vector<EkfSquareErrors> localizers;  // kEkfSquareLocalizers, in the order of the names
  std::vector<double> nees;                 // the bias EKF's, per odometry sample
  std::vector<double> t_s;                  // the odometry samples' times
  std::vector<std::vector<Vec2>> tracks;    // truth, then each localizer (every 10th sample)
};

struct EkfSquareResult {
  EkfSquareConfig config;
  std::string scenario_name;
  ExperimentGrid grid;
  std::vector<Trial<EkfSquareSeedRecord>> trials;
  std::vector<VariantSummary> summaries;  // per localizer: the four errors
  // Per localizer: seeds whose RMSE and end drift are both at most half of dead reckoning's.
  std::vector<int> halves_odometry;
  std::vector<int> halves_odometry_rmse;  // the RMSE alone
  std::vector<int> heading_under_half_degree;  // seeds whose final heading error is under 0.5 deg
  std::vector<double> nees_mean;  // over the seeds, per odometry sample
  double nees_low = 0.0, nees_high = 0.0;  // the 95 % interval of the mean
  double nees_in_band = 0.0;               // fraction of samples inside it
  double bias_truth_radps = 0.0;
};

EkfSquareResult run_ekf_square(const EkfSquareConfig& config, const ExperimentProgress& progress = {});
std::string ekf_square_markdown(const EkfSquareResult& result);
std::string ekf_square_json(const EkfSquareResult& result);
std::string ekf_square_runs_csv(const EkfSquareResult& result);
std::string ekf_square_nees_csv(const EkfSquareResult& result);  // t_s,nees_mean
// trajectories.svg (the first seed's tracks), nees.svg (the mean NEES and its interval).
void write_ekf_square_pictures(const EkfSquareResult& result, const std::string& dir);

// AMCL in the simulator (Ren et al. 2022 Figs. 7-8): each scenario (a localization chain with a
// particle filter; tracking, global start or a teleport event) run over seeds. Per run, from the
// estimate at every scan against the truth: filter updates until the first convergence within
// 0.25 m and 0.25 rad, the error after it (outside a kidnapped window), updates from the last
// teleport until it converges again there, and false convergences (claimed with an error over 1 m,
// the kidnapped window aside: a filter cannot know it was carried until its scans disagree).
// Cases run on every scenario: tracking (the scenario as written), global (up to 10,000 particles
// from the scan proposal, recovery on), kidnap (recovery on, up to 10,000 particles; a scenario
// with a route is carried 5 m ahead along it and turned 90 degrees at 40 % of its drive).
struct AmclBenchConfig {
  std::vector<std::string> scenarios;
  std::vector<std::string> cases = {"tracking"};
  std::vector<ScenarioOverride> overrides;
  std::uint64_t seeds = 20;
  std::uint64_t seed_base = 0;
};

struct AmclRunRecord {
  double distance_m = 0.0;
  int updates = 0;
  int updates_to_converge = -1;   // -1: never
  double rmse_m = 0.0, yaw_rmse_deg = 0.0;  // after convergence (NaN without one)
  double max_error_m = 0.0;
  int kidnap_reconverge_updates = -1;  // -1: no teleport, or never
  bool kidnapped = false;
  int false_convergences = 0;     // scans claimed converged with an error over 1 m
  int max_particles = 0;
  std::vector<Vec2> error_m;      // (t, error) at every scan
  std::vector<Vec2> particles;    // (t, particles) at every scan
};

// The settings a case adds to a scenario's.
std::vector<ScenarioOverride> amcl_case_overrides(const std::string& case_name);

struct AmclBenchResult {
  AmclBenchConfig config;
  ExperimentGrid grid;               // instances: the scenarios; variants: the cases
  std::vector<std::string> names;  // the scenarios' names
  std::vector<Trial<AmclRunRecord>> trials;
};

AmclBenchResult run_amcl_bench(const AmclBenchConfig& config, const ExperimentProgress& progress = {});
std::string amcl_bench_markdown(const AmclBenchResult& result);
std::string amcl_bench_json(const AmclBenchResult& result);
std::string amcl_bench_runs_csv(const AmclBenchResult& result);
// error_<scenario>.svg: the first seed's error and particle count over time, per scenario.
void write_amcl_bench_pictures(const AmclBenchResult& result, const std::string& dir);

// The p quantile of chi-square with k degrees of freedom (Wilson-Hilferty; within 0.1 % for k >= 30).
double chi_square_quantile_wilson_hilferty(double p, double k);

}  // namespace starnav
