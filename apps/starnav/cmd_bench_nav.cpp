// starnav bench nav: a navigation scenario over many seeds (Li et al. 2019 navigation loop;
// experiment/navigation_experiment.hpp), with D* Lite and A*-from-scratch replanning compared on the
// same runs. This file parses the flags and prints; the experiment and its reports are the library's.
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
// --out DIR also DIR/runs.csv and DIR/summary.json (the --json document, byte-identical between
// identical runs) and DIR/timing.json (the wall-clock figures). Exit 0 when every run
// completed (a run that does not reach the goal is a result); 1 when a run failed with an
// exception (reported in the results as outcome "error" and in one line on stderr); 2 for bad
// flags or a bad scenario.
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/run_limits.hpp"
#include "starnav/experiment/navigation_experiment.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;


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

// cli_util's parse_unsigned, also taking a leading '+'.
std::uint64_t parse_count(const std::string& text, const std::string& flag, const char* what) {
  return parse_unsigned(text.size() > 1 && text[0] == '+' ? text.substr(1) : text, flag, what);
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
  if (o.json && o.csv) throw Error("give --json or --csv, not both", {}, 0, "--csv");
  if (!o.out.empty()) {
    std::error_code ec;
    if (fs::exists(o.out, ec) && !fs::is_directory(o.out, ec)) throw Error("exists and is not a folder", o.out, 0, "--out");
    if (!o.force && (fs::exists(fs::path(o.out) / "summary.json", ec) || fs::exists(fs::path(o.out) / "runs.csv", ec)))
      throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
  }
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(o.out, "--out");
  if (out_folder) listing.emplace(o.out);

  NavExperimentConfig config;
  config.scenario_file = o.scenario;
  std::vector<ScenarioOverride> overrides;
  for (const std::string& text : o.sets) overrides.push_back(parse_scenario_override(text));
  std::vector<CommandOwnedKey> owned = {{"navigation.planner", "bench nav runs dstar_lite and astar on every seed"},
                                        {"sim.seed", "--seeds and --seed-base give each run its seed"}};
  if (!o.motion_mode.empty()) {
    owned.push_back({"motion_mode", "--motion-mode gives it"});
    owned.push_back({"navigation.follower.motion_mode", "--motion-mode gives it"});
  }
  check_user_overrides(overrides, owned);
  config.scenario = load_scenario(o.scenario, overrides);
  if (!config.scenario.navigation)
    throw Error("not a navigation scenario (no navigation section; see docs/scenarios.md)", o.scenario, 0, "navigation");
  config.seed_base = base;
  config.seeds = n;
  if (!o.motion_mode.empty()) config.motion_mode = o.motion_mode;

  const ExperimentGrid grid = nav_experiment_grid(config);
  ProgressBar progress("bench nav", grid.trials(), o.quiet);
  NavExperimentResult result;
  try {
    result = run_nav_experiment(config, [&](std::size_t done, std::size_t total, const TrialKey& key) {
      progress.update(done, done < total ? "seed " + std::to_string(key.seed) + " " + grid.variants[key.variant].name : "done");
    });
  } catch (...) {
    progress.finish();
    throw;
  }
  progress.finish();

  const std::string csv = nav_runs_csv(result);
  const std::string doc = nav_experiment_json(result);
  if (o.json) std::cout << doc;
  else if (o.csv) std::cout << csv;
  else std::cout << nav_experiment_table(result);
  std::cout.flush();

  if (!o.out.empty()) {
    std::error_code ec;
    fs::create_directories(o.out, ec);
    if (ec) throw Error("cannot create the folder: " + ec.message(), o.out, 0, "--out");
    write_text_file((fs::path(o.out) / "runs.csv").string(), csv, "--out");
    write_text_file((fs::path(o.out) / "summary.json").string(), doc, "--out");
    write_text_file((fs::path(o.out) / "timing.json").string(), nav_timing_json(result), "--out");
    listing->print(o.json || o.csv, o.quiet);
  }

  std::size_t failed = 0;
  const NavTrial* first = nullptr;
  for (const NavTrial& t : result.trials)
    if (!t.completed) {
      ++failed;
      if (!first) first = &t;
    }
  if (failed) {
    std::cerr << "starnav: error: " << o.scenario << ": " << failed << " of " << result.trials.size()
              << " runs failed (first: seed " << first->key.seed << ", " << first->record.planner << ": " << first->error << ")\n";
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
