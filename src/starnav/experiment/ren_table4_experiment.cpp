#include "starnav/experiment/ren_table4_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/statistics.hpp"

namespace starnav {

namespace {

ErrorSpread spread(const std::vector<double>& v) {
  ErrorSpread s;
  if (v.empty()) return s;
  s.max = *std::max_element(v.begin(), v.end());
  s.min = *std::min_element(v.begin(), v.end());
  double sum = 0.0;
  for (const double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  return s;
}

std::string cm(double m) { return format_fixed(m * 100.0, 1); }
std::string deg(double r) { return format_fixed(rad_to_deg(r), 2); }

}  // namespace

RenTable4Result run_ren_table4(const RenTable4Config& config, const ExperimentProgress& progress) {
  if (config.seeds < 1) throw Error("at least one seed", {}, 0, "--seeds");
  RenTable4Result result;
  result.config = config;
  const CommandOwnedKey owned[] = {{"sim.seed", "--seeds and --seed-base give each run its seed"}};
  check_user_overrides(config.overrides, owned);
  const ScenarioSpec base = load_scenario(config.scenario_file, config.overrides);
  if (!base.navigation) throw Error("not a navigation scenario (no navigation section)", base.file, 0, "navigation");
  result.scenario_name = base.name;
  result.grid.instances = {config.scenario_file};
  result.grid.variants = {{"stack", {}}};
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
    NavigationOptions o;
    o.record_steps = false;
    NavigationRun nav(setup.spec, o);
    nav.run();
    const NavigationMetrics m = nav.metrics();
    RenTable4SeedRecord r;
    r.outcome = m.outcome;
    r.arrivals = m.arrivals;
    r.goals_total = m.goals_total;
    r.recoveries = m.recoveries;
    r.collisions = m.collisions;
    r.success = m.success && m.collisions == 0;
    r.sim_s = m.duration_s;
    r.wall_s = nav.wall_s();
    r.arrival_list = nav.arrivals();
    std::vector<double> ex, ey, eyaw;
    for (const NavArrival& a : r.arrival_list) {
      ex.push_back(std::abs(a.error_x_m()));
      ey.push_back(std::abs(a.error_y_m()));
      if (a.has_yaw) eyaw.push_back(std::abs(a.error_yaw_rad()));
    }
    r.x = spread(ex);
    r.y = spread(ey);
    r.yaw = spread(eyaw);
    if (result.controller.empty()) {
      result.controller = m.controller;
      result.planner = m.planner;
      result.localizer = std::string(nav.localizer().name());
    }
    return r;
  };
  result.trials = run_experiment<Setup, RenTable4SeedRecord>(result.grid, prepare, run, progress);

  std::vector<ErrorSpread> xs, ys, yaws;
  std::vector<double> rtf;
  for (const auto& t : result.trials) {
    if (!t.completed || !t.record.success) continue;
    ++result.seeds_ok;
    xs.push_back(t.record.x);
    ys.push_back(t.record.y);
    yaws.push_back(t.record.yaw);
    result.worst_x = std::max(result.worst_x, t.record.x.max);
    result.worst_y = std::max(result.worst_y, t.record.y.max);
    result.worst_yaw = std::max(result.worst_yaw, t.record.yaw.max);
    if (t.record.wall_s > 0.0) rtf.push_back(t.record.sim_s / t.record.wall_s);
  }
  const auto mean_of = [](const std::vector<ErrorSpread>& v) {
    ErrorSpread s;
    if (v.empty()) return s;
    for (const ErrorSpread& e : v) {
      s.max += e.max;
      s.min += e.min;
      s.mean += e.mean;
    }
    const double n = static_cast<double>(v.size());
    s.max /= n;
    s.min /= n;
    s.mean /= n;
    return s;
  };
  result.x = mean_of(xs);
  result.y = mean_of(ys);
  result.yaw = mean_of(yaws);
  result.real_time_factor_median = sample_stats(rtf).median;
  return result;
}

std::string ren_table4_markdown(const RenTable4Result& r) {
  std::string s = "# Ren et al. 2022 Table 4: arrival accuracy (" + r.scenario_name + ")\n\n";
  s += "Stack: " + r.localizer + " localization, " + r.planner + " global planner, " + r.controller +
       " local controller. " + std::to_string(r.seeds_ok) + " of " + std::to_string(r.trials.size()) +
       " seeds reached every goal without a collision; the table is over those. Each row: the mean over the seeds "
       "of each seed's max, min and mean absolute error over its arrivals (the true pose at rest against the goal).\n\n";
  s += "| error | max | min | mean | worst arrival | paper (max / min / mean) |\n|---|---|---|---|---|---|\n";
  s += "| x (cm) | " + cm(r.x.max) + " | " + cm(r.x.min) + " | " + cm(r.x.mean) + " | " + cm(r.worst_x) + " | 8.5 / 4.0 / 5.5 |\n";
  s += "| y (cm) | " + cm(r.y.max) + " | " + cm(r.y.min) + " | " + cm(r.y.mean) + " | " + cm(r.worst_y) + " | 7.2 / 4.3 / 5.2 |\n";
  s += "| heading (deg) | " + deg(r.yaw.max) + " | " + deg(r.yaw.min) + " | " + deg(r.yaw.mean) + " | " + deg(r.worst_yaw) +
       " | 21.8 / 6.5 / 15.6 |\n\n";
  s += "Real-time factor (simulated over wall time, median over seeds): " + format_fixed(r.real_time_factor_median, 1) + "x.\n\n";
  s += "| seed | outcome | arrivals | recoveries | x max / mean (cm) | y max / mean (cm) | heading max / mean (deg) |\n";
  s += "|---|---|---|---|---|---|---|\n";
  for (const auto& t : r.trials) {
    const RenTable4SeedRecord& x = t.record;
    if (!t.completed) {
      s += "| " + std::to_string(t.key.seed) + " | error: " + t.error + " | | | | | |\n";
      continue;
    }
    s += "| " + std::to_string(t.key.seed) + " | " + x.outcome + (x.collisions ? " (collided)" : "") + " | " +
         std::to_string(x.arrivals) + "/" + std::to_string(x.goals_total) + " | " + std::to_string(x.recoveries) + " | " +
         cm(x.x.max) + " / " + cm(x.x.mean) + " | " + cm(x.y.max) + " / " + cm(x.y.mean) + " | " + deg(x.yaw.max) + " / " +
         deg(x.yaw.mean) + " |\n";
  }
  return s;
}

std::string ren_table4_json(const RenTable4Result& r) {
  nlohmann::ordered_json j;
  j["scenario"] = r.scenario_name;
  j["localizer"] = r.localizer;
  j["planner"] = r.planner;
  j["controller"] = r.controller;
  j["seeds"] = r.trials.size();
  j["seeds_ok"] = r.seeds_ok;
  const auto row = [](const ErrorSpread& e, double scale) {
    return nlohmann::ordered_json{{"max", e.max * scale}, {"min", e.min * scale}, {"mean", e.mean * scale}};
  };
  j["x_cm"] = row(r.x, 100.0);
  j["y_cm"] = row(r.y, 100.0);
  j["heading_deg"] = row(r.yaw, 180.0 / kPi);
  j["worst"] = {{"x_cm", r.worst_x * 100.0}, {"y_cm", r.worst_y * 100.0}, {"heading_deg", rad_to_deg(r.worst_yaw)}};
  j["real_time_factor_median"] = r.real_time_factor_median;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const auto& t : r.trials) {
    nlohmann::ordered_json x;
    x["seed"] = t.key.seed;
    x["completed"] = t.completed;
    if (!t.completed) x["error"] = t.error;
    x["success"] = t.record.success;
    x["outcome"] = t.record.outcome;
    x["arrivals"] = t.record.arrivals;
    x["recoveries"] = t.record.recoveries;
    x["collisions"] = t.record.collisions;
    x["x_cm"] = row(t.record.x, 100.0);
    x["y_cm"] = row(t.record.y, 100.0);
    x["heading_deg"] = row(t.record.yaw, 180.0 / kPi);
    runs.push_back(std::move(x));
  }
  j["runs"] = std::move(runs);
  return j.dump(2) + "\n";
}

std::string ren_table4_runs_csv(const RenTable4Result& r) {
  std::string s =
      "seed,completed,success,outcome,arrivals,goals,recoveries,collisions,x_max_m,x_min_m,x_mean_m,y_max_m,y_min_m,y_mean_m,"
      "yaw_max_deg,yaw_min_deg,yaw_mean_deg,sim_s\n";
  for (const auto& t : r.trials) {
    const RenTable4SeedRecord& x = t.record;
    s += std::to_string(t.key.seed) + ',' + (t.completed ? "1" : "0") + ',' + (x.success ? "1" : "0") + ',' + x.outcome + ',' +
         std::to_string(x.arrivals) + ',' + std::to_string(x.goals_total) + ',' + std::to_string(x.recoveries) + ',' +
         std::to_string(x.collisions) + ',' + format_fixed6(x.x.max) + ',' + format_fixed6(x.x.min) + ',' +
         format_fixed6(x.x.mean) + ',' + format_fixed6(x.y.max) + ',' + format_fixed6(x.y.min) + ',' + format_fixed6(x.y.mean) +
         ',' + format_fixed6(rad_to_deg(x.yaw.max)) + ',' + format_fixed6(rad_to_deg(x.yaw.min)) + ',' +
         format_fixed6(rad_to_deg(x.yaw.mean)) + ',' + format_fixed6(x.sim_s) + '\n';
  }
  return s;
}

std::string ren_table4_arrivals_csv(const RenTable4Result& r) {
  std::string s = "seed,goal,lap,t_s,error_x_m,error_y_m,error_yaw_deg\n";
  for (const auto& t : r.trials)
    for (const NavArrival& a : t.record.arrival_list)
      s += std::to_string(t.key.seed) + ',' + std::to_string(a.goal) + ',' + std::to_string(a.lap) + ',' +
           format_fixed6(a.settled_t_s) + ',' + format_fixed6(a.error_x_m()) + ',' + format_fixed6(a.error_y_m()) + ',' +
           (a.has_yaw ? format_fixed6(rad_to_deg(a.error_yaw_rad())) : "") + '\n';
  return s;
}

}  // namespace starnav
