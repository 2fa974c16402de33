// starnav bench movingai: grid planners on the MovingAI benchmarks (Sturtevant 2012), checked
// against the scenario files' optimal lengths and timed. `bench` is a command group; later
// benchmarks (ablation, terrain, nav) register beside `movingai`.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/plan/grid_planner.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct MovingAiBenchOptions {
  std::string map;
  std::string scen;
  std::string dir;
  std::vector<std::string> planners;
  std::size_t limit = 0;
  int repeat = 1;
  bool json = false;
  std::string csv;
  bool force = false;
  bool per_map = false;
  bool quiet = false;
};

struct BenchPair {
  std::string name;  // "dao/den520d" under --dir, the map's stem otherwise
  std::string map_path;
  std::string scen_path;
};

// The exactness rule (docs/benchmarks.md): published lengths carry up to 0.005 of rounding.
double exact_tolerance(double optimal) { return std::max(0.01, 1e-5 * optimal); }

// Everything a summary needs, for one planner on one map or on all of them.
struct Tally {
  std::string planner;
  bool admissible = true;
  int maps = 0;
  std::size_t instances = 0;
  std::size_t unsolvable = 0;  // length-0 lines with start != goal
  std::size_t solved = 0;      // a path was returned
  std::size_t exact = 0;
  std::size_t shorter = 0;  // cost below the 8-connected optimum by more than the tolerance (any-angle)
  double max_abs_error = 0.0;
  double max_suboptimality = 0.0;
  double sum_suboptimality = 0.0;
  std::size_t suboptimality_count = 0;
  std::vector<double> instance_time_us;  // each instance's median over repeats
  std::uint64_t expanded = 0;
  std::uint64_t generated = 0;
  double preprocess_ms = 0.0;

  void merge(const Tally& o) {
    maps += o.maps;
    instances += o.instances;
    unsolvable += o.unsolvable;
    solved += o.solved;
    exact += o.exact;
    shorter += o.shorter;
    max_abs_error = std::max(max_abs_error, o.max_abs_error);
    max_suboptimality = std::max(max_suboptimality, o.max_suboptimality);
    sum_suboptimality += o.sum_suboptimality;
    suboptimality_count += o.suboptimality_count;
    instance_time_us.insert(instance_time_us.end(), o.instance_time_us.begin(), o.instance_time_us.end());
    expanded += o.expanded;
    generated += o.generated;
    preprocess_ms += o.preprocess_ms;
  }

  // One summary object; `map` names the map of a per-map row (and drops the map count).
  nlohmann::ordered_json to_json(const std::string* map = nullptr) const {
    double total_us = 0.0;
    for (double t : instance_time_us) total_us += t;
    nlohmann::ordered_json j;
    if (map) j["map"] = *map;
    j["planner"] = planner;
    j["admissible"] = admissible;
    if (!map) j["maps"] = maps;
    j["instances"] = instances;
    j["unsolvable"] = unsolvable;
    j["solved"] = solved;
    j["exact"] = exact;
    j["shorter"] = shorter;
    j["max_abs_error"] = max_abs_error;
    j["max_suboptimality"] = max_suboptimality;
    j["mean_suboptimality"] = suboptimality_count ? sum_suboptimality / static_cast<double>(suboptimality_count) : 0.0;
    j["median_time_us"] = sample_stats(instance_time_us).median;
    j["mean_time_us"] = instance_time_us.empty() ? 0.0 : total_us / static_cast<double>(instance_time_us.size());
    j["total_time_ms"] = total_us / 1000.0;
    j["total_expanded"] = expanded;
    j["total_generated"] = generated;
    j["expansions_per_s"] = total_us > 0 ? static_cast<double>(expanded) / (total_us * 1e-6) : 0.0;
    j["preprocess_ms"] = preprocess_ms;
    return j;
  }
};

// The progress display on stderr: a live bar when stderr is a terminal, otherwise one line per
// finished map (readable in CI logs), nothing with --quiet.
class Progress {
 public:
  Progress(bool quiet, std::size_t maps, std::size_t planners)
      : enabled_(!quiet), tty_(!quiet && ::isatty(2) == 1), maps_(maps), planners_(planners) {}

  void update(std::size_t map_index, const std::string& map, std::size_t planner_index, const std::string& planner,
              std::size_t done, std::size_t total) {
    if (!tty_) return;
    const auto now = Clock::now();
    if (done != 0 && done != total && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double map_frac = total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
    const double frac = (static_cast<double>(map_index) +
                         (static_cast<double>(planner_index) + map_frac) / static_cast<double>(planners_)) /
                        static_cast<double>(maps_);
    constexpr int kWidth = 24;
    const int filled = std::clamp(static_cast<int>(frac * kWidth), 0, kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.append(static_cast<std::size_t>(kWidth - filled), '.');
    std::string line = "[" + bar + "] " + std::to_string(map_index + 1) + "/" + std::to_string(maps_) + " " + map +
                       " " + planner + " " + std::to_string(done) + "/" + std::to_string(total);
    if (line.size() > 79) line.resize(79);  // one line of an 80-column terminal
    std::fprintf(stderr, "\r%-79s", line.c_str());
    std::fflush(stderr);
  }

  void map_done(std::size_t map_index, const std::string& map, std::size_t instances, double seconds) {
    if (!enabled_ || tty_) return;
    std::fprintf(stderr, "bench movingai: [%zu/%zu] %s: %zu instances x %zu planners, %.1f s\n", map_index + 1, maps_,
                 map.c_str(), instances, planners_, seconds);
  }

  void finish() {
    if (tty_) std::fprintf(stderr, "\r%-79s\r", "");
  }

 private:
  bool enabled_;
  bool tty_;
  std::size_t maps_;
  std::size_t planners_;
  Clock::time_point last_{};
};

std::vector<BenchPair> find_pairs(const MovingAiBenchOptions& o) {
  std::vector<BenchPair> pairs;
  if (!o.dir.empty()) {
    if (!o.map.empty() || !o.scen.empty())
      throw Error("give either --dir or --map with --scen, not both", {}, 0, "--dir");
    std::error_code ec;
    if (!fs::is_directory(o.dir, ec)) throw Error("not a folder", o.dir, 0, "--dir");
    for (fs::recursive_directory_iterator it(o.dir, fs::directory_options::follow_directory_symlink, ec), end;
         it != end; it.increment(ec)) {
      if (ec) throw Error("cannot list the folder: " + ec.message(), o.dir, 0, "--dir");
      const fs::path p = it->path();
      if (p.extension() != ".map" || !it->is_regular_file(ec)) continue;
      const fs::path scen = fs::path(p.string() + ".scen");
      if (!fs::is_regular_file(scen, ec)) continue;
      // Lexically (not fs::relative, which follows symbolic links out of the folder).
      fs::path rel = p.lexically_normal().lexically_relative(fs::path(o.dir).lexically_normal());
      if (rel.empty() || *rel.begin() == "..") rel = p.filename();
      rel.replace_extension();
      pairs.push_back({rel.generic_string(), p.string(), scen.string()});
    }
    if (ec) throw Error("cannot list the folder: " + ec.message(), o.dir, 0, "--dir");
    std::sort(pairs.begin(), pairs.end(), [](const BenchPair& a, const BenchPair& b) { return a.name < b.name; });
    if (pairs.empty()) throw Error("no FILE.map with a FILE.map.scen beside it under this folder", o.dir, 0, "--dir");
    return pairs;
  }
  if (o.map.empty() || o.scen.empty())
    throw Error("give --map FILE.map and --scen FILE.scen, or --dir DIR", {}, 0, o.map.empty() ? "--map" : "--scen");
  pairs.push_back({fs::path(o.map).stem().string(), o.map, o.scen});
  return pairs;
}

// Problem indices to run: all, or --limit N spread evenly over the file (every bucket is
// represented, unlike the first N lines which are the shortest problems).
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

std::string format_number(double v, int precision) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

// A CSV field, quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& v) {
  if (v.find_first_of(",\"\r\n") == std::string::npos) return v;
  std::string q = "\"";
  for (char c : v) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
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
    cell(format_number(r["max_abs_error"].get<double>(), 4));
    cell(format_number(r["max_suboptimality"].get<double>(), 4));
    cell(format_number(r["median_time_us"].get<double>(), 1));
    cell(format_number(r["mean_time_us"].get<double>(), 1));
    cell(std::to_string(r["total_expanded"].get<std::uint64_t>()));
    cell(format_number(r["expansions_per_s"].get<double>() / 1e6, 2));
    cell(format_number(r["preprocess_ms"].get<double>(), 1));
    out << "\n";
  }
}

int run_bench_movingai(const MovingAiBenchOptions& o) {
  if (o.repeat < 1) throw Error("must be at least 1, got " + std::to_string(o.repeat), {}, 0, "--repeat");
  std::vector<std::string> planners;
  for (const std::string& p : o.planners.empty() ? std::vector<std::string>{"astar", "jps", "jpsplus"} : o.planners)
    if (std::find(planners.begin(), planners.end(), p) == planners.end()) planners.push_back(p);
  const std::vector<std::string> known = grid_planner_names();
  for (const std::string& p : planners)
    if (std::find(known.begin(), known.end(), p) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw Error("unknown planner '" + p + "' (" + list + ")", {}, 0, "--planner");
    }
  const std::vector<BenchPair> pairs = find_pairs(o);
  std::unique_ptr<std::ofstream> csv;
  if (!o.csv.empty()) {
    check_output_path(o.csv, o.force, "--csv");
    csv = std::make_unique<std::ofstream>(o.csv, std::ios::binary | std::ios::trunc);
    if (!*csv) throw Error("cannot open for writing", o.csv, 0, "--csv");
    *csv << "map,problem,bucket,start_x,start_y,goal_x,goal_y,optimal,planner,status,found,cost,abs_error,"
            "suboptimality,exact,expanded,generated,time_us\n";
    *csv << std::setprecision(10);
  }

  std::vector<Tally> totals(planners.size());
  std::vector<nlohmann::ordered_json> per_map;
  Progress progress(o.quiet, pairs.size(), planners.size());
  std::size_t total_instances = 0;

  for (std::size_t mi = 0; mi < pairs.size(); ++mi) {
    const BenchPair& pair = pairs[mi];
    const auto map_t0 = Clock::now();
    const MovingAiMap mai = read_movingai_map(pair.map_path);
    const MovingAiScenario scen = read_movingai_scenario(pair.scen_path);
    const OccupancyGrid grid = mai.to_occupancy();
    for (std::size_t k = 0; k < scen.entries.size(); ++k) {
      const ScenarioEntry& e = scen.entries[k];
      if (e.map_width != mai.width || e.map_height != mai.height)
        throw Error("problem " + std::to_string(k + 1) + " is for a " + std::to_string(e.map_width) + " x " +
                        std::to_string(e.map_height) + " map, but " + pair.map_path + " is " +
                        std::to_string(mai.width) + " x " + std::to_string(mai.height),
                    pair.scen_path, 0, "width/height");
    }
    const std::vector<std::size_t> chosen = select_instances(scen.entries.size(), o.limit);
    total_instances += chosen.size();

    for (std::size_t pi = 0; pi < planners.size(); ++pi) {
      std::unique_ptr<GridPlanner> planner = make_grid_planner(planners[pi], grid, GridPlannerOptions{});
      Tally t;
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
      const std::size_t steps = n * static_cast<std::size_t>(o.repeat);
      std::size_t done = 0;
      for (int r = 0; r < o.repeat; ++r)
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
          if ((done & 15u) == 0) progress.update(mi, pair.name, pi, planners[pi], done, steps);
        }
      progress.update(mi, pair.name, pi, planners[pi], steps, steps);

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
        if (csv) {
          *csv << csv_field(pair.name) << ',' << chosen[i] + 1 << ',' << e.bucket << ',' << e.start_x << ',' << e.start_y << ','
               << e.goal_x << ',' << e.goal_y << ',' << e.optimal_length << ',' << planners[pi] << ','
               << plan_status_reason(res.status) << ',' << (res.found() ? 1 : 0) << ',' << res.cost << ','
               << abs_error << ',' << subopt << ',' << (exact ? 1 : 0) << ',' << res.expanded << ','
               << res.generated << ',' << time_us << '\n';
        }
      }
      per_map.push_back(t.to_json(&pair.name));
      totals[pi].planner = t.planner;
      totals[pi].admissible = t.admissible;
      totals[pi].merge(t);
    }
    progress.map_done(mi, pair.name, chosen.size(),
                      std::chrono::duration<double>(Clock::now() - map_t0).count());
  }
  progress.finish();
  if (csv) {
    csv->flush();
    if (!*csv) throw Error("write failed", o.csv, 0, "--csv");
  }

  // Exit 1 when an admissible planner missed an optimal answer (a bug worth failing CI on).
  int code = 0;
  for (const Tally& t : totals)
    if (t.admissible && t.exact != t.instances) code = 1;

  std::vector<nlohmann::ordered_json> summary;
  for (const Tally& t : totals) summary.push_back(t.to_json());
  if (o.json) {
    nlohmann::ordered_json j;
    j["benchmark"] = "movingai";
    j["maps"] = pairs.size();
    j["instances"] = total_instances;
    j["repeat"] = o.repeat;
    j["limit"] = o.limit;
    j["exact_rule"] = "|cost - optimal| <= max(0.01, 1e-5 * optimal); length-0 lines with start != goal: no path";
    j["planners"] = summary;
    j["per_map"] = per_map;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "MovingAI benchmark: " << pairs.size() << (pairs.size() == 1 ? " map, " : " maps, ")
              << total_instances << " instances, repeat " << o.repeat
              << " (times: median over instances of each instance's median over repeats)\n";
    print_table(std::cout, summary, false);
    if (o.per_map) {
      std::cout << "\nper map:\n";
      print_table(std::cout, per_map, true);
    }
    for (const Tally& t : totals) {
      if (t.exact == t.instances) continue;
      const std::size_t off = t.instances - t.exact;
      if (t.admissible)
        std::cout << "NOT EXACT: " << t.planner << " answered " << off << " of " << t.instances
                  << " problems inexactly\n";
      else
        std::cout << t.planner << " (not admissible): " << off << " of " << t.instances
                  << " answers differ from the 8-connected optimum (" << t.shorter
                  << " shorter, e.g. any-angle paths; max suboptimality " << format_number(t.max_suboptimality, 4)
                  << ")\n";
    }
  }
  return code;
}

}  // namespace

void register_bench_commands(CLI::App& app, Context& ctx) {
  auto* bench = app.add_subcommand("bench", "benchmarks and reproductions");
  bench->require_subcommand(1);

  auto opts = std::make_shared<MovingAiBenchOptions>();
  auto* mai = bench->add_subcommand(
      "movingai",
      "grid planners on MovingAI benchmark maps: exactness against the .scen optimal lengths and search times.\n"
      "An answer is exact when |cost - optimal| <= max(0.01, 1e-5 * optimal); a length-0 line whose start\n"
      "differs from its goal is unsolvable and 'no path' is its exact answer. Times exclude per-map\n"
      "preprocessing (reported as preprocess_ms). Exit 1 when an admissible planner is not exact.");
  mai->add_option("--map", opts->map, "a MovingAI .map file (with --scen)");
  mai->add_option("--scen", opts->scen, "its .scen file");
  mai->add_option("--dir", opts->dir, "every FILE.map with a FILE.map.scen under DIR, recursively");
  mai->add_option("--planner", opts->planners, "planner to run (repeatable; default astar, jps, jpsplus)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  mai->add_option("--limit", opts->limit, "at most N problems per scenario file, spread evenly over it (0 = all)");
  mai->add_option("--repeat", opts->repeat, "run every problem R times; its time is the median (default 1)");
  mai->add_flag("--json", opts->json, "print one JSON object {\"planners\": [...], \"per_map\": [...]}");
  mai->add_option("--csv", opts->csv, "write one row per problem and planner to FILE");
  mai->add_flag("--force", opts->force, "overwrite the --csv file if it exists");
  mai->add_flag("--per-map", opts->per_map, "also print a table per map");
  mai->add_flag("--quiet", opts->quiet, "no progress on stderr");
  mai->callback([opts, &ctx] { ctx.exit_code = run_bench_movingai(*opts); });
  register_bench_terrain(app, ctx);  // Liu 2024 (cmd_bench_terrain.cpp)
  register_bench_nav(app, ctx);      // Li 2019 navigation over seeds (cmd_bench_nav.cpp)
}

}  // namespace starnav::cli
