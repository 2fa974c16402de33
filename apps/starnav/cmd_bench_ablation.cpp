// starnav bench ablation: the path-planning experiment of Ou et al. 2022 (paper 4.2, Table 2 and
// Fig. 15; docs/papers/ou2022.md). The experiment is experiment/ablation_experiment.hpp; this file
// parses the flags, reports progress and writes the files.
//
//   starnav bench ablation --map FILE (--queries FILE | --random N [--seed S]) [--out DIR]
//                          [--inflate R] [--turn-cost K] [--min-dist C] [--max-dist C]
//                          [--repeat R] [--no-exact] [--svg-limit N] [--force] [--quiet]
//
// Output (with --out DIR; the Markdown summary is always printed): DIR/ablation.md (summary and
// per-query tables), DIR/ablation.json, DIR/queries.csv (the queries, reusable with --queries)
// and DIR/svg/query_NNN.svg (the paper's Fig. 15).
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <optional>
#include <string>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/run_limits.hpp"
#include "starnav/experiment/ablation_experiment.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct AblationOptions {
  AblationConfig config;
  int random = 0;
  bool no_exact = false;
  std::string out;
  int svg_limit = -1;
  bool force = false;
  bool quiet = false;
  CLI::Option* random_opt = nullptr;
};

void run_bench_ablation(AblationOptions& o) {
  AblationConfig& c = o.config;
  if (c.queries.empty() == (o.random_opt->count() == 0))
    throw Error("give exactly one of --queries FILE and --random N", {}, 0, "--queries");
  // Each query is planned by every variant and kept in memory with its paths.
  if (c.queries.empty() && (o.random <= 0 || static_cast<std::uint64_t>(o.random) > kMaxRandomQueries))
    throw Error("expected a number of queries in 1.." + std::to_string(kMaxRandomQueries), {}, 0, "--random");
  c.random = c.queries.empty() ? static_cast<std::size_t>(o.random) : 0;
  c.exact_variant = !o.no_exact;
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) {
    if (fs::exists(o.out) && !fs::is_directory(o.out)) throw Error("is not a directory", o.out, 0, "--out");
    if (fs::exists(fs::path(o.out) / "ablation.json") && !o.force)
      throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
    out_folder.emplace(o.out, "--out");
    listing.emplace(o.out);
  }
  if (!o.quiet)
    c.on_table = [](const std::string& table, std::size_t queries) {
      std::cerr << "bench ablation: " << table << ", " << queries << " queries\n";
    };
  const AblationResult r = run_ablation_experiment(c);
  std::cout << ablation_summary_markdown(r);
  if (o.out.empty()) return;

  fs::create_directories(fs::path(o.out) / "svg");
  write_text_file((fs::path(o.out) / "ablation.md").string(), ablation_full_markdown(r), "--out");
  write_text_file((fs::path(o.out) / "queries.csv").string(), ablation_queries_csv(r), "--out");
  write_text_file((fs::path(o.out) / "ablation.json").string(), ablation_json(r), "--out");
  const std::size_t svgs = o.svg_limit < 0 ? r.queries.size() : std::min<std::size_t>(r.queries.size(), o.svg_limit);
  for (std::size_t q = 0; q < svgs; ++q) {
    std::ostringstream name;
    name << "query_" << std::setw(3) << std::setfill('0') << q << ".svg";
    write_ablation_query_svg(r, q, (fs::path(o.out) / "svg" / name.str()).string());
  }
  listing->print(false, o.quiet);
}

}  // namespace

void register_bench_ablation(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<AblationOptions>();
  auto* cmd = bench->add_subcommand(
      "ablation",
      "Ou et al. 2022 (Table 2, Fig. 15): A*, A* + turn_w, A* + turn_w + W, + LOS smoothing (the full method on the\n"
      "inflated map), the exact steering variant, JPS and JPS + LOS on the same queries; time, expansions, Tir and\n"
      "Enr (% better than A*) and path metrics, per heuristic (manhattan, octile) and map (original, inflated).");
  cmd->add_option("--map", o->config.map, "occupancy map (MovingAI .map, map_server .yaml)")->required();
  cmd->add_option("--queries", o->config.queries,
                  "queries in cells: a MovingAI .scen or a CSV with header start_x,start_y,goal_x,goal_y");
  o->random_opt = cmd->add_option("--random", o->random, "draw N random queries instead");
  cmd->add_option("--seed", o->config.seed, "seed of --random (default 0)");
  cmd->add_option("--min-dist", o->config.min_dist, "--random: least start-goal distance in cells (default 40)");
  cmd->add_option("--max-dist", o->config.max_dist, "--random: largest start-goal distance in cells (default 60)");
  cmd->add_option("--inflate", o->config.inflate, "hard inflation radius R (metres; cells on MovingAI maps; default 0)");
  cmd->add_option("--turn-cost", o->config.turn_cost, "steering cost k_turn (default 1, the paper's k = 10)");
  cmd->add_option("--repeat", o->config.repeat, "runs per query and variant; the time is their least thread CPU time (default 5)");
  cmd->add_flag("--no-exact", o->no_exact, "leave out the exact (cell, direction) steering variant");
  cmd->add_option("--svg-limit", o->svg_limit, "write SVGs for the first N queries only (default all)");
  cmd->add_option("--out", o->out, "directory for ablation.md, ablation.json, queries.csv and svg/");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] {
    run_bench_ablation(*o);
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
