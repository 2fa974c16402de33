// starnav bench slam: the Freiburg SLAM benchmark (experiment/slam_benchmark).
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <optional>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/slam_benchmark.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct SlamBenchOptions {
  std::string data, relations, out, logs, method = "graph";
  std::vector<std::string> sets;
  bool json = false, force = false, quiet = false;
};

void run_bench_slam(const SlamBenchOptions& o, Context& ctx) {
  SlamBenchmarkConfig c;
  c.data_dir = o.data;
  c.relations_dir = o.relations;
  c.method = o.method;
  c.settings = parse_set_options(o.sets);
  if (!o.logs.empty()) {
    std::vector<SlamBenchmarkLog> chosen;
    std::stringstream names(o.logs);
    std::string name;
    while (std::getline(names, name, ',')) {
      bool found = false;
      for (const SlamBenchmarkLog& l : c.logs)
        if (l.name == name) chosen.push_back(l), found = true;
      // Any other name is a `starnav sim` output folder under --data (log.clf), its relations
      // NAME/log.relations under --relations: the generated buildings (docs/slam.md).
      if (!found && !name.empty() && fs::is_regular_file(fs::path(o.data) / name / "log.clf"))
        chosen.push_back({name, (fs::path(name) / "log.clf").string(), (fs::path(name) / "log.relations").string(), {}}), found = true;
      if (!found)
        throw Error("unknown log '" + name + "' (intel, fr079, aces, mit-csail, or a folder under --data holding log.clf)", {}, 0, "--logs");
    }
    c.logs = chosen;
  }
  for (const char* dir : {"data", "relations"}) {
    const std::string& d = std::string(dir) == "data" ? o.data : o.relations;
    if (!fs::is_directory(d)) throw Error("is not a directory", d, 0, std::string("--") + dir);
  }
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) {
    if (fs::exists(o.out) && !fs::is_directory(o.out)) throw Error("is not a directory", o.out, 0, "--out");
    if (fs::exists(fs::path(o.out) / "slam.json") && !o.force) throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
    out_folder.emplace(o.out, "--out");
    listing.emplace(o.out);
    c.out_dir = o.out;
  }
  ProgressBar bar("bench slam", c.logs.size() * 1000, o.quiet);
  c.progress = [&](const std::string& log, std::size_t done, std::size_t) { bar.update(done, log); };
  const SlamBenchmarkResult r = run_slam_benchmark(c);
  bar.finish();
  std::cout << (o.json ? slam_benchmark_json(r) : slam_benchmark_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    write_text_file((fs::path(o.out) / "slam.md").string(), slam_benchmark_markdown(r), "--out");
    write_text_file((fs::path(o.out) / "slam.json").string(), slam_benchmark_json(r), "--out");
    listing->print(o.json, o.quiet);
  }
  ctx.exit_code = 0;
}

}  // namespace

void register_bench_slam(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<SlamBenchOptions>();
  auto* cmd = bench->add_subcommand(
      "slam",
      "The Freiburg SLAM benchmark (Kuemmerle et al. 2009): a SLAM method with one parameter set on the raw logs\n"
      "intel, fr079, aces and mit-csail, the relative-pose error of each beside graph mapping, Cartographer and RBPF,\n"
      "CPU and wall time, real-time factor and peak memory (docs/slam.md)");
  cmd->add_option("--data", o->data, "the raw logs' folder (../shared/datasets/carmen_raw)")->required();
  cmd->add_option("--relations", o->relations, "the relation files' folder (../shared/datasets/slam_benchmark_relations)")->required();
  cmd->add_option("--logs", o->logs,
                  "a comma-separated subset of intel,fr079,aces,mit-csail, or simulated runs: NAME is --data/NAME/log.clf with "
                  "--relations/NAME/log.relations (slam make-benchmark)");
  cmd->add_option("--method", o->method, "the SLAM method")->default_str("graph");
  cmd->add_option("--set", o->sets, "a parameter key=value for every log (repeatable)")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--out", o->out, "folder for slam.md, slam.json and each log's trajectory, map and pose graph");
  cmd->add_flag("--json", o->json, "print the JSON report instead of the Markdown");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_slam(*o, ctx); });
}

}  // namespace starnav::cli
