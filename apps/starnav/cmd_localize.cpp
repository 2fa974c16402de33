// starnav localize: AMCL on a recorded 2D laser log and a known map, evaluated against a log of
// corrected poses.
//
//   starnav localize LOG --map MAP.yaml --out DIR [--initial x,y,yaw_deg|global|first]
//       [--reference CORRECTED_LOG] [--set amcl.KEY=VALUE ...] [--seed N] [--flaser-angles] [--range-max M]
//       [--scan-topic T] [--odom-topic T] [--imu-topic T] [--truth-topic T] [--json] [--force] [--quiet]
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "nav2_flags.hpp"
#include "log_flags.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/localize_report.hpp"

namespace starnav::cli {

namespace {

struct LocalizeOptions {
  std::string log;
  std::string map;
  std::string out;
  std::string initial;
  std::string reference;
  std::vector<std::string> sets;
  std::string seed = "1";
  std::string nav2_params;
  LogReadFlags read;
  bool json = false;
  bool force = false;
  bool quiet = false;
};

LocalizeInitial parse_localize_initial(const std::string& text, bool have_reference) {
  LocalizeInitial init;
  if (text.empty()) {
    if (!have_reference) throw Error("give the start: x,y,yaw_deg, global, or first (with --reference)", {}, 0, "--initial");
    return init;  // first
  }
  if (text == "first") return init;
  if (text == "global") {
    init.kind = LocalizeStart::Global;
    return init;
  }
  const std::vector<double> v = parse_number_list(text, "--initial", 3, "x,y,yaw_deg (metres, degrees), global or first");
  init.kind = LocalizeStart::Pose;
  init.pose = Pose2(v[0], v[1], wrap_angle(deg_to_rad(v[2])));
  return init;
}

void run_localize_command(const LocalizeOptions& o, Context& ctx) {
  namespace fs = std::filesystem;
  LocalizeRunRequest q;
  q.log = o.log;
  q.read = log_read_options(o.read);
  q.map = o.map;
  q.reference = o.reference;
  q.initial = parse_localize_initial(o.initial, !o.reference.empty());
  q.seed = parse_unsigned(o.seed, "--seed", "a seed (a non-negative integer)");
  if (!o.nav2_params.empty()) {
    Nav2Target target;
    target.kind = Nav2Target::Kind::Localize;
    const Nav2Params nav2 = read_nav2_params(o.nav2_params, target);
    for (ParamSetting s : nav2.settings()) {
      s.key = s.key.substr(5);  // "amcl."
      q.settings.push_back(std::move(s));
    }
    print_nav2_summary(nav2);
  }
  for (ParamSetting s : parse_set_options(o.sets)) {
    if (s.key.rfind("amcl.", 0) != 0 || s.key.size() == 5)
      throw Error("expected amcl.KEY=VALUE (keys: starnav params, section amcl), got '" + printable(s.key, 60) + "'", {}, 0, s.field);
    s.key = s.key.substr(5);
    q.settings.push_back(std::move(s));
  }
  if (fs::exists(o.out) && !fs::is_directory(o.out)) throw Error("is not a directory", o.out, 0, "--out");
  const fs::path dir(o.out);
  if (fs::exists(dir))
    for (const std::string& f : localize_output_files())
      if (fs::exists(dir / f) && !o.force) throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
  const OutputFolder out_folder(o.out, "--out");
  const OutputListing listing(o.out);
  ProgressBar bar("localize", 1, o.quiet);
  const LocalizeRunResult r = run_localize_on_file(q, [&](std::size_t done, std::size_t total) {
    bar.set_total(total);
    bar.update(done, "scans");
  });
  bar.finish();
  write_localize_outputs(r, o.out);
  if (o.json) {
    std::cout << localize_summary_json(r).dump() << "\n";
  } else {
    std::cout << localize_summary_text(r);
  }
  listing.print(o.json, o.quiet);
  ctx.exit_code = 0;
}

}  // namespace

void register_localize_command(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<LocalizeOptions>();
  auto* cmd = app.add_subcommand(
      "localize",
      "AMCL on a recorded 2D laser log and a known map (the amcl localizer's parameters), evaluated against a log of\n"
      "corrected poses (scans paired by identical ranges); writes trajectory.csv, errors.csv, summary.json, map.png");
  cmd->add_option("LOG", o->log, "the log (CARMEN .clf/.gz, ROS 1 .bag, ROS 2 .mcap/.db3/folder, text extract) with scans and odometry")->required();
  cmd->add_option("--map", o->map, "the map (map_server YAML, e.g. from starnav map build --poses log on the corrected log)")->required();
  cmd->add_option("--out", o->out, "output folder")->required();
  cmd->add_option("--initial", o->initial,
                  "x,y,yaw_deg (a cloud of initial_sigma_xy_m, initial_sigma_yaw_deg around it), global (particles over the\n"
                  "free space), or first (the corrected pose of the first raw scan with a twin in --reference; the run starts\n"
                  "there; the default with --reference)");
  cmd->add_option("--reference", o->reference, "a log whose scans carry corrected laser poses (e.g. a corrected CARMEN log)");
  cmd->add_option("--set", o->sets, "an AMCL parameter amcl.KEY=VALUE (repeatable; starnav params --role localizer lists them). A log's\n"
                  "defaults differ from Nav2's online ones: every scan, 180 beams, sigma_hit_m 0.1; a global start also\n"
                  "10000 particles, recovery alphas 0.001 / 0.1 and the scan proposal (docs/localization.md)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--seed", o->seed, "random seed (default 1)");
  cmd->add_option("--params", o->nav2_params,
                  "a Nav2 parameter file (nav2_params.yaml): its amcl keys mapped to the localizer's parameters before --set\n"
                  "(docs/ros2.md; starnav params --nav2 FILE lists the mapping)");
  add_log_read_flags(cmd, o->read);
  cmd->add_flag("--json", o->json, "print the summary as one JSON object");
  cmd->add_flag("--force", o->force, "overwrite the outputs in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_localize_command(*o, ctx); });
}

}  // namespace starnav::cli
