#include "starnav/experiment/navigation_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/experiment/metrics.hpp"

namespace starnav {

namespace {

using json = nlohmann::ordered_json;
using Stat = SampleStats;

// The two navigation runs of every seed, in this order.
constexpr const char* kNavPlanners[2] = {"dstar_lite", "astar"};

json nav_number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json nav_stat_json(const Stat& s) {
  json j;
  j["n"] = s.n;
  if (s.n == 0) {
    j["median"] = j["min"] = j["max"] = j["mean"] = nullptr;
    return j;
  }
  j["median"] = nav_number_or_null(s.median);
  j["min"] = nav_number_or_null(s.min);
  j["max"] = nav_number_or_null(s.max);
  j["mean"] = nav_number_or_null(s.mean);
  return j;
}

// The metrics summarised over the seeds. arrived_only: only runs that reached the goal.
struct NavMetricField {
  const char* key;
  double (*get)(const NavigationMetrics&);
  int precision;
  bool count;  // an integer count (table: no decimals for min and max)
  bool arrived_only;
};

const NavMetricField kMetrics[] = {
    {"time_to_goal_s", [](const NavigationMetrics& m) { return m.time_to_goal_s; }, 2, false, true},
    {"duration_s", [](const NavigationMetrics& m) { return m.duration_s; }, 2, false, false},
    {"distance_m", [](const NavigationMetrics& m) { return m.distance_m; }, 2, false, false},
    {"plans", [](const NavigationMetrics& m) { return static_cast<double>(m.plans); }, 1, true, false},
    {"replans", [](const NavigationMetrics& m) { return static_cast<double>(m.replans); }, 1, true, false},
    {"expanded_total", [](const NavigationMetrics& m) { return static_cast<double>(m.expanded_total); }, 1, true, false},
    {"replan_expanded", [](const NavigationMetrics& m) { return static_cast<double>(m.replan_expanded); }, 1, true, false},
    {"collisions", [](const NavigationMetrics& m) { return static_cast<double>(m.collisions); }, 1, true, false},
    {"deviation_mean_m", [](const NavigationMetrics& m) { return m.deviation_mean_m; }, 4, false, false},
    {"deviation_max_m", [](const NavigationMetrics& m) { return m.deviation_max_m; }, 4, false, false},
    {"goal_distance_m", [](const NavigationMetrics& m) { return m.goal_distance_m; }, 3, false, false},
};

std::vector<MetricGetter<NavRunRecord>> metric_getters() {
  std::vector<MetricGetter<NavRunRecord>> g;
  for (const NavMetricField& f : kMetrics)
    g.push_back([f](const NavRunRecord& r) -> std::optional<double> {
      if (f.arrived_only && !r.m.success) return std::nullopt;
      return f.get(r.m);
    });
  return g;
}

NavSummary summarise(const std::vector<NavTrial>& trials, const VariantSummary& generic, std::size_t variant) {
  NavSummary s;
  s.planner = generic.variant;
  s.runs = generic.runs;
  s.completed = generic.completed;
  s.successes = generic.successes;
  s.metrics = generic.metrics;
  std::vector<double> ratios, walls, rtfs;
  for (const NavTrial& t : trials) {
    if (t.key.variant != variant) continue;
    if (!t.completed) {
      ++s.errors;
      continue;
    }
    const NavigationMetrics& m = t.record.m;
    if (m.outcome == "arrived") ++s.arrived;
    else if (m.outcome == "no_path") ++s.no_path;
    else if (m.outcome == "timeout") ++s.timeout;
    else ++s.other;
    s.collisions_total += m.collisions;
    s.replans_total += m.replans;
    s.replan_expanded_total += m.replan_expanded;
    s.astar_replan_expanded_total += m.astar_replan_expanded;
    s.astar_backward_replan_expanded_total += m.astar_backward_replan_expanded;
    if (m.replan_expanded > 0)
      ratios.push_back(static_cast<double>(m.astar_replan_expanded) / static_cast<double>(m.replan_expanded));
    if (!m.costs_match) {
      s.costs_match_all = false;
      s.costs_differ_seeds.push_back(t.key.seed);
    }
    s.wall_s_total += t.record.wall_s;
    walls.push_back(t.record.wall_s);
    rtfs.push_back(t.record.real_time_factor);
  }
  if (s.replan_expanded_total > 0) {
    const auto total = static_cast<double>(s.replan_expanded_total);
    s.expansion_ratio = static_cast<double>(s.astar_replan_expanded_total) / total;
    s.backward_expansion_ratio = static_cast<double>(s.astar_backward_replan_expanded_total) / total;
  }
  s.per_run_ratio = sample_stats(std::move(ratios));
  s.wall_s = sample_stats(std::move(walls));
  s.real_time_factor = sample_stats(std::move(rtfs));
  return s;
}

json summary_json(const NavSummary& s, bool compared) {
  json j;
  j["planner"] = s.planner;
  j["role"] = compared ? "followed by the robot; A* from scratch ran beside every plan (compare_astar)"
                       : "A* from scratch at every plan (the paper)";
  j["runs"] = s.runs;
  j["completed"] = s.completed;
  j["successes"] = s.successes;
  j["success_rate"] = s.runs ? static_cast<double>(s.successes) / static_cast<double>(s.runs) : 0.0;
  j["outcomes"] = {{"arrived", s.arrived}, {"no_path", s.no_path}, {"timeout", s.timeout}, {"error", s.errors}};
  if (s.other) j["outcomes"]["other"] = s.other;
  json metrics;
  for (std::size_t k = 0; k < std::size(kMetrics); ++k) metrics[kMetrics[k].key] = nav_stat_json(s.metrics[k]);
  j["metrics"] = metrics;
  j["metrics_over"] = "completed runs; time_to_goal_s over the runs that arrived";
  j["collisions_total"] = s.collisions_total;
  j["replans_total"] = s.replans_total;
  if (compared) {
    json c;
    c["replans"] = s.replans_total;
    c["replan_expanded_total"] = s.replan_expanded_total;
    c["astar_replan_expanded_total"] = s.astar_replan_expanded_total;
    c["expansion_ratio"] = nav_number_or_null(s.expansion_ratio);
    c["expansion_ratio_means"] = "sum of A*-from-scratch expansions / sum of D* Lite expansions over the replans";
    c["astar_backward_replan_expanded_total"] = s.astar_backward_replan_expanded_total;
    c["backward_expansion_ratio"] = nav_number_or_null(s.backward_expansion_ratio);
    c["backward_expansion_ratio_means"] =
        "the same with A* from scratch searching from the goal to the robot, D* Lite's direction";
    c["per_run_ratio"] = nav_stat_json(s.per_run_ratio);
    c["costs_match_all"] = s.costs_match_all;
    c["costs_differ_seeds"] = s.costs_differ_seeds;
    j["astar_comparison"] = c;
  }
  return j;
}

// The wall-clock figures of a planner's runs: timing.json only (they differ between runs).
json wall_clock_json(const NavSummary& s) {
  json w;
  w["wall_s_total"] = s.wall_s_total;
  w["wall_s"] = nav_stat_json(s.wall_s);
  w["real_time_factor"] = nav_stat_json(s.real_time_factor);
  return w;
}

json run_json(const NavTrial& t) {
  const NavRunRecord& r = t.record;
  json j;
  j["seed"] = t.key.seed;
  j["planner"] = r.planner;
  if (!t.completed) {
    j["success"] = false;
    j["outcome"] = "error";
    j["reason"] = t.error;
    return j;
  }
  const NavigationMetrics& m = r.m;
  j["success"] = m.success;
  j["outcome"] = m.outcome;
  j["reason"] = m.reason;
  j["motion_mode"] = m.motion_mode;
  j["time_to_goal_s"] = m.success ? json(m.time_to_goal_s) : json(nullptr);
  j["duration_s"] = m.duration_s;
  j["distance_m"] = m.distance_m;
  j["plans"] = m.plans;
  j["replans"] = m.replans;
  j["expanded_total"] = m.expanded_total;
  j["replan_expanded"] = m.replan_expanded;
  if (r.planner == kNavPlanners[0]) {
    j["astar_replan_expanded"] = m.astar_replan_expanded;
    j["astar_backward_replan_expanded"] = m.astar_backward_replan_expanded;
    j["expansion_ratio"] = m.replan_expanded > 0 ? json(static_cast<double>(m.astar_replan_expanded) /
                                                         static_cast<double>(m.replan_expanded))
                                                   : json(nullptr);
    j["costs_match"] = m.costs_match;
  }
  j["collisions"] = m.collisions;
  j["deviation_mean_m"] = m.deviation_mean_m;
  j["deviation_max_m"] = m.deviation_max_m;
  j["goal_distance_m"] = m.goal_distance_m;
  return j;
}

std::string csv_number(double v) {
  if (!std::isfinite(v)) return {};
  std::ostringstream s;
  s << std::setprecision(10) << v;
  return s.str();
}

std::string runs_csv(const std::vector<NavTrial>& trials) {
  std::ostringstream o;
  o << "seed,planner,success,outcome,reason,motion_mode,time_to_goal_s,duration_s,distance_m,plans,replans,"
       "expanded_total,replan_expanded,astar_replan_expanded,astar_backward_replan_expanded,expansion_ratio,costs_match,collisions,"
       "deviation_mean_m,deviation_max_m,goal_distance_m\n";
  for (const NavTrial& t : trials) {
    const NavRunRecord& r = t.record;
    o << t.key.seed << ',' << r.planner << ',';
    if (!t.completed) {
      o << "0,error," << csv_field(t.error) << std::string(16, ',') << '\n';
      continue;
    }
    const NavigationMetrics& m = r.m;
    const bool compared = r.planner == kNavPlanners[0];
    o << (m.success ? 1 : 0) << ',' << csv_field(m.outcome) << ',' << csv_field(m.reason) << ','
      << csv_field(m.motion_mode) << ',' << (m.success ? csv_number(m.time_to_goal_s) : std::string()) << ','
      << csv_number(m.duration_s) << ',' << csv_number(m.distance_m) << ',' << m.plans << ',' << m.replans << ','
      << m.expanded_total << ',' << m.replan_expanded << ',';
    if (compared) {
      o << m.astar_replan_expanded << ',' << m.astar_backward_replan_expanded << ',';
      if (m.replan_expanded > 0)
        o << csv_number(static_cast<double>(m.astar_replan_expanded) / static_cast<double>(m.replan_expanded));
      o << ',' << (m.costs_match ? 1 : 0) << ',';
    } else {
      o << ",,,,";
    }
    o << m.collisions << ',' << csv_number(m.deviation_mean_m) << ',' << csv_number(m.deviation_max_m) << ','
      << csv_number(m.goal_distance_m) << '\n';
  }
  return o.str();
}

std::string count_or_fixed(double v, bool count, int precision) {
  if (count && std::isfinite(v) && v == std::floor(v)) return format_fixed(v, 0);
  return format_fixed(v, precision);
}

std::string stat_cell(const Stat& s, const NavMetricField& f) {
  if (s.n == 0) return "-";
  return count_or_fixed(s.median, f.count, f.precision) + " [" + count_or_fixed(s.min, f.count, f.precision) + " .. " +
         count_or_fixed(s.max, f.count, f.precision) + "] " + count_or_fixed(s.mean, f.count, f.precision);
}

std::string percent(std::size_t k, std::size_t n) {
  return n ? format_fixed(100.0 * static_cast<double>(k) / static_cast<double>(n), 1) + " %" : std::string("-");
}

void print_table(std::ostream& out, const NavExperimentResult& result) {
  const NavExperimentConfig& c = result.config;
  const std::vector<NavSummary>& sums = result.summaries;
  const std::uint64_t base = c.seed_base, n = c.seeds;
  out << "bench nav: " << c.scenario.name << " (" << c.scenario_file << "), " << n << (n == 1 ? " seed" : " seeds")
      << " (" << base << ".." << base + n - 1 << "), motion mode " << c.motion_mode.value_or("from the scenario") << "\n";
  out << "dstar_lite: the robot follows D* Lite, A* from scratch runs beside every plan; astar: A* from scratch "
         "at every plan (the paper)\n\n";
  constexpr int kLabel = 28, kCol = 36;
  // One line of padded cells, without trailing blanks.
  auto line = [&](const std::string& label, const std::vector<std::string>& cells) {
    std::ostringstream l;
    l << std::left << std::setw(kLabel) << label;
    for (const std::string& c : cells) l << std::left << std::setw(kCol) << c;
    std::string text = l.str();
    text.erase(text.find_last_not_of(' ') + 1);
    out << text << "\n";
  };
  auto row = [&](const std::string& label, auto cell) {
    std::vector<std::string> cells;
    for (const NavSummary& s : sums) cells.push_back(cell(s));
    line(label, cells);
  };
  row("", [](const NavSummary& s) { return s.planner; });
  row("success", [](const NavSummary& s) {
    return std::to_string(s.successes) + "/" + std::to_string(s.runs) + " (" + percent(s.successes, s.runs) + ")";
  });
  row("outcomes", [](const NavSummary& s) {
    std::string t = "arrived " + std::to_string(s.arrived) + ", no_path " + std::to_string(s.no_path) + ", timeout " +
                    std::to_string(s.timeout);
    if (s.errors) t += ", error " + std::to_string(s.errors);
    if (s.other) t += ", other " + std::to_string(s.other);
    return t;
  });
  out << "\nmedian [min .. max] mean over the completed runs (time_to_goal_s: the runs that arrived)\n";
  for (std::size_t k = 0; k < std::size(kMetrics); ++k)
    row(kMetrics[k].key, [k](const NavSummary& s) { return stat_cell(s.metrics[k], kMetrics[k]); });
  row("collisions (total)", [](const NavSummary& s) { return std::to_string(s.collisions_total); });
  row("real-time factor (wall)", [](const NavSummary& s) {
    if (s.real_time_factor.n == 0) return std::string("-");
    return "median " + format_fixed(s.real_time_factor.median, 1) + "x, wall " + format_fixed(s.wall_s_total, 1) +
           " s total";
  });

  const NavSummary& d = sums[0];
  out << "\nD* Lite vs A* from scratch on the same replans (dstar_lite runs): ";
  if (d.replan_expanded_total == 0) {
    out << "no replan expanded a node (" << d.replans_total << " replans)\n";
  } else {
    out << "A* " << d.astar_replan_expanded_total << " / D* Lite " << d.replan_expanded_total << " expansions over "
        << d.replans_total << " replans = " << format_fixed(d.expansion_ratio, 2) << "x; per run median "
        << format_fixed(d.per_run_ratio.median, 2) << "x [" << format_fixed(d.per_run_ratio.min, 2) << " .. "
        << format_fixed(d.per_run_ratio.max, 2) << "] over " << d.per_run_ratio.n
        << (d.per_run_ratio.n == 1 ? " run" : " runs") << " with replans\n";
    out << "A* from scratch from the goal to the robot (D* Lite's direction): " << d.astar_backward_replan_expanded_total
        << " = " << format_fixed(d.backward_expansion_ratio, 2) << "x D* Lite's\n";
  }
  out << "plan costs: ";
  if (d.costs_match_all) {
    out << "every compared plan of every completed run had A*'s cost\n";
  } else {
    out << "DIFFER from A*'s in " << d.costs_differ_seeds.size() << " runs (seeds";
    for (std::size_t i = 0; i < d.costs_differ_seeds.size() && i < 10; ++i) out << " " << d.costs_differ_seeds[i];
    if (d.costs_differ_seeds.size() > 10) out << " ...";
    out << ")\n";
  }
}

}  // namespace

ExperimentGrid nav_experiment_grid(const NavExperimentConfig& config) {
  ExperimentGrid g;
  g.instances = {config.scenario_file};
  for (const char* planner : kNavPlanners) g.variants.push_back({planner, {{"navigation.planner", planner}}});
  g.seeds = consecutive_seeds(config.seed_base, config.seeds);
  return g;
}

const std::vector<std::string>& nav_summary_metrics() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const NavMetricField& f : kMetrics) n.emplace_back(f.key);
    return n;
  }();
  return names;
}

NavExperimentResult run_nav_experiment(const NavExperimentConfig& config, const ExperimentProgress& progress) {
  if (config.seeds < 1) throw Error("at least one seed", {}, 0, "seeds");
  NavExperimentResult result;
  result.config = config;
  result.grid = nav_experiment_grid(config);
  const ExperimentGrid& grid = result.grid;
  struct Setup {
    std::unique_ptr<NavigationRun> run;
  };
  const auto prepare = [&](const TrialKey& key) {
    ScenarioSpec spec = config.scenario;
    spec.seed = key.seed;
    const std::string planner = grid.variants[key.variant].setting("navigation.planner");
    NavigationOptions options;
    options.motion_mode = config.motion_mode;
    options.planner = planner;
    options.compare_astar = planner == kNavPlanners[0];
    options.record_steps = false;
    return Setup{std::make_unique<NavigationRun>(spec, options)};
  };
  const auto run = [&](Setup& setup, const TrialKey&) {
    NavigationRun& r = *setup.run;
    r.run();
    NavRunRecord rec;  // its planner is named below, failed trials included
    rec.m = r.metrics();
    rec.wall_s = r.wall_s();
    rec.real_time_factor = rec.wall_s > 0.0 ? rec.m.duration_s / rec.wall_s : 0.0;
    return rec;
  };
  result.trials = run_experiment<Setup, NavRunRecord>(grid, prepare, run, progress);
  // A failed trial still names its planner in the reports.
  for (NavTrial& t : result.trials) t.record.planner = grid.variants[t.key.variant].name;
  const auto generic = summarise_by_variant<NavRunRecord>(grid, result.trials, metric_getters(),
                                                          [](const NavRunRecord& r) { return r.m.success; });
  for (std::size_t v = 0; v < generic.size(); ++v) result.summaries.push_back(summarise(result.trials, generic[v], v));
  return result;
}

std::string nav_experiment_json(const NavExperimentResult& result) {
  const NavExperimentConfig& c = result.config;
  json doc;
  doc["benchmark"] = "nav";
  doc["scenario"] = c.scenario_file;
  doc["name"] = c.scenario.name;
  doc["seeds"] = c.seeds;
  doc["seed_base"] = c.seed_base;
  doc["seed_last"] = c.seed_base + c.seeds - 1;
  doc["motion_mode"] = c.motion_mode ? json(*c.motion_mode) : json(nullptr);
  json planners = json::array();
  for (std::size_t p = 0; p < result.summaries.size(); ++p) planners.push_back(summary_json(result.summaries[p], p == 0));
  doc["planners"] = planners;
  json runs = json::array();
  for (const NavTrial& t : result.trials) runs.push_back(run_json(t));
  doc["runs"] = runs;
  return doc.dump(2) + "\n";
}

std::string nav_runs_csv(const NavExperimentResult& result) { return runs_csv(result.trials); }

std::string nav_timing_json(const NavExperimentResult& result) {
  json doc;
  doc["benchmark"] = "nav";
  doc["scenario"] = result.config.scenario_file;
  json planners = json::array();
  for (const NavSummary& s : result.summaries) {
    json p = wall_clock_json(s);
    p["planner"] = s.planner;
    planners.push_back(p);
  }
  doc["planners"] = planners;
  json runs = json::array();
  for (const NavTrial& t : result.trials)
    runs.push_back({{"seed", t.key.seed}, {"planner", t.record.planner}, {"wall_s", t.record.wall_s},
                    {"real_time_factor", t.record.real_time_factor}});
  doc["runs"] = runs;
  return doc.dump(2) + "\n";
}

std::string nav_experiment_table(const NavExperimentResult& result) {
  std::ostringstream out;
  print_table(out, result);
  return out.str();
}

}  // namespace starnav
