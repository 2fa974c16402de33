// starnav bench ekf-square (odometry vs EKF vs EKF with the bias state), starnav bench amcl
// (experiment/localization_experiment) and starnav bench amcl-cost (experiment/amcl_cost_experiment).
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/amcl_cost_experiment.hpp"
#include "starnav/experiment/localization_experiment.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct EkfSquareOptions {
  std::string scenario = "scenarios/ekf_square.yaml", out;
  std::vector<std::string> sets;
  std::uint64_t seeds = 20, seed_base = 0;
  double plain_sigma_deg = 0.5;
  bool json = false, force = false, quiet = false;
};

void run_bench_ekf_square(const EkfSquareOptions& o, Context& ctx) {
  EkfSquareConfig c;
  c.scenario_file = o.scenario;
  for (const std::string& s : o.sets) c.overrides.push_back(parse_scenario_override(s));
  c.seeds = o.seeds;
  c.seed_base = o.seed_base;
  c.plain_imu_yaw_sigma_deg = o.plain_sigma_deg;
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  ProgressBar bar("bench ekf-square", o.seeds, o.quiet);
  const EkfSquareResult r = run_ekf_square(c, [&](std::size_t done, std::size_t, const TrialKey&) { bar.update(done, "seed"); });
  bar.finish();
  std::cout << (o.json ? ekf_square_json(r) : ekf_square_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "ekf_square.md").string(), ekf_square_markdown(r), "--out");
    write_text_file((d / "ekf_square.json").string(), ekf_square_json(r), "--out");
    write_text_file((d / "runs.csv").string(), ekf_square_runs_csv(r), "--out");
    write_text_file((d / "nees.csv").string(), ekf_square_nees_csv(r), "--out");
    write_ekf_square_pictures(r, o.out);
    listing->print(o.json, o.quiet);
  }
  ctx.exit_code = 0;
}

struct AmclBenchOptions {
  std::vector<std::string> scenarios, sets, cases{"tracking"};
  std::string out;
  std::uint64_t seeds = 20, seed_base = 0;
  bool json = false, force = false, quiet = false;
};

void run_bench_amcl(const AmclBenchOptions& o, Context& ctx) {
  AmclBenchConfig c;
  c.scenarios = o.scenarios;
  c.cases = o.cases;
  for (const std::string& s : o.sets) c.overrides.push_back(parse_scenario_override(s));
  c.seeds = o.seeds;
  c.seed_base = o.seed_base;
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  ProgressBar bar("bench amcl", o.seeds * o.scenarios.size() * o.cases.size(), o.quiet);
  const AmclBenchResult r = run_amcl_bench(c, [&](std::size_t done, std::size_t, const TrialKey& next) {
    bar.update(done, fs::path(o.scenarios[next.instance]).stem().string() + " seed " + std::to_string(next.seed));
  });
  bar.finish();
  std::cout << (o.json ? amcl_bench_json(r) : amcl_bench_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "amcl.md").string(), amcl_bench_markdown(r), "--out");
    write_text_file((d / "amcl.json").string(), amcl_bench_json(r), "--out");
    write_text_file((d / "runs.csv").string(), amcl_bench_runs_csv(r), "--out");
    write_amcl_bench_pictures(r, o.out);
    listing->print(o.json, o.quiet);
  }
  // A run that threw is in the table; the command still failed.
  for (const auto& t : r.trials)
    if (!t.completed) {
      ctx.exit_code = 1;
      return;
    }
  ctx.exit_code = 0;
}

struct AmclCostOptions {
  AmclCostConfig config;
  std::string out;
  bool json = false, force = false, quiet = false;
};

void run_bench_amcl_cost(const AmclCostOptions& o, Context& ctx) {
  o.config.validate();
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  ProgressBar bar("bench amcl-cost", o.config.particles.size() * o.config.beams.size(), o.quiet);
  const AmclCostResult r = run_amcl_cost(o.config, [&](std::size_t done, std::size_t) { bar.update(done, "pair"); });
  bar.finish();
  std::cout << (o.json ? amcl_cost_json(r) : amcl_cost_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "amcl_cost.md").string(), amcl_cost_markdown(r), "--out");
    write_text_file((d / "amcl_cost.json").string(), amcl_cost_json(r), "--out");
    write_text_file((d / "amcl_cost.csv").string(), amcl_cost_csv(r), "--out");
    write_amcl_cost_pictures(r, o.out);
    listing->print(o.json, o.quiet);
  }
  ctx.exit_code = 0;
}

}  // namespace

void register_bench_localization(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<EkfSquareOptions>();
  auto* cmd = bench->add_subcommand(
      "ekf-square",
      "Ren et al. 2022 Fig. 5: a square driven with slipping wheels and a biased gyro; dead reckoning, the paper's\n"
      "three-state EKF and the EKF with the gyro bias in its state on the same noise, over seeds: end drift,\n"
      "trajectory RMSE, heading error, and the bias EKF's NEES against its chi-square interval (docs/localization.md)");
  cmd->add_option("--scenario", o->scenario, "the scenario (localization: odometry wheel, localizer ekf)")->default_str(o->scenario);
  cmd->add_option("--seeds", o->seeds, "how many seeds")->default_str("20")->check(CLI::Range(1, 10000));
  cmd->add_option("--seed-base", o->seed_base, "the first seed")->default_str("0");
  cmd->add_option("--plain-yaw-sigma-deg", o->plain_sigma_deg, "the three-state EKF's IMU yaw noise (deg)")
      ->default_str("0.5")->check(CLI::Range(1e-6, 180.0));
  cmd->add_option("--set", o->sets, "a scenario key=value (repeatable)")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--out", o->out, "folder for ekf_square.md, ekf_square.json, runs.csv and the pictures");
  cmd->add_flag("--json", o->json, "print the JSON report instead of the Markdown");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_ekf_square(*o, ctx); });

  auto a = std::make_shared<AmclBenchOptions>();
  auto* amcl = bench->add_subcommand(
      "amcl",
      "Ren et al. 2022 Figs. 7-8: AMCL in the simulator over seeds, one scenario per case (tracking, global start,\n"
      "kidnapped robot; scenarios/amcl_*.yaml): updates until converged, error after, updates to reconverge\n"
      "after a teleport, false convergences (docs/localization.md)");
  amcl->add_option("scenarios", a->scenarios, "SCENARIO.yaml ... (each with a localization section)")->required();
  amcl->add_option("--cases", a->cases, "tracking, global, kidnap (comma-separated)")->delimiter(',')->default_str("tracking");
  amcl->add_option("--seeds", a->seeds, "how many seeds")->default_str("20")->check(CLI::Range(1, 10000));
  amcl->add_option("--seed-base", a->seed_base, "the first seed")->default_str("0");
  amcl->add_option("--set", a->sets, "a scenario key=value for every scenario (repeatable)")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  amcl->add_option("--out", a->out, "folder for amcl.md, amcl.json, runs.csv and the pictures");
  amcl->add_flag("--json", a->json, "print the JSON report instead of the Markdown");
  amcl->add_flag("--force", a->force, "overwrite the results in --out");
  amcl->add_flag("--quiet", a->quiet, "no progress on stderr");
  amcl->callback([a, &ctx] { run_bench_amcl(*a, ctx); });

  auto k = std::make_shared<AmclCostOptions>();
  k->config.map_file = "scenarios/maps/indoor_rooms.yaml";
  auto* cost = bench->add_subcommand(
      "amcl-cost",
      "CPU time of one AMCL update against particles and beams on a map_server map (median of repeated timings,\n"
      "one core; a table and two plots; docs/localization.md)");
  cost->add_option("--map", k->config.map_file, "MAP.yaml (map_server)")->default_str(k->config.map_file);
  cost->add_option("--particles", k->config.particles, "particle counts (comma-separated)")
      ->delimiter(',')->default_str("500,1000,2000,5000,10000,20000");
  cost->add_option("--beams", k->config.beams, "beams used per update (comma-separated, 2-360)")
      ->delimiter(',')->default_str("30,60,120,180,360");
  cost->add_option("--updates", k->config.updates, "updates per timing")->default_str("10");
  cost->add_option("--repeats", k->config.repeats, "timings per pair (median, min, max)")->default_str("5");
  cost->add_option("--seed", k->config.seed, "the filter's seed")->default_str("0");
  cost->add_option("--out", k->out, "folder for amcl_cost.md, amcl_cost.json, amcl_cost.csv and the plots");
  cost->add_flag("--json", k->json, "print the JSON report instead of the Markdown");
  cost->add_flag("--force", k->force, "overwrite the results in --out");
  cost->add_flag("--quiet", k->quiet, "no progress on stderr");
  cost->callback([k, &ctx] { run_bench_amcl_cost(*k, ctx); });
}

}  // namespace starnav::cli
