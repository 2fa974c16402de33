// starnav bench nav: a navigation scenario over many seeds (Li et al. 2019 navigation loop;
// harness/navigation_run.hpp), with D* Lite and A*-from-scratch replanning compared on the same runs.
//
//   starnav bench nav --scenario FILE --seeds N [--seed-base B] [--motion-mode M]
//                     [--out DIR] [--json | --csv] [--force] [--quiet]
//
// For every seed s = B .. B+N-1 (B = 0 by default) the scenario (loaded once) runs twice with
// sim.seed = s:
//   dstar_lite  the robot follows D* Lite; at every plan A* from scratch also runs on the same map
//               and start (compare_astar), so expansions are compared on identical queries;
//   astar       the paper's navigation, A* from scratch at every plan.
// Reported per planner: the success rate k/N and outcomes; median, min, max and mean over the seeds
// of time to goal (arrived runs only), sim duration, distance, plans, replans, expansions,
// collisions and path deviation; for the dstar_lite runs the expansion ratio A* / D* Lite over the
// replans (sum over all runs, and the median of the per-run ratios) and whether every compared plan
// had A*'s cost. Wall-clock figures are kept apart, in fields named wall_s and real_time_factor
// (simulated seconds per wall second) and in the "wall_clock" objects; everything else is
// deterministic.
//
// Output: a table on stdout (--json: one JSON document; --csv: one row per seed and planner). With
// --out DIR also DIR/runs.csv and DIR/summary.json (the --json document). Exit 0 when every run
// completed (a run that does not reach the goal is a result); 1 when a run failed with an
// exception (reported in the results as outcome "error" and in one line on stderr); 2 for bad
// flags or a bad scenario.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <limits>
#include <memory>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/control/path_follower.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

constexpr std::uint64_t kMaxSeeds = 1000000;
// The two navigation runs of every seed, in this order.
constexpr const char* kNavPlanners[2] = {"dstar_lite", "astar"};

struct NavBenchOptions {
  std::string scenario;
  std::string seeds;  // strings: parsed here so that errors name the flag in one line
  std::string seed_base;
  std::string motion_mode;
  std::vector<std::string> sets;
  std::string out;
  bool json = false;
  bool csv = false;
  bool force = false;
  bool quiet = false;
};

struct RunRecord {
  std::uint64_t seed = 0;
  std::string planner;
  bool completed = false;  // false: the run threw (error holds what)
  std::string error;
  NavigationMetrics m;
  double wall_s = 0.0;            // wall clock
  double real_time_factor = 0.0;  // wall clock: simulated s per wall s (0 when not measurable)
};

// ---- flags --------------------------------------------------------------------------------------

// cli_util's parse_unsigned, also taking a leading '+'.
std::uint64_t parse_count(const std::string& text, const std::string& flag, const char* what) {
  return parse_unsigned(text.size() > 1 && text[0] == '+' ? text.substr(1) : text, flag, what);
}

// ---- statistics ---------------------------------------------------------------------------------

using Stat = SampleStats;

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

// What one planner did over all seeds.
struct NavSummary {
  std::string planner;
  std::size_t runs = 0, completed = 0, successes = 0;
  std::size_t arrived = 0, no_path = 0, timeout = 0, errors = 0, other = 0;
  std::vector<Stat> metrics;  // as kMetrics
  std::int64_t collisions_total = 0;
  std::int64_t replans_total = 0;
  // dstar_lite: A* from scratch on the same replans.
  std::uint64_t replan_expanded_total = 0, astar_replan_expanded_total = 0;
  std::uint64_t astar_backward_replan_expanded_total = 0;  // A* from the goal to the robot
  double expansion_ratio = std::numeric_limits<double>::quiet_NaN();  // sum A* / sum D* Lite
  double backward_expansion_ratio = std::numeric_limits<double>::quiet_NaN();  // sum backward A* / sum D* Lite
  Stat per_run_ratio;                                                 // runs with replan expansions
  bool costs_match_all = true;
  std::vector<std::uint64_t> costs_differ_seeds;
  // wall clock
  double wall_s_total = 0.0;
  Stat wall_s, real_time_factor;
};

NavSummary summarise(const std::vector<RunRecord>& records, const std::string& planner) {
  NavSummary s;
  s.planner = planner;
  std::vector<std::vector<double>> values(std::size(kMetrics));
  std::vector<double> ratios, walls, rtfs;
  for (const RunRecord& r : records) {
    if (r.planner != planner) continue;
    ++s.runs;
    if (!r.completed) {
      ++s.errors;
      continue;
    }
    ++s.completed;
    const NavigationMetrics& m = r.m;
    s.successes += m.success;
    if (m.outcome == "arrived") ++s.arrived;
    else if (m.outcome == "no_path") ++s.no_path;
    else if (m.outcome == "timeout") ++s.timeout;
    else ++s.other;
    for (std::size_t k = 0; k < std::size(kMetrics); ++k)
      if (!kMetrics[k].arrived_only || m.success) values[k].push_back(kMetrics[k].get(m));
    s.collisions_total += m.collisions;
    s.replans_total += m.replans;
    s.replan_expanded_total += m.replan_expanded;
    s.astar_replan_expanded_total += m.astar_replan_expanded;
    s.astar_backward_replan_expanded_total += m.astar_backward_replan_expanded;
    if (m.replan_expanded > 0)
      ratios.push_back(static_cast<double>(m.astar_replan_expanded) / static_cast<double>(m.replan_expanded));
    if (!m.costs_match) {
      s.costs_match_all = false;
      s.costs_differ_seeds.push_back(r.seed);
    }
    s.wall_s_total += r.wall_s;
    walls.push_back(r.wall_s);
    rtfs.push_back(r.real_time_factor);
  }
  for (auto& v : values) s.metrics.push_back(sample_stats(std::move(v)));
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
  json w;
  w["wall_s_total"] = s.wall_s_total;
  w["wall_s"] = nav_stat_json(s.wall_s);
  w["real_time_factor"] = nav_stat_json(s.real_time_factor);
  j["wall_clock"] = w;
  return j;
}

json run_json(const RunRecord& r) {
  json j;
  j["seed"] = r.seed;
  j["planner"] = r.planner;
  if (!r.completed) {
    j["success"] = false;
    j["outcome"] = "error";
    j["reason"] = r.error;
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
  j["wall_s"] = r.wall_s;
  j["real_time_factor"] = r.real_time_factor;
  return j;
}

// ---- CSV ----------------------------------------------------------------------------------------

std::string csv_number(double v) {
  if (!std::isfinite(v)) return {};
  std::ostringstream s;
  s << std::setprecision(10) << v;
  return s.str();
}

std::string runs_csv(const std::vector<RunRecord>& records) {
  std::ostringstream o;
  o << "seed,planner,success,outcome,reason,motion_mode,time_to_goal_s,duration_s,distance_m,plans,replans,"
       "expanded_total,replan_expanded,astar_replan_expanded,astar_backward_replan_expanded,expansion_ratio,costs_match,collisions,"
       "deviation_mean_m,deviation_max_m,goal_distance_m,wall_s,real_time_factor\n";
  for (const RunRecord& r : records) {
    o << r.seed << ',' << r.planner << ',';
    if (!r.completed) {
      o << "0,error," << csv_field(r.error) << std::string(18, ',') << '\n';
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
      << csv_number(m.goal_distance_m) << ',' << csv_number(r.wall_s) << ',' << csv_number(r.real_time_factor)
      << '\n';
  }
  return o.str();
}

// ---- table --------------------------------------------------------------------------------------

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

void print_table(std::ostream& out, const ScenarioSpec& spec, const NavBenchOptions& o, std::uint64_t base,
                 std::uint64_t n, const std::vector<NavSummary>& sums) {
  out << "bench nav: " << spec.name << " (" << o.scenario << "), " << n << (n == 1 ? " seed" : " seeds") << " ("
      << base << ".." << base + n - 1 << "), motion mode "
      << (o.motion_mode.empty() ? std::string("from the scenario") : o.motion_mode) << "\n";
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

// ---- the command --------------------------------------------------------------------------------

void write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << text;
  f.flush();
  if (!f) throw Error("cannot write", p.string(), 0, "--out");
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

void run_bench_nav(const NavBenchOptions& o, Context& ctx) {
  // Flags first, before any work.
  if (o.scenario.empty()) throw Error("missing: give --scenario FILE (a navigation scenario)", {}, 0, "--scenario");
  if (o.seeds.empty()) throw Error("missing: give --seeds N (the number of seeds, at least 1)", {}, 0, "--seeds");
  const bool negative = !o.seeds.empty() && o.seeds[0] == '-';
  const std::uint64_t n = negative ? 0 : parse_count(o.seeds, "--seeds", "a positive integer");
  if (negative || n < 1 || n > kMaxSeeds)
    throw Error("must be 1.." + std::to_string(kMaxSeeds) + ", got '" + o.seeds + "'", {}, 0, "--seeds");
  const std::uint64_t base = o.seed_base.empty() ? 0 : parse_count(o.seed_base, "--seed-base", "a non-negative integer");
  if (base > std::numeric_limits<std::uint64_t>::max() - (n - 1))
    throw Error("the last seed B + N - 1 exceeds 2^64 - 1", {}, 0, "--seed-base");
  std::optional<MotionMode> mode;
  if (!o.motion_mode.empty()) mode = parse_motion_mode(o.motion_mode, "--motion-mode");
  if (o.json && o.csv) throw Error("give --json or --csv, not both", {}, 0, "--csv");
  if (!o.out.empty()) {
    std::error_code ec;
    if (fs::exists(o.out, ec) && !fs::is_directory(o.out, ec)) throw Error("exists and is not a folder", o.out, 0, "--out");
    if (!o.force && (fs::exists(fs::path(o.out) / "summary.json", ec) || fs::exists(fs::path(o.out) / "runs.csv", ec)))
      throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
  }

  std::vector<ScenarioOverride> overrides;
  for (const std::string& text : o.sets) overrides.push_back(parse_scenario_override(text));
  const ScenarioSpec loaded = load_scenario(o.scenario, overrides);
  if (!loaded.navigation)
    throw Error("not a navigation scenario (no navigation section; see docs/scenarios.md)", o.scenario, 0, "navigation");
  if (mode) (void)resolve_motion_mode(*mode, loaded.vehicle.robot.drive, "--motion-mode");

  std::vector<RunRecord> records;
  records.reserve(static_cast<std::size_t>(2 * n));
  ProgressBar progress("bench nav", static_cast<std::size_t>(2 * n), o.quiet);
  std::size_t done = 0;
  try {
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::uint64_t seed = base + i;
      for (const char* planner : kNavPlanners) {
        ScenarioSpec spec = loaded;
        spec.seed = seed;
        NavigationOptions options;
        if (!o.motion_mode.empty()) options.motion_mode = o.motion_mode;
        options.planner = planner;
        options.compare_astar = planner == kNavPlanners[0];
        options.record_steps = false;
        RunRecord r;
        r.seed = seed;
        r.planner = planner;
        // Construction errors are the scenario's (or the flags'): exit 2 through main.
        NavigationRun run(spec, options);
        progress.update(done, "seed " + std::to_string(seed) + " " + planner);
        try {
          run.run();
          r.m = run.metrics();
          r.completed = true;
          r.wall_s = run.wall_s();
          r.real_time_factor = r.wall_s > 0.0 ? r.m.duration_s / r.wall_s : 0.0;
        } catch (const std::bad_alloc&) {
          throw;
        } catch (const std::exception& e) {
          r.completed = false;
          r.error = one_line(e.what());
        }
        records.push_back(std::move(r));
        ++done;
      }
    }
  } catch (...) {
    progress.finish();
    throw;
  }
  progress.update(done, "done");
  progress.finish();

  std::vector<NavSummary> sums;
  for (const char* planner : kNavPlanners) sums.push_back(summarise(records, planner));

  json doc;
  doc["benchmark"] = "nav";
  doc["scenario"] = o.scenario;
  doc["name"] = loaded.name;
  doc["seeds"] = n;
  doc["seed_base"] = base;
  doc["seed_last"] = base + n - 1;
  doc["motion_mode"] = o.motion_mode.empty() ? json(nullptr) : json(o.motion_mode);
  doc["wall_clock_fields"] = "wall_s, real_time_factor and every \"wall_clock\" object; everything else is deterministic";
  json planners = json::array();
  for (std::size_t p = 0; p < sums.size(); ++p) planners.push_back(summary_json(sums[p], p == 0));
  doc["planners"] = planners;
  json runs = json::array();
  for (const RunRecord& r : records) runs.push_back(run_json(r));
  doc["runs"] = runs;

  const std::string csv = runs_csv(records);
  if (o.json) std::cout << doc.dump(2) << "\n";
  else if (o.csv) std::cout << csv;
  else print_table(std::cout, loaded, o, base, n, sums);
  std::cout.flush();

  if (!o.out.empty()) {
    std::error_code ec;
    fs::create_directories(o.out, ec);
    if (ec) throw Error("cannot create the folder: " + ec.message(), o.out, 0, "--out");
    write_file(fs::path(o.out) / "runs.csv", csv);
    write_file(fs::path(o.out) / "summary.json", doc.dump(2) + "\n");
    if (!o.quiet) std::cerr << "bench nav: wrote " << o.out << "/runs.csv, summary.json\n";
  }

  std::size_t failed = 0;
  const RunRecord* first = nullptr;
  for (const RunRecord& r : records)
    if (!r.completed) {
      ++failed;
      if (!first) first = &r;
    }
  if (failed) {
    std::cerr << "starnav: error: " << o.scenario << ": " << failed << " of " << records.size()
              << " runs failed (first: seed " << first->seed << ", " << first->planner << ": " << first->error << ")\n";
    ctx.exit_code = 1;
    return;
  }
  ctx.exit_code = 0;
}

}  // namespace

void register_bench_nav(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<NavBenchOptions>();
  auto* cmd = bench->add_subcommand(
      "nav",
      "a navigation scenario over seeds B..B+N-1: success rate and the distributions of time to goal, distance,\n"
      "replans, expansions and deviation, for the robot following D* Lite (A* from scratch compared at every plan,\n"
      "on the same map and start) and for A* from scratch at every plan (the paper). Exit 0 when every run\n"
      "completed (not reaching the goal is a result), 1 when a run failed, 2 for bad flags or scenarios.");
  cmd->add_option("--scenario", o->scenario, "a navigation scenario (.yaml with a navigation section)");
  cmd->add_option("--seeds", o->seeds, "number of seeds N (at least 1)");
  cmd->add_option("--seed-base", o->seed_base, "first seed B (default 0): seeds B..B+N-1 replace sim.seed");
  cmd->add_option("--motion-mode", o->motion_mode, "auto | turn_then_drive | holonomic | pure_pursuit (overrides the scenario)");
  cmd->add_option("--set", o->sets,
                  "KEY=VALUE: set any scenario key before it is read, e.g. navigation.follower.cruise_speed_mps=0.3 (repeatable)");
  cmd->add_option("--out", o->out, "directory for runs.csv and summary.json (created)");
  cmd->add_flag("--json", o->json, "print one JSON document (the summary.json of --out)");
  cmd->add_flag("--csv", o->csv, "print one CSV row per seed and planner (the runs.csv of --out)");
  cmd->add_flag("--force", o->force, "overwrite runs.csv and summary.json in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_nav(*o, ctx); });
}

}  // namespace starnav::cli
