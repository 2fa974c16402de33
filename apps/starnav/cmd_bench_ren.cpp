// starnav bench ren-table1 (A* against Dijkstra, experiment/ren_table1_experiment) and
// starnav bench ren-table4 (the whole indoor stack cycling between two goal poses over seeds,
// experiment/ren_table4_experiment): Ren et al. 2022.
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/dwa_experiment.hpp"
#include "starnav/experiment/ren_table1_experiment.hpp"
#include "starnav/experiment/ren_table4_experiment.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct Table4Options {
  std::string scenario = "scenarios/ren_table4.yaml", out;
  std::vector<std::string> sets;
  std::uint64_t seeds = 20, seed_base = 0;
  bool json = false, force = false, quiet = false;
};

void run_bench_table4(const Table4Options& o, Context& ctx) {
  RenTable4Config c;
  c.scenario_file = o.scenario;
  for (const std::string& s : o.sets) c.overrides.push_back(parse_scenario_override(s));
  c.seeds = o.seeds;
  c.seed_base = o.seed_base;
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  ProgressBar bar("bench ren-table4", o.seeds, o.quiet);
  const RenTable4Result r = run_ren_table4(c, [&](std::size_t done, std::size_t, const TrialKey& next) {
    bar.update(done, "seed " + std::to_string(next.seed));
  });
  bar.finish();
  std::cout << (o.json ? ren_table4_json(r) : ren_table4_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "table4.md").string(), ren_table4_markdown(r), "--out");
    write_text_file((d / "table4.json").string(), ren_table4_json(r), "--out");
    write_text_file((d / "runs.csv").string(), ren_table4_runs_csv(r), "--out");
    write_text_file((d / "arrivals.csv").string(), ren_table4_arrivals_csv(r), "--out");
    listing->print(o.json, o.quiet);
  }
  // A seed that threw, collided or did not arrive is in the table; the command still failed.
  for (const auto& t : r.trials)
    if (!t.completed || !t.record.success) {
      ctx.exit_code = 1;
      return;
    }
  ctx.exit_code = 0;
}

struct Table1Options {
  RenTable1Config config;
  std::string out;
  bool json = false, force = false, quiet = false;
};

void run_bench_table1(const Table1Options& o, Context& ctx) {
  o.config.validate();
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  if (!o.quiet) std::cerr << "bench ren-table1: " << o.config.queries << " random queries and " << o.config.repeats
                          << " repeats of the room query per planner\n";
  const RenTable1Result r = run_ren_table1(o.config);
  std::cout << (o.json ? ren_table1_json(r) : ren_table1_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "table1.md").string(), ren_table1_markdown(r), "--out");
    write_text_file((d / "table1.json").string(), ren_table1_json(r), "--out");
    write_text_file((d / "table1.csv").string(), ren_table1_csv(r), "--out");
    listing->print(o.json, o.quiet);
  }
  ctx.exit_code = r.cost_mismatches == 0 ? 0 : 1;
}

struct DwaOptions {
  std::string experiment = "doorway", scenario, out;
  std::vector<std::string> sets;
  std::uint64_t seeds = 20, seed_base = 0;
  bool json = false, force = false, quiet = false;
};

void run_bench_dwa(const DwaOptions& o, Context& ctx) {
  DwaExperimentConfig c;
  c.experiment = o.experiment;
  c.scenario_file = o.scenario.empty() ? "scenarios/dwa_" + o.experiment + ".yaml" : o.scenario;
  for (const std::string& s : o.sets) c.overrides.push_back(parse_scenario_override(s));
  c.seeds = o.seeds;
  c.seed_base = o.seed_base;
  c.validate();
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  ProgressBar bar("bench dwa", o.seeds, o.quiet);
  const DwaExperimentResult r = run_dwa_experiment(c, [&](std::size_t done, std::size_t, const TrialKey& next) {
    bar.update(done, "seed " + std::to_string(next.seed));
  });
  bar.finish();
  std::cout << (o.json ? dwa_experiment_json(r) : dwa_experiment_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "dwa.md").string(), dwa_experiment_markdown(r), "--out");
    write_text_file((d / "dwa.json").string(), dwa_experiment_json(r), "--out");
    write_text_file((d / "runs.csv").string(), dwa_experiment_csv(r), "--out");
    listing->print(o.json, o.quiet);
  }
  for (const auto& t : r.trials)
    if (!t.completed) {
      ctx.exit_code = 1;
      return;
    }
  ctx.exit_code = 0;
}

}  // namespace

void register_bench_ren(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<Table4Options>();
  auto* cmd = bench->add_subcommand(
      "ren-table4",
      "Ren et al. 2022 Table 4: the indoor robot's whole stack (AMCL on EKF odometry, A*, DWA, bumper) cycling\n"
      "between two goal poses over seeds; per seed the max, min and mean arrival error in x, y and heading, and\n"
      "the paper's table over the seeds (docs/local_planning.md)");
  cmd->add_option("--scenario", o->scenario, "the scenario (navigation goals with headings and laps)")->default_str(o->scenario);
  cmd->add_option("--seeds", o->seeds, "how many seeds")->default_str("20")->check(CLI::Range(1, 10000));
  cmd->add_option("--seed-base", o->seed_base, "the first seed")->default_str("0");
  cmd->add_option("--set", o->sets, "a scenario key=value (repeatable)")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--out", o->out, "folder for table4.md, table4.json, runs.csv and arrivals.csv");
  cmd->add_flag("--json", o->json, "print the JSON report instead of the Markdown");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_table4(*o, ctx); });

  auto t = std::make_shared<Table1Options>();
  auto* t1 = bench->add_subcommand(
      "ren-table1",
      "Ren et al. 2022 Table 1: A* against Dijkstra from (1, 1) m to (18, 18) m in a 20 m x 20 m room, empty and\n"
      "with obstacles, and on random queries on the indoor map: nodes expanded and search CPU time\n"
      "(docs/local_planning.md)");
  t1->add_option("--empty-room", t->config.empty_room, "the empty room (map_server YAML)")->default_str(t->config.empty_room);
  t1->add_option("--obstacle-room", t->config.obstacle_room, "the room with obstacles")->default_str(t->config.obstacle_room);
  t1->add_option("--indoor-map", t->config.indoor_map, "the map of the random queries")->default_str(t->config.indoor_map);
  t1->add_option("--inflation-m", t->config.inflation_m, "obstacle inflation (the robot's inscribed radius)")->default_str("0.25");
  t1->add_option("--repeats", t->config.repeats, "timings of the room query per planner (median)")->default_str("20");
  t1->add_option("--queries", t->config.queries, "random queries on the indoor map (0: none)")->default_str("1000");
  t1->add_option("--seed", t->config.seed, "the random queries' seed")->default_str("0");
  t1->add_option("--out", t->out, "folder for table1.md, table1.json and table1.csv");
  t1->add_flag("--json", t->json, "print the JSON report instead of the Markdown");
  t1->add_flag("--force", t->force, "overwrite the results in --out");
  t1->add_flag("--quiet", t->quiet, "no progress on stderr");
  t1->callback([t, &ctx] { run_bench_table1(*t, ctx); });

  auto w = std::make_shared<DwaOptions>();
  auto* dwa = bench->add_subcommand(
      "dwa",
      "DWA's experiments over seeds: doorway (0.8 m door: arrivals, sign changes of vx and wz per 2 s), sideways\n"
      "(a goal to a Mecanum robot's side: |vy|, turn, final error), people (walking people-like obstacles: arrivals,\n"
      "contacts the robot caused) (docs/local_planning.md)");
  dwa->add_option("--case", w->experiment, "doorway, sideways or people")->default_str("doorway");
  dwa->add_option("--scenario", w->scenario, "the scenario (default scenarios/dwa_CASE.yaml)");
  dwa->add_option("--seeds", w->seeds, "how many seeds")->default_str("20")->check(CLI::Range(1, 100000));
  dwa->add_option("--seed-base", w->seed_base, "the first seed")->default_str("0");
  dwa->add_option("--set", w->sets, "a scenario key=value (repeatable)")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  dwa->add_option("--out", w->out, "folder for dwa.md, dwa.json and runs.csv");
  dwa->add_flag("--json", w->json, "print the JSON report instead of the Markdown");
  dwa->add_flag("--force", w->force, "overwrite the results in --out");
  dwa->add_flag("--quiet", w->quiet, "no progress on stderr");
  dwa->callback([w, &ctx] { run_bench_dwa(*w, ctx); });
}

}  // namespace starnav::cli
