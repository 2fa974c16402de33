// starnav bench movingai: grid planners on the MovingAI benchmarks (Sturtevant 2012), checked
// against the scenario files' optimal lengths and timed. `bench` is a command group; later
// benchmarks (ablation, terrain, nav) register beside `movingai`.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/run_limits.hpp"
#include "starnav/experiment/movingai_experiment.hpp"

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

std::vector<MovingAiPair> find_pairs(const MovingAiBenchOptions& o) {
  if (!o.dir.empty()) {
    if (!o.map.empty() || !o.scen.empty())
      throw Error("give either --dir or --map with --scen, not both", {}, 0, "--dir");
    return find_movingai_pairs(o.dir);
  }
  if (o.map.empty() || o.scen.empty())
    throw Error("give --map FILE.map and --scen FILE.scen, or --dir DIR", {}, 0, o.map.empty() ? "--map" : "--scen");
  return {{fs::path(o.map).stem().string(), o.map, o.scen}};
}

int run_bench_movingai(const MovingAiBenchOptions& o) {
  // Every repeat runs the whole scenario file again: 1,000 is already hours on a large map.
  if (o.repeat < 1 || o.repeat > kMaxRepeats) throw Error("must be 1.." + std::to_string(kMaxRepeats) + ", got " + std::to_string(o.repeat), {}, 0, "--repeat");
  MovingAiConfig config;
  std::vector<std::string> warnings;
  config.planners = movingai_planners(o.planners, &warnings);  // an unknown name fails before any map is read
  for (const std::string& w : warnings) print_warning("--planner: " + w);
  config.limit = o.limit;
  config.repeat = o.repeat;
  config.pairs = find_pairs(o);
  if (!o.csv.empty()) {
    check_output_path(o.csv, o.force, "--csv");
    std::vector<CommandFile> files;
    for (const auto& pair : config.pairs) {
      files.push_back({pair.map_path, "--map", false});
      files.push_back({pair.scen_path, "--scen", false});
    }
    files.push_back({o.csv, "--csv"});
    check_distinct_files(files);
    config.csv_rows = true;
  }
  Progress progress(o.quiet, config.pairs.size(), config.planners.size());
  config.on_queries = [&](std::size_t mi, const std::string& map, std::size_t pi, const std::string& planner, std::size_t done,
                          std::size_t steps) { progress.update(mi, map, pi, planner, done, steps); };
  config.on_map_done = [&](std::size_t mi, const std::string& map, std::size_t instances, double seconds) {
    progress.map_done(mi, map, instances, seconds);
  };
  MovingAiResult result;
  try {
    result = run_movingai_experiment(config);
  } catch (...) {
    progress.finish();
    throw;
  }
  progress.finish();
  if (!o.csv.empty()) {
    write_text_file(o.csv, result.csv, "--csv");
  }
  std::cout << (o.json ? movingai_json(result) : movingai_report(result, o.per_map));
  return movingai_exit_code(result);
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
  register_bench_slam(app, ctx);     // the Freiburg SLAM benchmark (cmd_bench_slam.cpp)
  register_bench_localization(app, ctx);  // Ren 2022 localization (cmd_bench_localization.cpp)
  register_bench_ren(app, ctx);           // Ren 2022 local planning and the whole stack (cmd_bench_ren.cpp)
  register_bench_cloud(app, ctx);         // 3D registration on KITTI (cmd_bench_cloud.cpp)
}

}  // namespace starnav::cli
