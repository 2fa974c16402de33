#include "starnav/experiment/movingai_experiment.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The exactness rule (docs/benchmarks.md): published lengths carry up to 0.005 of rounding.
double exact_tolerance(double optimal) { return std::max(0.01, 1e-5 * optimal); }

// One summary object; `map` names the map of a per-map row (and drops the map count).
nlohmann::ordered_json tally_json(const MovingAiTally& t, const std::string* map = nullptr) {
  double total_us = 0.0;
  for (const double x : t.instance_time_us) total_us += x;
  nlohmann::ordered_json j;
  if (map) j["map"] = *map;
  j["planner"] = t.planner;
  j["admissible"] = t.admissible;
  if (!map) j["maps"] = t.maps;
  j["instances"] = t.instances;
  j["unsolvable"] = t.unsolvable;
  j["solved"] = t.solved;
  j["exact"] = t.exact;
  j["shorter"] = t.shorter;
  j["max_abs_error"] = t.max_abs_error;
  j["max_suboptimality"] = t.max_suboptimality;
  j["mean_suboptimality"] = t.suboptimality_count ? t.sum_suboptimality / static_cast<double>(t.suboptimality_count) : 0.0;
  j["median_time_us"] = sample_stats(t.instance_time_us).median;
  j["mean_time_us"] = t.instance_time_us.empty() ? 0.0 : total_us / static_cast<double>(t.instance_time_us.size());
  j["total_time_ms"] = total_us / 1000.0;
  j["total_expanded"] = t.expanded;
  j["total_generated"] = t.generated;
  j["expansions_per_s"] = total_us > 0 ? static_cast<double>(t.expanded) / (total_us * 1e-6) : 0.0;
  j["preprocess_ms"] = t.preprocess_ms;
  return j;
}

void print_table(std::ostream& out, const std::vector<nlohmann::ordered_json>& rows, bool with_map) {
  struct Col {
    const char* title;
    int width;
  };
  std::vector<Col> cols;
  if (with_map) cols.push_back({"map", 28});
  const Col rest[] = {{"planner", 10},    {"instances", 10}, {"solved", 8},      {"exact", 8},
                      {"max_abs_err", 12}, {"max_subopt", 11}, {"median_us", 11},  {"mean_us", 11},
                      {"expanded", 13},    {"Mexp/s", 8},      {"preprocess_ms", 14}};
  cols.insert(cols.end(), std::begin(rest), std::end(rest));
  for (const Col& c : cols) out << std::left << std::setw(c.width) << c.title;
  out << "\n";
  for (const auto& r : rows) {
    std::size_t k = 0;
    auto cell = [&](const std::string& s) { out << std::left << std::setw(cols[k++].width) << s; };
    if (with_map) cell(r["map"].get<std::string>());
    cell(r["planner"].get<std::string>());
    cell(std::to_string(r["instances"].get<std::size_t>()));
    cell(std::to_string(r["solved"].get<std::size_t>()));
    cell(std::to_string(r["exact"].get<std::size_t>()));
    cell(format_fixed(r["max_abs_error"].get<double>(), 4));
    cell(format_fixed(r["max_suboptimality"].get<double>(), 4));
    cell(format_fixed(r["median_time_us"].get<double>(), 1));
    cell(format_fixed(r["mean_time_us"].get<double>(), 1));
    cell(std::to_string(r["total_expanded"].get<std::uint64_t>()));
    cell(format_fixed(r["expansions_per_s"].get<double>() / 1e6, 2));
    cell(format_fixed(r["preprocess_ms"].get<double>(), 1));
    out << "\n";
  }
}

}  // namespace

std::vector<MovingAiPair> find_movingai_pairs(const std::string& dir) {
  std::vector<MovingAiPair> pairs;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("not a folder", dir, 0, "--dir");
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::follow_directory_symlink, ec), end; it != end;
       it.increment(ec)) {
    if (ec) throw Error("cannot list the folder: " + ec.message(), dir, 0, "--dir");
    const fs::path p = it->path();
    if (p.extension() != ".map" || !it->is_regular_file(ec)) continue;
    const fs::path scen = fs::path(p.string() + ".scen");
    if (!fs::is_regular_file(scen, ec)) continue;
    // Lexically (not fs::relative, which follows symbolic links out of the folder).
    fs::path rel = p.lexically_normal().lexically_relative(fs::path(dir).lexically_normal());
    if (rel.empty() || *rel.begin() == "..") rel = p.filename();
    rel.replace_extension();
    pairs.push_back({rel.generic_string(), p.string(), scen.string()});
  }
  if (ec) throw Error("cannot list the folder: " + ec.message(), dir, 0, "--dir");
  std::sort(pairs.begin(), pairs.end(), [](const MovingAiPair& a, const MovingAiPair& b) { return a.name < b.name; });
  if (pairs.empty()) throw Error("no FILE.map with a FILE.map.scen beside it under this folder", dir, 0, "--dir");
  return pairs;
}

std::vector<std::size_t> select_instances(std::size_t total, std::size_t limit) {
  std::vector<std::size_t> idx;
  if (limit == 0 || limit >= total) {
    idx.resize(total);
    for (std::size_t i = 0; i < total; ++i) idx[i] = i;
    return idx;
  }
  idx.reserve(limit);
  for (std::size_t i = 0; i < limit; ++i) idx.push_back(i * total / limit);
  return idx;
}

std::vector<std::string> movingai_planners(const std::vector<std::string>& requested, std::vector<std::string>* warnings) {
  // Names are the registry's, as `plan` and scenarios read them: an old spelling works with a
  // warning and runs under its current name.
  std::vector<std::string> planners;
  for (const std::string& p : requested.empty() ? std::vector<std::string>{"astar", "jps", "jpsplus"} : requested) {
    std::string warning;
    const GlobalPlannerDef& def = find_global_planner(p, "--planner", &warning);
    if (!def.info.has(Capability::Occupancy))
      throw Error("'" + def.info.name + "' plans on elevation maps; MovingAI maps are occupancy grids", {}, 0, "--planner");
    if (def.info.has(Capability::NeedsHeadings))
      throw Error("'" + def.info.name + "' plans between poses; MovingAI scenarios give cells", {}, 0, "--planner");
    if (!warning.empty() && warnings) warnings->push_back(warning);
    if (std::find(planners.begin(), planners.end(), def.info.name) == planners.end()) planners.push_back(def.info.name);
  }
  return planners;
}

MovingAiResult run_movingai_experiment(const MovingAiConfig& config) {
  const int repeat = config.repeat;
  if (repeat < 1) throw Error("must be at least 1, got " + std::to_string(repeat), {}, 0, "--repeat");
  MovingAiResult result;
  result.config = config;
  const std::vector<std::string> planners = movingai_planners(config.planners);
  result.config.planners = planners;
  std::ostringstream csv;
  if (config.csv_rows) {
    csv << "map,problem,bucket,start_x,start_y,goal_x,goal_y,optimal,planner,status,found,cost,abs_error,"
           "suboptimality,exact,expanded,generated,time_us\n";
    csv << std::setprecision(10);
  }

  ExperimentGrid grid;
  for (const MovingAiPair& p : config.pairs) grid.instances.push_back(p.name);
  for (const std::string& p : planners) grid.variants.push_back({p, {{"planner", p}}});
  grid.seeds = {0};  // deterministic planners: one run per map and planner

  // The map of the current instance, loaded once for all its planners.
  struct Loaded {
    std::size_t index = static_cast<std::size_t>(-1);
    MovingAiMap map;
    MovingAiScenario scen;
    OccupancyGrid grid;
    std::vector<std::size_t> chosen;
    Clock::time_point t0;
  } loaded;
  result.totals.resize(planners.size());
  const auto finish_map = [&] {
    if (loaded.index == static_cast<std::size_t>(-1) || !config.on_map_done) return;
    config.on_map_done(loaded.index, config.pairs[loaded.index].name, loaded.chosen.size(),
                       std::chrono::duration<double>(Clock::now() - loaded.t0).count());
  };
  struct Setup {
    std::unique_ptr<GridPlanner> planner;
  };
  const auto prepare = [&](const TrialKey& key) {
    if (key.instance != loaded.index) {
      finish_map();
      const MovingAiPair& pair = config.pairs[key.instance];
      loaded.t0 = Clock::now();
      loaded.index = key.instance;
      loaded.map = read_movingai_map(pair.map_path);
      loaded.scen = read_movingai_scenario(pair.scen_path);
      loaded.grid = loaded.map.to_occupancy();
      check_scenario_map_size(loaded.scen, pair.scen_path, loaded.map.width, loaded.map.height, pair.map_path);
      loaded.chosen = select_instances(loaded.scen.entries.size(), config.limit);
      result.total_instances += loaded.chosen.size();
    }
    return Setup{make_grid_planner(planners[key.variant], loaded.grid, GridPlannerOptions{})};
  };
  const auto run = [&](Setup& setup, const TrialKey& key) {
    const MovingAiPair& pair = config.pairs[key.instance];
    const std::size_t mi = key.instance, pi = key.variant;
    GridPlanner* planner = setup.planner.get();
    const MovingAiScenario& scen = loaded.scen;
    const std::vector<std::size_t>& chosen = loaded.chosen;
    MovingAiTally t;
    t.planner = planners[pi];
    t.admissible = planner->admissible();
    t.maps = 1;
    t.preprocess_ms = planner->preprocess_ms();
    const std::size_t n = chosen.size();
    std::vector<PlanResult> first(n);
    std::vector<std::vector<double>> times(n);
    // Warm-up (sizes the search memory and open list, untimed).
    if (n > 0) {
      const ScenarioEntry& e = scen.entries[chosen[n - 1]];
      (void)planner->plan({e.start_x, e.start_y}, {e.goal_x, e.goal_y});
    }
    const std::size_t steps = n * static_cast<std::size_t>(repeat);
    std::size_t done = 0;
    for (int r = 0; r < repeat; ++r)
      for (std::size_t i = 0; i < n; ++i, ++done) {
        const ScenarioEntry& e = scen.entries[chosen[i]];
        PlanResult res = planner->plan({e.start_x, e.start_y}, {e.goal_x, e.goal_y});
        times[i].push_back(res.time_ms * 1000.0);
        if (r == 0) {
          res.path_world.clear();
          res.path_world.shrink_to_fit();
          res.path_cells.clear();
          res.path_cells.shrink_to_fit();
          first[i] = std::move(res);
        }
        if ((done & 15u) == 0 && config.on_queries) config.on_queries(mi, pair.name, pi, planners[pi], done, steps);
      }
    if (config.on_queries) config.on_queries(mi, pair.name, pi, planners[pi], steps, steps);

    for (std::size_t i = 0; i < n; ++i) {
      const ScenarioEntry& e = scen.entries[chosen[i]];
      const PlanResult& res = first[i];
      const bool unsolvable = e.unsolvable();
      const double time_us = sample_stats(times[i]).median;
      bool exact = false;
      double abs_error = 0.0, subopt = 0.0;
      ++t.instances;
      if (unsolvable) ++t.unsolvable;
      if (res.found()) ++t.solved;
      if (unsolvable) {
        exact = res.status == PlanStatus::NoPath;
      } else if (res.found()) {
        abs_error = std::abs(res.cost - e.optimal_length);
        exact = abs_error <= exact_tolerance(e.optimal_length);
        if (!exact && res.cost < e.optimal_length) ++t.shorter;
        t.max_abs_error = std::max(t.max_abs_error, abs_error);
        if (e.optimal_length > 0) {
          subopt = std::max(0.0, (res.cost - e.optimal_length) / e.optimal_length);
          t.max_suboptimality = std::max(t.max_suboptimality, subopt);
          t.sum_suboptimality += subopt;
          ++t.suboptimality_count;
        }
      }
      if (exact) ++t.exact;
      t.instance_time_us.push_back(time_us);
      t.expanded += res.expanded;
      t.generated += res.generated;
      if (config.csv_rows) {
        csv << csv_field(pair.name) << ',' << chosen[i] + 1 << ',' << e.bucket << ',' << e.start_x << ',' << e.start_y << ','
            << e.goal_x << ',' << e.goal_y << ',' << e.optimal_length << ',' << planners[pi] << ','
            << plan_status_reason(res.status) << ',' << (res.found() ? 1 : 0) << ',' << res.cost << ','
            << abs_error << ',' << subopt << ',' << (exact ? 1 : 0) << ',' << res.expanded << ','
            << res.generated << ',' << time_us << '\n';
      }
    }
    return t;
  };
  const auto trials = run_experiment<Setup, MovingAiTally>(grid, prepare, run);
  finish_map();
  for (const Trial<MovingAiTally>& tr : trials) {
    // A failed query is a bug of the planner, not a result: say so.
    if (!tr.completed) throw Error(tr.error, config.pairs[tr.key.instance].map_path, 0, planners[tr.key.variant]);
    result.per_map.push_back(tr.record);
    result.per_map_names.push_back(config.pairs[tr.key.instance].name);
    MovingAiTally& total = result.totals[tr.key.variant];
    total.planner = tr.record.planner;
    total.admissible = tr.record.admissible;
    total.merge(tr.record);
  }
  result.csv = csv.str();
  return result;
}

int movingai_exit_code(const MovingAiResult& result) {
  // Exit 1 when an admissible planner missed an optimal answer (a bug worth failing CI on).
  for (const MovingAiTally& t : result.totals)
    if (t.admissible && t.exact != t.instances) return 1;
  return 0;
}

std::string movingai_json(const MovingAiResult& result) {
  std::vector<nlohmann::ordered_json> summary, per_map;
  for (const MovingAiTally& t : result.totals) summary.push_back(tally_json(t));
  for (std::size_t i = 0; i < result.per_map.size(); ++i) per_map.push_back(tally_json(result.per_map[i], &result.per_map_names[i]));
  nlohmann::ordered_json j;
  j["benchmark"] = "movingai";
  j["maps"] = result.config.pairs.size();
  j["instances"] = result.total_instances;
  j["repeat"] = result.config.repeat;
  j["limit"] = result.config.limit;
  j["exact_rule"] = "|cost - optimal| <= max(0.01, 1e-5 * optimal); length-0 lines with start != goal: no path";
  j["planners"] = summary;
  j["per_map"] = per_map;
  return j.dump(2) + "\n";
}

std::string movingai_report(const MovingAiResult& result, bool with_per_map) {
  std::vector<nlohmann::ordered_json> summary, per_map;
  for (const MovingAiTally& t : result.totals) summary.push_back(tally_json(t));
  for (std::size_t i = 0; i < result.per_map.size(); ++i) per_map.push_back(tally_json(result.per_map[i], &result.per_map_names[i]));
  std::ostringstream out;
  const std::size_t maps = result.config.pairs.size();
  out << "MovingAI benchmark: " << maps << (maps == 1 ? " map, " : " maps, ") << result.total_instances
      << " instances, repeat " << result.config.repeat
      << " (times: median over instances of each instance's median over repeats)\n";
  print_table(out, summary, false);
  if (with_per_map) {
    out << "\nper map:\n";
    print_table(out, per_map, true);
  }
  for (const MovingAiTally& t : result.totals) {
    if (t.exact == t.instances) continue;
    const std::size_t off = t.instances - t.exact;
    if (t.admissible)
      out << "NOT EXACT: " << t.planner << " answered " << off << " of " << t.instances << " problems inexactly\n";
    else
      out << t.planner << " (not admissible): " << off << " of " << t.instances
          << " answers differ from the 8-connected optimum (" << t.shorter
          << " shorter, e.g. any-angle paths; max suboptimality " << format_fixed(t.max_suboptimality, 4) << ")\n";
  }
  return out.str();
}

}  // namespace starnav
