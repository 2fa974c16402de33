#include "starnav/experiment/localization_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/harness/localization_chain.hpp"
#include "starnav/harness/route_drive.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/sim/simulation.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

constexpr double kRadToDeg = 180.0 / kPi;
constexpr std::size_t kTrackStride = 10;

double standard_normal_quantile(double p) {
  // Bisection on the CDF: exact to rounding, and only called a few times.
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

EkfSquareErrors track_errors(const std::vector<EstimateRecord>& records) {
  EkfSquareErrors e;
  double sum_d2 = 0.0, sum_a2 = 0.0;
  std::size_t n = 0;
  for (const EstimateRecord& r : records) {
    if (r.scan) continue;
    const double d2 = (r.estimate.pose.translation() - r.truth.translation()).squaredNorm();
    const double a = wrap_angle(r.estimate.pose.yaw - r.truth.yaw);
    sum_d2 += d2;
    sum_a2 += a * a;
    ++n;
    e.end_drift_m = std::sqrt(d2);
    e.final_heading_error_deg = std::abs(a) * kRadToDeg;
  }
  if (n == 0) throw Error("the run recorded no odometry (sensors.encoders?)", {}, 0, "sensors.encoders");
  e.rmse_m = std::sqrt(sum_d2 / static_cast<double>(n));
  e.heading_rmse_deg = std::sqrt(sum_a2 / static_cast<double>(n)) * kRadToDeg;
  return e;
}

double nees_of(const EstimateRecord& r) {
  const Eigen::Vector3d e(r.truth.x - r.estimate.pose.x, r.truth.y - r.estimate.pose.y,
                          wrap_angle(r.truth.yaw - r.estimate.pose.yaw));
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(r.estimate.covariance);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return e.dot(ldlt.solve(e));
}

std::vector<ParamSetting> with_setting(std::vector<ParamSetting> settings, const std::string& key, const std::string& value) {
  std::erase_if(settings, [&](const ParamSetting& s) { return s.key == key; });
  settings.push_back({key, value, {}, 0, "localization.ekf." + key});
  return settings;
}

const std::vector<std::string>& error_metric_names() {
  static const std::vector<std::string> names = {"end_drift_m", "rmse_m", "final_heading_error_deg", "heading_rmse_deg"};
  return names;
}

}  // namespace

const std::vector<std::string>& ekf_square_localizer_names() {
  static const std::vector<std::string> names = {"odometry", "ekf", "ekf_bias"};
  return names;
}

double chi_square_quantile_wilson_hilferty(double p, double k) {
  const double z = standard_normal_quantile(p);
  const double a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + z * std::sqrt(a);
  return k * c * c * c;
}

EkfSquareResult run_ekf_square(const EkfSquareConfig& config, const ExperimentProgress& progress) {
  if (config.seeds < 1) throw Error("at least one seed", {}, 0, "--seeds");
  EkfSquareResult result;
  result.config = config;
  const CommandOwnedKey owned[] = {{"sim.seed", "--seeds and --seed-base give each run its seed"},
                                   {"localization.ekf.bias_state", "the square runs the EKF with and without it"}};
  check_user_overrides(config.overrides, owned);
  const ScenarioSpec base = load_scenario(config.scenario_file, config.overrides);
  result.scenario_name = base.name;
  if (!base.imu) throw Error("the scenario has no sensors.imu", base.file, 0, "sensors.imu");
  if (base.imu) result.bias_truth_radps = base.imu->config.yaw_rate_bias_radps;
  const LocalizationConfig chain_config = localization_config(base);
  // The square compares one localizer with and without its gyro-bias state: one that declares it.
  const auto declares = [&](const char* key) {
    const ComponentInfo& info = find_localizer(chain_config.localizer.name).info;
    return std::any_of(info.params.begin(), info.params.end(), [&](const ParamSpec& p) { return p.key == key; });
  };
  if (!declares("bias_state") || !declares("imu_yaw_sigma_deg") || chain_config.odometry != "wheel" || chain_config.odometry_filter)
    throw Error("the EKF square needs localization {odometry: wheel, localizer: ekf} (a localizer with a bias_state)", base.file, 0,
                "localization");
  std::vector<ParamSetting> bias = chain_config.localizer.settings;
  std::vector<ParamSetting> plain = with_setting(with_setting(bias, "bias_state", "false"), "imu_yaw_sigma_deg",
                                                 format_param_real(config.plain_imu_yaw_sigma_deg));
  bias = with_setting(bias, "bias_state", "true");

  result.grid.instances = {config.scenario_file};
  result.grid.variants = {{"paired", {}}};
  result.grid.seeds = consecutive_seeds(config.seed_base, config.seeds);
  struct Setup {
    ScenarioSpec spec;
  };
  const auto prepare = [&](const TrialKey& key) {
    Setup s{base};
    s.spec.seed = key.seed;
    return s;
  };
  const auto run = [&](Setup& setup, const TrialKey&) {
    Simulation sim(setup.spec);
    LocalizationConfig c = chain_config;
    c.localizer = {"odometry", {}, "localization.localizer", 0, base.file};
    LocalizationChain chain(sim, c);
    chain.add_localizer("ekf", plain);
    chain.add_localizer("ekf", bias);
    sim.run();
    EkfSquareSeedRecord rec;
    for (std::size_t i = 0; i < chain.localizers(); ++i) rec.localizers.push_back(track_errors(chain.records(i)));
    rec.tracks.resize(chain.localizers() + 1);
    std::size_t k = 0;
    for (const EstimateRecord& r : chain.records(2)) {
      if (r.scan) continue;
      rec.t_s.push_back(r.t_s);
      rec.nees.push_back(nees_of(r));
      if (k++ % kTrackStride == 0) {
        rec.tracks[0].push_back(r.truth.translation());
        for (std::size_t i = 0; i < chain.localizers(); ++i) rec.tracks[i + 1].push_back(chain.records(i)[k - 1].estimate.pose.translation());
      }
    }
    return rec;
  };
  result.trials = run_experiment<Setup, EkfSquareSeedRecord>(result.grid, prepare, run, progress);
  for (const auto& t : result.trials)
    if (!t.completed) throw Error("seed " + std::to_string(t.key.seed) + ": " + t.error, base.file, 0, "sim");

  // Per localizer summaries: the runner's statistics over the seeds, one pseudo-variant each.
  const std::vector<std::string>& names = ekf_square_localizer_names();
  result.halves_odometry.assign(names.size(), 0);
  result.halves_odometry_rmse.assign(names.size(), 0);
  result.heading_under_half_degree.assign(names.size(), 0);
  for (std::size_t l = 0; l < names.size(); ++l) {
    ExperimentGrid g = result.grid;
    g.variants = {{names[l], {}}};
    std::vector<MetricGetter<EkfSquareSeedRecord>> getters = {
        [l](const EkfSquareSeedRecord& r) { return std::optional<double>(r.localizers[l].end_drift_m); },
        [l](const EkfSquareSeedRecord& r) { return std::optional<double>(r.localizers[l].rmse_m); },
        [l](const EkfSquareSeedRecord& r) { return std::optional<double>(r.localizers[l].final_heading_error_deg); },
        [l](const EkfSquareSeedRecord& r) { return std::optional<double>(r.localizers[l].heading_rmse_deg); }};
    auto s = summarise_by_variant<EkfSquareSeedRecord>(g, result.trials, getters, [](const EkfSquareSeedRecord&) { return true; });
    result.summaries.push_back(std::move(s.front()));
    for (const auto& t : result.trials) {
      const EkfSquareErrors& o = t.record.localizers[0];
      const EkfSquareErrors& e = t.record.localizers[l];
      if (e.rmse_m <= 0.5 * o.rmse_m && e.end_drift_m <= 0.5 * o.end_drift_m) ++result.halves_odometry[l];
      if (e.rmse_m <= 0.5 * o.rmse_m) ++result.halves_odometry_rmse[l];
      if (e.final_heading_error_deg < 0.5) ++result.heading_under_half_degree[l];
    }
  }
  // The mean NEES over the seeds at each odometry sample (every seed has the same clock).
  const std::size_t steps = result.trials.front().record.nees.size();
  result.nees_mean.assign(steps, 0.0);
  for (const auto& t : result.trials) {
    if (t.record.nees.size() != steps) throw Error("the seeds' runs have different lengths", base.file, 0, "sim");
    for (std::size_t i = 0; i < steps; ++i) result.nees_mean[i] += t.record.nees[i] / static_cast<double>(config.seeds);
  }
  const double dof = 3.0 * static_cast<double>(config.seeds);
  result.nees_low = chi_square_quantile_wilson_hilferty(0.025, dof) / static_cast<double>(config.seeds);
  result.nees_high = chi_square_quantile_wilson_hilferty(0.975, dof) / static_cast<double>(config.seeds);
  std::size_t inside = 0;
  for (const double v : result.nees_mean)
    if (v >= result.nees_low && v <= result.nees_high) ++inside;
  result.nees_in_band = steps ? static_cast<double>(inside) / static_cast<double>(steps) : 0.0;
  return result;
}

std::string ekf_square_markdown(const EkfSquareResult& r) {
  std::ostringstream out;
  out << "# EKF square: " << r.scenario_name << ", " << r.config.seeds << " seeds from " << r.config.seed_base << "\n\n";
  out << "Three localizers on the same runs: `odometry`, dead reckoning from the wheel encoders; `ekf`, the paper's "
         "three-state EKF (x, y, yaw), which takes the IMU's yaw as it comes and has no model of the gyro's bias, so on a "
         "gyro with a bias it drifts and is expected to do worse than odometry (ratios above 1); `ekf_bias`, the same EKF "
         "with the gyro's bias as a fourth state, learnt at rest: the filter to use. Ratios below 1 are better than "
         "odometry.\n\n";
  out << summary_markdown(r.summaries, error_metric_names(), 0) << "\n";
  out << "| localizer | seeds with RMSE at most half of odometry's | ... and end drift too | seeds with final heading "
         "error under 0.5 deg |\n|---|---|---|---|\n";
  for (std::size_t l = 0; l < r.summaries.size(); ++l)
    out << "| " << r.summaries[l].variant << " | " << r.halves_odometry_rmse[l] << " of " << r.config.seeds << " | "
        << r.halves_odometry[l] << " of " << r.config.seeds << " | " << r.heading_under_half_degree[l] << " of "
        << r.config.seeds << " |\n";
  out << "\nNEES of the bias EKF, mean over the seeds: inside [" << format_fixed(r.nees_low, 2) << ", "
      << format_fixed(r.nees_high, 2) << "] at " << format_fixed(100.0 * r.nees_in_band, 1) << " % of "
      << r.nees_mean.size() << " samples\n";
  return out.str();
}

std::string ekf_square_runs_csv(const EkfSquareResult& r) {
  std::string out = "seed,localizer,end_drift_m,rmse_m,final_heading_error_deg,heading_rmse_deg\n";
  for (const auto& t : r.trials)
    for (std::size_t l = 0; l < t.record.localizers.size(); ++l) {
      const EkfSquareErrors& e = t.record.localizers[l];
      out += std::to_string(t.key.seed) + "," + ekf_square_localizer_names()[l];
      for (const double v : {e.end_drift_m, e.rmse_m, e.final_heading_error_deg, e.heading_rmse_deg}) {
        out += ',';
        out += format_fixed(v, 6);
      }
      out += '\n';
    }
  return out;
}

std::string ekf_square_json(const EkfSquareResult& r) {
  json doc;
  doc["benchmark"] = "ekf_square";
  doc["scenario"] = r.config.scenario_file;
  doc["seeds"] = r.config.seeds;
  doc["seed_base"] = r.config.seed_base;
  doc["plain_imu_yaw_sigma_deg"] = r.config.plain_imu_yaw_sigma_deg;
  json locs = json::array();
  for (std::size_t l = 0; l < r.summaries.size(); ++l) {
    json j;
    j["localizer"] = r.summaries[l].variant;
    for (std::size_t k = 0; k < error_metric_names().size(); ++k) {
      const SampleStats& s = r.summaries[l].metrics[k];
      j[error_metric_names()[k]] = {{"median", s.median}, {"mean", s.mean}, {"max", s.max}};
    }
    j["seeds_halving_odometry"] = r.halves_odometry[l];
    j["seeds_halving_odometry_rmse"] = r.halves_odometry_rmse[l];
    j["seeds_heading_under_half_degree"] = r.heading_under_half_degree[l];
    locs.push_back(j);
  }
  doc["localizers"] = locs;
  doc["nees"] = {{"interval", {r.nees_low, r.nees_high}}, {"fraction_inside", r.nees_in_band}, {"samples", r.nees_mean.size()}};
  return doc.dump(2) + "\n";
}

std::string ekf_square_nees_csv(const EkfSquareResult& r) {
  std::string out = "t_s,nees_mean\n";
  const std::vector<double>& t = r.trials.front().record.t_s;
  for (std::size_t i = 0; i < r.nees_mean.size(); ++i) {
    out += format_fixed(t[i], 3);
    out += ',';
    out += format_fixed(r.nees_mean[i], 6);
    out += '\n';
  }
  return out;
}

void write_ekf_square_pictures(const EkfSquareResult& r, const std::string& dir) {
  const EkfSquareSeedRecord& first = r.trials.front().record;
  viz::LinePlot tracks({.title = "EKF square, seed " + std::to_string(r.trials.front().key.seed), .x_label = "x [m]",
                        .y_label = "y [m]", .equal_aspect = true});
  tracks.add_series(first.tracks[0], {.colour = {0, 0, 0, 255}, .width_px = 2.5}, "truth");
  for (std::size_t l = 0; l < ekf_square_localizer_names().size(); ++l)
    tracks.add_series(first.tracks[l + 1], {.colour = viz::categorical_colour(l), .width_px = 1.5},
                      ekf_square_localizer_names()[l]);
  tracks.write_svg((fs::path(dir) / "trajectories.svg").string());

  viz::LinePlot nees({.title = "NEES of the bias EKF, mean over " + std::to_string(r.config.seeds) + " seeds",
                      .x_label = "t [s]", .y_label = "NEES", .y_range = std::pair{0.0, 3.0 * r.nees_high}});
  std::vector<Vec2> points;
  for (std::size_t i = 0; i < r.nees_mean.size(); i += 5) points.emplace_back(first.t_s[i], r.nees_mean[i]);
  nees.add_series(points, {}, "mean NEES");
  const double t_end = first.t_s.empty() ? 1.0 : first.t_s.back();
  for (const double v : {r.nees_low, r.nees_high})
    nees.add_series({Vec2(0.0, v), Vec2(t_end, v)}, {.colour = {200, 0, 0, 255}, .dashed = true}, v == r.nees_low ? "95 % interval" : "");
  nees.write_svg((fs::path(dir) / "nees.svg").string());
}

namespace {

constexpr double kConvergedErrorM = 0.25, kConvergedErrorRad = 0.25, kFalseConvergenceM = 1.0;

AmclRunRecord amcl_run_record(const std::vector<EstimateRecord>& records, double teleport_t_s, double distance_m) {
  AmclRunRecord r;
  r.distance_m = distance_m;
  r.kidnapped = teleport_t_s >= 0.0;
  int kidnap_updates = -1;
  bool lost = false;  // between the teleport and the filter's convergence at the new place
  double sum_d2 = 0.0, sum_a2 = 0.0;
  std::size_t n = 0;
  for (const EstimateRecord& e : records) {
    if (!e.scan) continue;
    const double d = (e.estimate.pose.translation() - e.truth.translation()).norm();
    const double a = std::abs(wrap_angle(e.estimate.pose.yaw - e.truth.yaw));
    const bool good = e.estimate.converged && d <= kConvergedErrorM && a <= kConvergedErrorRad;
    r.error_m.emplace_back(e.t_s, d);
    r.particles.emplace_back(e.t_s, e.estimate.particles);
    r.max_particles = std::max(r.max_particles, e.estimate.particles);
    r.updates = e.estimate.updates;
    if (r.kidnapped && kidnap_updates < 0 && e.t_s > teleport_t_s) {
      kidnap_updates = e.estimate.updates;
      lost = true;
    }
    if (lost && good) {
      r.kidnap_reconverge_updates = e.estimate.updates - kidnap_updates;
      lost = false;
    }
    if (r.updates_to_converge < 0 && good) r.updates_to_converge = e.estimate.updates;
    if (lost) continue;
    if (e.estimate.converged && d > kFalseConvergenceM) ++r.false_convergences;
    if (r.updates_to_converge >= 0) {
      sum_d2 += d * d;
      sum_a2 += a * a;
      r.max_error_m = std::max(r.max_error_m, d);
      ++n;
    }
  }
  r.rmse_m = n ? std::sqrt(sum_d2 / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
  r.yaw_rmse_deg = n ? std::sqrt(sum_a2 / static_cast<double>(n)) * kRadToDeg : std::numeric_limits<double>::quiet_NaN();
  return r;
}

std::string file_stem(const std::string& path) { return fs::path(path).stem().string(); }

}  // namespace

std::vector<ScenarioOverride> amcl_case_overrides(const std::string& case_name) {
  const std::vector<ScenarioOverride> recovery = {{"localization.amcl.max_particles", "10000"},
                                                  {"localization.amcl.recovery_alpha_slow", "0.001"},
                                                  {"localization.amcl.recovery_alpha_fast", "0.1"}};
  if (case_name == "tracking") return {};
  if (case_name == "kidnap") {
    // The recovery draws from the scan where it fits clearly better than every particle.
    std::vector<ScenarioOverride> o = recovery;
    o.push_back({"localization.amcl.scan_proposal", "true"});
    o.push_back({"localization.amcl.proposal_recovery", "true"});
    return o;
  }
  if (case_name == "global") {
    std::vector<ScenarioOverride> o = recovery;
    o.push_back({"localization.amcl.initial", "global"});
    o.push_back({"localization.amcl.scan_proposal", "true"});
    return o;
  }
  throw Error("unknown case '" + case_name + "' (tracking, global, kidnap)", {}, 0, "--cases");
}

AmclBenchResult run_amcl_bench(const AmclBenchConfig& config, const ExperimentProgress& progress) {
  if (config.seeds < 1) throw Error("at least one seed", {}, 0, "--seeds");
  if (config.scenarios.empty()) throw Error("no scenario", {}, 0, "SCENARIO");
  const CommandOwnedKey owned[] = {{"sim.seed", "--seeds and --seed-base give each run its seed"}};
  check_user_overrides(config.overrides, owned);
  AmclBenchResult result;
  result.config = config;
  for (const std::string& c : config.cases) result.grid.variants.push_back({c, {}});
  // specs[instance][case]: the case's settings first, the user's --set after (they win).
  std::vector<std::vector<ScenarioSpec>> specs;
  for (const std::string& f : config.scenarios) {
    specs.emplace_back();
    for (const std::string& c : config.cases) {
      std::vector<ScenarioOverride> o = amcl_case_overrides(c);
      o.insert(o.end(), config.overrides.begin(), config.overrides.end());
      specs.back().push_back(load_scenario(f, o));
      if (!specs.back().back().localization) throw Error("no localization section", f, 0, "localization");
    }
    result.names.push_back(specs.back().front().name);
  }
  result.grid.instances = config.scenarios;
  result.grid.seeds = consecutive_seeds(config.seed_base, config.seeds);
  struct Setup {
    ScenarioSpec spec;
    bool kidnap = false;
  };
  const auto prepare = [&](const TrialKey& key) {
    Setup s{specs[key.instance][key.variant], config.cases[key.variant] == "kidnap"};
    s.spec.seed = key.seed;
    return s;
  };
  const auto run = [&](Setup& setup, const TrialKey&) {
    Simulation sim(setup.spec);
    LocalizationChain chain(sim, localization_config(setup.spec));
    std::unique_ptr<RouteDrive> route;
    if (setup.spec.route) {
      route = make_route_drive(sim);
      if (setup.kidnap)
        route->kidnap_at(0.4 * route->lap_length_m() * setup.spec.route->laps / setup.spec.route->speed_mps, 5.0, kPi / 2);
    }
    sim.run();
    double teleport = setup.spec.teleports.empty() ? -1.0 : setup.spec.teleports.back().t_s;
    if (route && route->kidnap_time() >= 0.0) teleport = route->kidnap_time();
    return amcl_run_record(chain.records(0), teleport, sim.metrics().distance_m);
  };
  result.trials = run_experiment<Setup, AmclRunRecord>(result.grid, prepare, run, progress);
  return result;
}

std::string amcl_bench_runs_csv(const AmclBenchResult& r) {
  std::string out =
      "scenario,case,seed,completed,distance_m,updates,updates_to_converge,rmse_m,yaw_rmse_deg,max_error_m,"
      "kidnap_reconverge_updates,false_convergences,max_particles,error\n";
  for (const auto& t : r.trials) {
    const AmclRunRecord& a = t.record;
    out += csv_field(r.names[t.key.instance]) + "," + r.config.cases[t.key.variant] + "," + std::to_string(t.key.seed) + (t.completed ? ",1," : ",0,");
    out += format_fixed(a.distance_m, 3) + "," + std::to_string(a.updates) + "," + std::to_string(a.updates_to_converge) + ",";
    out += format_fixed(a.rmse_m, 4) + "," + format_fixed(a.yaw_rmse_deg, 3) + "," + format_fixed(a.max_error_m, 4) + ",";
    out += std::to_string(a.kidnap_reconverge_updates) + "," + std::to_string(a.false_convergences) + "," +
           std::to_string(a.max_particles) + "," + csv_field(t.error) + "\n";
  }
  return out;
}

namespace {

struct AmclScenarioSummary {
  std::size_t runs = 0, completed = 0, converged = 0, converged_within_30 = 0, kidnapped = 0, reconverged_within_50 = 0;
  std::size_t runs_with_false_convergence = 0;
  SampleStats updates_to_converge, rmse_m, yaw_rmse_deg, reconverge_updates, distance_m;
};

AmclScenarioSummary summarise_amcl(const AmclBenchResult& r, std::size_t instance, std::size_t variant) {
  AmclScenarioSummary s;
  std::vector<double> conv, rmse, yaw, reconv, dist;
  for (const auto& t : r.trials) {
    if (t.key.instance != instance || t.key.variant != variant) continue;
    ++s.runs;
    if (!t.completed) continue;
    ++s.completed;
    const AmclRunRecord& a = t.record;
    dist.push_back(a.distance_m);
    if (a.false_convergences > 0) ++s.runs_with_false_convergence;
    if (a.updates_to_converge >= 0) {
      ++s.converged;
      if (a.updates_to_converge <= 30) ++s.converged_within_30;
      conv.push_back(a.updates_to_converge);
      rmse.push_back(a.rmse_m);
      yaw.push_back(a.yaw_rmse_deg);
    }
    if (a.kidnapped) {
      ++s.kidnapped;
      if (a.kidnap_reconverge_updates >= 0) {
        reconv.push_back(a.kidnap_reconverge_updates);
        if (a.kidnap_reconverge_updates <= 50) ++s.reconverged_within_50;
      }
    }
  }
  s.updates_to_converge = sample_stats(conv);
  s.rmse_m = sample_stats(rmse);
  s.yaw_rmse_deg = sample_stats(yaw);
  s.reconverge_updates = sample_stats(reconv);
  s.distance_m = sample_stats(dist);
  return s;
}

std::string median_text(const SampleStats& s, int precision) {
  return s.n ? format_fixed(s.median, precision) + " [" + format_fixed(s.q25, precision) + " .. " + format_fixed(s.q75, precision) + "]"
             : std::string("-");
}

}  // namespace

std::string amcl_bench_markdown(const AmclBenchResult& r) {
  std::ostringstream out;
  out << "# AMCL in the simulator: " << r.config.seeds << " seeds from " << r.config.seed_base << "\n\n";
  out << "| scenario | case | runs | converged (<= 30 updates) | updates to converge | RMSE after [m] | yaw RMSE after [deg] | "
         "kidnapped: reconverged (<= 50 updates) | updates to reconverge | runs with a false convergence | driven [m] |\n"
         "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < r.names.size(); ++i)
    for (std::size_t v = 0; v < r.config.cases.size(); ++v) {
    const AmclScenarioSummary s = summarise_amcl(r, i, v);
    out << "| " << r.names[i] << " | " << r.config.cases[v] << " | " << s.completed << "/" << s.runs << " | " << s.converged << " (" << s.converged_within_30
        << ") | " << median_text(s.updates_to_converge, 0) << " | " << median_text(s.rmse_m, 4) << " | "
        << median_text(s.yaw_rmse_deg, 3) << " | ";
    if (s.kidnapped)
      out << s.reconverge_updates.n << " (" << s.reconverged_within_50 << ") of " << s.kidnapped << " | "
          << median_text(s.reconverge_updates, 0);
    else
      out << "- | -";
    out << " | " << s.runs_with_false_convergence << " | " << median_text(s.distance_m, 1) << " |\n";
    }
  out << "\nMedians [quartiles] over the runs where they apply. Converged: the best cluster holds 90 % of the weight "
         "within 0.15 m, and the estimate is within 0.25 m and 0.25 rad of the truth.\n";
  return out.str();
}

std::string amcl_bench_json(const AmclBenchResult& r) {
  json doc;
  doc["benchmark"] = "amcl";
  doc["seeds"] = r.config.seeds;
  doc["seed_base"] = r.config.seed_base;
  json list = json::array();
  for (std::size_t i = 0; i < r.names.size(); ++i)
    for (std::size_t v = 0; v < r.config.cases.size(); ++v) {
    const AmclScenarioSummary s = summarise_amcl(r, i, v);
    const auto stats = [](const SampleStats& x) { return json{{"n", x.n}, {"median", x.median}, {"q25", x.q25}, {"q75", x.q75}, {"max", x.max}}; };
    list.push_back({{"scenario", r.names[i]},
                    {"case", r.config.cases[v]},
                    {"file", r.config.scenarios[i]},
                    {"runs", s.runs},
                    {"completed", s.completed},
                    {"converged", s.converged},
                    {"converged_within_30_updates", s.converged_within_30},
                    {"updates_to_converge", stats(s.updates_to_converge)},
                    {"rmse_m", stats(s.rmse_m)},
                    {"yaw_rmse_deg", stats(s.yaw_rmse_deg)},
                    {"kidnapped", s.kidnapped},
                    {"reconverged_within_50_updates", s.reconverged_within_50},
                    {"updates_to_reconverge", stats(s.reconverge_updates)},
                    {"runs_with_false_convergence", s.runs_with_false_convergence},
                    {"distance_m", stats(s.distance_m)}});
    }
  doc["runs"] = list;
  return doc.dump(2) + "\n";
}

void write_amcl_bench_pictures(const AmclBenchResult& r, const std::string& dir) {
  for (std::size_t i = 0; i < r.names.size(); ++i)
    for (std::size_t v = 0; v < r.config.cases.size(); ++v) {
    const Trial<AmclRunRecord>* first = nullptr;
    for (const auto& t : r.trials)
      if (t.key.instance == i && t.key.variant == v && t.completed) {
        first = &t;
        break;
      }
    if (!first) continue;
    const std::string stem = file_stem(r.config.scenarios[i]) + "_" + r.config.cases[v];
    viz::LinePlot error({.title = r.names[i] + ", seed " + std::to_string(first->key.seed) + ": position error",
                         .x_label = "t [s]", .y_label = "error [m]"});
    error.add_series(first->record.error_m, {}, "AMCL - truth");
    error.write_svg((fs::path(dir) / ("error_" + stem + ".svg")).string());
    viz::LinePlot particles({.title = r.names[i] + ", seed " + std::to_string(first->key.seed) + ": particles",
                             .x_label = "t [s]", .y_label = "particles"});
    particles.add_series(first->record.particles, {.colour = viz::categorical_colour(1)}, "particles");
    particles.write_svg((fs::path(dir) / ("particles_" + stem + ".svg")).string());
    }
}

}  // namespace starnav
