#include "starnav/experiment/localization_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/harness/localization_chain.hpp"
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
  const ScenarioSpec base = load_scenario(config.scenario_file, config.overrides);
  result.scenario_name = base.name;
  if (!base.imu) throw Error("the scenario has no sensors.imu", base.file, 0, "sensors.imu");
  if (base.imu) result.bias_truth_radps = base.imu->config.yaw_rate_bias_radps;
  const LocalizationConfig chain_config = localization_config(base);
  if (chain_config.localizer.name != "ekf" || chain_config.odometry != "wheel")
    throw Error("the EKF square needs localization {odometry: wheel, localizer: ekf}", base.file, 0, "localization");
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
  out << summary_markdown(r.summaries, error_metric_names(), 0) << "\n";
  out << "| localizer | seeds with RMSE and end drift at most half of odometry's |\n|---|---|\n";
  for (std::size_t l = 0; l < r.summaries.size(); ++l)
    out << "| " << r.summaries[l].variant << " | " << r.halves_odometry[l] << " of " << r.config.seeds << " |\n";
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

}  // namespace starnav
