// starnav bench terrain: the experiment of Liu et al. 2024 (paper section 4, Tables 2 and 3,
// Figs. 6 and 8; docs/terrain.md; write-up docs/papers/liu2024.md). The experiment is
// experiment/terrain_experiment.hpp; this file parses the flags, reports progress and writes files.
//
//   starnav bench terrain (--map FILE | --generate N [--seed S] [--amplitude A]) [--start X,Y --goal X,Y]
//                         [--model-resolution R] [planner flags as plan: --hy-m ... --unobserved]
//                         [--out DIR] [--json] [--svg-limit K] [--force] [--quiet]
//
// Output: the Markdown report on stdout (--json: the JSON instead); with --out DIR also
// DIR/terrain.md (with the per-terrain table), DIR/terrain.json (deterministic: no times),
// DIR/timing.json (search and preprocessing times), and for the first K terrains (--svg-limit,
// default 3) DIR/svg/<terrain>_paths.svg (Fig. 6) and DIR/svg/<terrain>_{roll,pitch,tilt}.svg (Fig. 8).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/terrain_experiment.hpp"
#include "terrain_cli.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct TerrainBenchOptions {
  TerrainExperimentConfig config;
  std::string start;
  std::string goal;
  std::string out;
  bool json = false;
  int svg_limit = 3;
  bool force = false;
  bool quiet = false;
  TerrainPlanFlags flags;
  CLI::Option* generate_opt = nullptr;
  CLI::Option* seed_opt = nullptr;
  CLI::Option* amplitude_opt = nullptr;
  CLI::Option* model_opt = nullptr;
};

void run_bench_terrain(TerrainBenchOptions& o, Context& ctx) {
  TerrainExperimentConfig& c = o.config;
  const bool from_map = !c.map.empty();
  if (from_map == (o.generate_opt->count() > 0))
    throw Error("give exactly one of --map FILE and --generate N", {}, 0, "--map");
  if (from_map) {
    if (o.seed_opt->count()) throw Error("applies to --generate only", {}, 0, "--seed");
    if (o.amplitude_opt->count()) throw Error("applies to --generate only", {}, 0, "--amplitude");
  } else {
    if (c.generate < 1) throw Error("expected a number of terrains >= 1", {}, 0, "--generate");
    if (o.model_opt->count()) throw Error("applies to --map only", {}, 0, "--model-resolution");
  }
  if (o.model_opt->count() && !(c.model_resolution > 0))
    throw Error("expected a cell size in metres > 0", {}, 0, "--model-resolution");
  if (o.svg_limit < 0) throw Error("expected a number >= 0", {}, 0, "--svg-limit");
  if (o.start.empty() != o.goal.empty()) throw Error("give both --start and --goal, or neither", {}, 0, o.start.empty() ? "--start" : "--goal");
  if (!o.start.empty()) {
    c.start_m = parse_xy(o.start, "--start");
    c.goal_m = parse_xy(o.goal, "--goal");
  }
  const RoughTerrainPlannerKind* planners = terrain_experiment_planners();
  c.options = terrain_planner_options(o.flags, {planners[0], planners[1], planners[2]});
  c.figures = static_cast<std::size_t>(o.svg_limit);
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) {
    if (fs::exists(o.out) && !fs::is_directory(o.out)) throw Error("is not a directory", o.out, 0, "--out");
    if (fs::exists(fs::path(o.out) / "terrain.json") && !o.force)
      throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
    out_folder.emplace(o.out, "--out");
    listing.emplace(o.out);
  }
  const std::size_t total = from_map ? 1 : static_cast<std::size_t>(c.generate);
  ProgressBar progress("bench terrain", total, o.quiet);
  c.progress = [&](std::size_t done, std::size_t, const std::string& terrain) { progress.update(done, terrain); };
  const TerrainExperimentResult r = run_terrain_experiment(c);
  progress.finish();

  std::cout << (o.json ? terrain_json(r) : terrain_markdown(r));
  ctx.exit_code = 0;
  if (o.out.empty()) return;
  const std::size_t figures = std::min(r.terrains.size(), c.figures);
  if (figures > 0) fs::create_directories(fs::path(o.out) / "svg");
  for (std::size_t i = 0; i < figures; ++i)
    write_terrain_figures(r, i, (fs::path(o.out) / "svg" / terrain_file_stem(r.terrains[i].name)).string());
  fs::create_directories(o.out);
  write_text_file((fs::path(o.out) / "terrain.md").string(), terrain_full_markdown(r, figures), "--out");
  write_text_file((fs::path(o.out) / "terrain.json").string(), terrain_json(r), "--out");
  write_text_file((fs::path(o.out) / "timing.json").string(), terrain_timing_json(r), "--out");
  listing->print(o.json, o.quiet);
}

}  // namespace

void register_bench_terrain(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<TerrainBenchOptions>();
  auto* cmd = bench->add_subcommand(
      "terrain",
      "Liu et al. 2024 (Tables 2 and 3, Figs. 6 and 8): OA*, AOEA* and IA* on an elevation map or on N generated\n"
      "10 m x 10 m hills terrains (0.1 m, start (0.5, 0.5), goal (9.5, 9.5)); lv, av, hv, Sv and the attitude angles\n"
      "along each path, mean and spread over the terrains, and the paper's pairwise claims.");
  cmd->add_option("--map", o->config.map, "an elevation map (.yaml + 16-bit PNG, .asc, .csv, .raw, GeoTIFF)");
  o->generate_opt = cmd->add_option("--generate", o->config.generate, "generate N hills terrains instead");
  o->seed_opt = cmd->add_option("--seed", o->config.seed, "--generate: seed of the first terrain (default 0; then S+1, ...)");
  o->amplitude_opt = cmd->add_option("--amplitude", o->config.amplitude, "--generate: hills amplitude (default 1)");
  cmd->add_option("--start", o->start, "start X,Y in metres (default (0.5, 0.5) on generated terrains; on a map: see docs/terrain.md)");
  cmd->add_option("--goal", o->goal, "goal X,Y in metres (default (9.5, 9.5) on generated terrains)");
  o->model_opt = cmd->add_option("--model-resolution", o->config.model_resolution,
                                 "--map: plan on a geometric scale model of the map with cells of R metres");
  add_terrain_plan_flags(cmd, o->flags);
  cmd->add_option("--out", o->out, "directory for terrain.md, terrain.json, timing.json and svg/");
  cmd->add_flag("--json", o->json, "print the JSON report instead of the Markdown");
  cmd->add_option("--svg-limit", o->svg_limit, "figures for the first K terrains (default 3)");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_terrain(*o, ctx); });
}

}  // namespace starnav::cli
