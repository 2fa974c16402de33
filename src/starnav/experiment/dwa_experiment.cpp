#include "starnav/experiment/dwa_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/harness/navigation_run.hpp"

namespace starnav {

void DwaExperimentConfig::validate() const {
  if (experiment != "doorway" && experiment != "sideways" && experiment != "people")
    throw Error("unknown experiment '" + one_line(experiment, 40) + "' (doorway, sideways, people)", {}, 0, "--case");
  if (seeds < 1 || seeds > 100000) throw Error("must be in [1, 100000]", {}, 0, "--seeds");
}

int max_sign_changes(const std::vector<double>& t, const std::vector<std::vector<double>>& series, double window_s,
                     double deadband) {
  // Times of the sign changes of every series, then the most inside any window.
  std::vector<double> changes;
  for (const std::vector<double>& v : series) {
    int last = 0;
    for (std::size_t i = 0; i < v.size() && i < t.size(); ++i) {
      const int s = v[i] > deadband ? 1 : (v[i] < -deadband ? -1 : 0);
      if (s == 0) continue;
      if (last != 0 && s != last) changes.push_back(t[i]);
      last = s;
    }
  }
  std::sort(changes.begin(), changes.end());
  int best = 0;
  for (std::size_t i = 0, j = 0; i < changes.size(); ++i) {
    while (changes[i] - changes[j] > window_s) ++j;
    best = std::max(best, static_cast<int>(i - j + 1));
  }
  return best;
}

namespace {

// Each moving obstacle shifted in time by up to +-3 s and slowed by up to 20 %, from the seed.
void vary_people(ScenarioSpec& spec, std::uint64_t seed) {
  Rng rng = Rng(seed).fork(77);
  for (ScenarioObstacle& o : spec.obstacles) {
    if (o.waypoints.size() < 2) continue;
    const double shift = rng.uniform(-3.0, 3.0), scale = rng.uniform(0.8, 1.0);
    const double t0 = o.waypoints.front().t_s;
    for (ScenarioObstacle::Point& p : o.waypoints) p.t_s = std::max(0.0, t0 + shift) + (p.t_s - t0) / scale;
  }
}

}  // namespace

DwaExperimentResult run_dwa_experiment(const DwaExperimentConfig& config, const ExperimentProgress& progress) {
  config.validate();
  DwaExperimentResult result;
  result.config = config;
  const CommandOwnedKey owned[] = {{"sim.seed", "--seeds and --seed-base give each run its seed"}};
  check_user_overrides(config.overrides, owned);
  const ScenarioSpec base = load_scenario(config.scenario_file, config.overrides);
  if (!base.navigation) throw Error("not a navigation scenario (no navigation section)", base.file, 0, "navigation");
  result.scenario_name = base.name;
  result.grid.instances = {config.scenario_file};
  result.grid.variants = {{config.experiment, {}}};
  result.grid.seeds = consecutive_seeds(config.seed_base, config.seeds);
  struct Setup {
    ScenarioSpec spec;
  };
  const auto prepare = [&](const TrialKey& key) {
    Setup s{base};
    s.spec.seed = key.seed;
    if (config.experiment == "people") vary_people(s.spec, key.seed);
    return s;
  };
  const auto run = [&](Setup& setup, const TrialKey&) {
    NavigationOptions o;
    o.record_steps = false;
    NavigationRun nav(setup.spec, o);
    nav.run();
    const NavigationMetrics m = nav.metrics();
    DwaRunRecord r;
    r.arrived = m.success;
    r.outcome = m.outcome;
    r.time_s = m.duration_s;
    r.goal_distance_m = m.goal_distance_m;
    r.recoveries = m.recoveries;
    const auto& traj = nav.simulation().trajectory();
    std::vector<double> t, vx, wz;
    const double yaw0 = setup.spec.start.yaw;
    for (const TrajectorySample& s : traj) {
      t.push_back(s.t_s);
      vx.push_back(s.twist.vx);
      wz.push_back(s.twist.wz);
      r.max_abs_vy_mps = std::max(r.max_abs_vy_mps, std::abs(s.twist.vy));
      r.max_turn_deg = std::max(r.max_turn_deg, std::abs(rad_to_deg(wrap_angle(s.rpy.z() - yaw0))));
    }
    r.max_sign_changes_2s = max_sign_changes(t, {vx, wz}, 2.0, 0.01);
    for (const SimEvent& e : nav.simulation().events()) {
      if (e.kind != "collision") continue;
      ++r.contacts;
      // The robot's velocity towards the contact at the sample before it.
      auto it = std::upper_bound(traj.begin(), traj.end(), e.t_s, [](double v, const TrajectorySample& s) { return v < s.t_s; });
      if (it != traj.begin()) --it;
      const double c = std::cos(it->rpy.z()), s = std::sin(it->rpy.z());
      const Vec2 v(c * it->twist.vx - s * it->twist.vy, s * it->twist.vx + c * it->twist.vy);
      const Vec2 d = e.where - it->position.head<2>();
      if (d.norm() > 1e-9 && v.dot(d.normalized()) > 0.05) ++r.robot_caused_contacts;
    }
    return r;
  };
  result.trials = run_experiment<Setup, DwaRunRecord>(result.grid, prepare, run, progress);
  for (const auto& t : result.trials) {
    if (!t.completed) continue;
    result.arrived += t.record.arrived;
    result.calm += t.record.arrived && t.record.max_sign_changes_2s <= 2;
    result.robot_caused += t.record.robot_caused_contacts;
  }
  return result;
}

std::string dwa_experiment_markdown(const DwaExperimentResult& r) {
  const std::size_t n = r.trials.size();
  std::string s = "# DWA: " + r.config.experiment + " (" + r.scenario_name + ", " + std::to_string(n) + " seeds)\n\n";
  s += "Arrived: " + std::to_string(r.arrived) + " of " + std::to_string(n) + ". ";
  if (r.config.experiment == "doorway")
    s += "Arrived with at most two sign changes of vx or wz in any 2 s window: " + std::to_string(r.calm) + " of " +
         std::to_string(n) + ".";
  if (r.config.experiment == "people")
    s += "Contacts the robot caused (moving towards the contact faster than 0.05 m/s): " + std::to_string(r.robot_caused) + ".";
  s += "\n\n| seed | outcome | time (s) | goal distance (m) | sign changes / 2 s | max \\|vy\\| (m/s) | max turn (deg) | contacts | robot-caused | recoveries |\n";
  s += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& t : r.trials) {
    const DwaRunRecord& x = t.record;
    if (!t.completed) {
      s += "| " + std::to_string(t.key.seed) + " | error: " + t.error + " | | | | | | | | |\n";
      continue;
    }
    s += "| " + std::to_string(t.key.seed) + " | " + x.outcome + " | " + format_fixed(x.time_s, 1) + " | " +
         format_fixed(x.goal_distance_m, 3) + " | " + std::to_string(x.max_sign_changes_2s) + " | " +
         format_fixed(x.max_abs_vy_mps, 2) + " | " + format_fixed(x.max_turn_deg, 1) + " | " + std::to_string(x.contacts) +
         " | " + std::to_string(x.robot_caused_contacts) + " | " + std::to_string(x.recoveries) + " |\n";
  }
  return s;
}

std::string dwa_experiment_json(const DwaExperimentResult& r) {
  nlohmann::ordered_json j;
  j["experiment"] = r.config.experiment;
  j["scenario"] = r.scenario_name;
  j["seeds"] = r.trials.size();
  j["arrived"] = r.arrived;
  j["calm"] = r.calm;
  j["robot_caused_contacts"] = r.robot_caused;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const auto& t : r.trials) {
    const DwaRunRecord& x = t.record;
    runs.push_back({{"seed", t.key.seed}, {"completed", t.completed}, {"arrived", x.arrived}, {"outcome", x.outcome},
                    {"time_s", x.time_s}, {"goal_distance_m", x.goal_distance_m},
                    {"max_sign_changes_2s", x.max_sign_changes_2s}, {"max_abs_vy_mps", x.max_abs_vy_mps},
                    {"max_turn_deg", x.max_turn_deg}, {"contacts", x.contacts},
                    {"robot_caused_contacts", x.robot_caused_contacts}, {"recoveries", x.recoveries}});
  }
  j["runs"] = std::move(runs);
  return j.dump(2) + "\n";
}

std::string dwa_experiment_csv(const DwaExperimentResult& r) {
  std::string s = "seed,completed,arrived,outcome,time_s,goal_distance_m,max_sign_changes_2s,max_abs_vy_mps,max_turn_deg,"
                  "contacts,robot_caused_contacts,recoveries\n";
  for (const auto& t : r.trials) {
    const DwaRunRecord& x = t.record;
    s += std::to_string(t.key.seed) + ',' + (t.completed ? "1" : "0") + ',' + (x.arrived ? "1" : "0") + ',' + x.outcome + ',' +
         format_fixed6(x.time_s) + ',' + format_fixed6(x.goal_distance_m) + ',' + std::to_string(x.max_sign_changes_2s) + ',' +
         format_fixed6(x.max_abs_vy_mps) + ',' + format_fixed6(x.max_turn_deg) + ',' + std::to_string(x.contacts) + ',' +
         std::to_string(x.robot_caused_contacts) + ',' + std::to_string(x.recoveries) + '\n';
  }
  return s;
}

}  // namespace starnav
