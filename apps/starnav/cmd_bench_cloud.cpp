// starnav bench kitti: scan-to-scan registration of the 3D matchers on real KITTI frames and the
// RANSAC floor against SemanticKITTI's ground labels (experiment/kitti_registration_experiment).
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/experiment/kitti_registration_experiment.hpp"
#include "starnav/experiment/mapping3d_experiment.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct KittiOptions {
  KittiRegistrationConfig config;
  double voxel_m = 0.25;
  std::string out;
  bool json = false, force = false, quiet = false;
};

void run_bench_kitti(KittiOptions& o, Context& ctx) {
  o.config.prefilter.voxel_leaf_m = o.voxel_m;
  o.config.validate();
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  ProgressBar bar("bench kitti", 1, o.quiet);
  const KittiRegistrationResult r = run_kitti_registration(o.config, [&](std::size_t done, std::size_t total, const std::string& what) {
    bar.set_total(total);
    bar.update(done, what);
  });
  bar.finish();
  std::cout << (o.json ? kitti_registration_json(r) : kitti_registration_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "kitti.md").string(), kitti_registration_markdown(r), "--out");
    write_text_file((d / "kitti.json").string(), kitti_registration_json(r), "--out");
    write_text_file((d / "pairs.csv").string(), kitti_registration_csv(r), "--out");
    listing->print(o.json, o.quiet);
  }
  ctx.exit_code = 0;
}

struct Mapping3dOptions {
  Mapping3dExperimentConfig config;
  std::vector<std::string> sets, slam_sets;
  std::string out;
  bool json = false, force = false, quiet = false;
};

void run_bench_mapping3d(Mapping3dOptions& o, Context& ctx) {
  if (o.config.no_floor_matcher == "none") o.config.no_floor_matcher.clear();
  for (const std::string& s : o.sets) o.config.overrides.push_back(parse_scenario_override(s));
  o.config.slam_settings = parse_set_options(o.slam_sets);
  o.config.validate();
  std::optional<OutputFolder> out_folder;
  std::optional<OutputListing> listing;
  if (!o.out.empty()) out_folder.emplace(check_out_dir(o.out, o.force));
  if (out_folder) listing.emplace(o.out);
  ProgressBar bar("bench mapping3d", o.config.seeds, o.quiet);
  const Mapping3dResult r = run_mapping3d_experiment(o.config, [&](std::size_t done, std::size_t, const std::string& what) {
    bar.update(done, what);
  });
  bar.finish();
  std::cout << (o.json ? mapping3d_json(r) : mapping3d_markdown(r));
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    const fs::path d(o.out);
    write_text_file((d / "mapping3d.md").string(), mapping3d_markdown(r), "--out");
    write_text_file((d / "mapping3d.json").string(), mapping3d_json(r), "--out");
    write_text_file((d / "runs.csv").string(), mapping3d_csv(r), "--out");
    write_mapping3d_figures(r, o.out);
    listing->print(o.json, o.quiet);
  }
  ctx.exit_code = 0;
}

}  // namespace

void register_bench_cloud(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<KittiOptions>();
  auto* cmd = bench->add_subcommand(
      "kitti",
      "3D scan matchers on real data: each matcher registers KITTI odometry frame k+1 onto frame k from the identity;\n"
      "translation and rotation error against the reference poses, time and iterations per matcher; the RANSAC floor\n"
      "of frame 0 against SemanticKITTI's ground labels (docs/mapping3d.md)");
  cmd->add_option("--dataset", o->config.dataset, "the kitti_odometry_mini folder")->default_str(o->config.dataset);
  cmd->add_option("--sequences", o->config.sequences, "sequences, comma-separated")->delimiter(',')->default_str("00,05,07");
  cmd->add_option("--matchers", o->config.matchers, "icp, icp_plane, gicp, vgicp, ndt, ndt_mt, pcl_icp, pcl_gicp, pcl_ndt (comma-separated)")
      ->delimiter(',')
      ->default_str("icp,icp_plane,gicp,ndt,ndt_mt");
  cmd->add_option("--frames", o->config.frames, "frames per sequence (pairs: frames - 1)")->default_str("10");
  cmd->add_option("--voxel-m", o->voxel_m, "the prefilter's voxel leaf (m)")->default_str("0.25");
  cmd->add_option("--out", o->out, "folder for kitti.md, kitti.json and pairs.csv");
  cmd->add_flag("--json", o->json, "print the JSON report instead of the Markdown");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_kitti(*o, ctx); });

  auto m = std::make_shared<Mapping3dOptions>();
  auto* mc = bench->add_subcommand(
      "mapping3d",
      "Ou et al. 2022 section 4.1 simulated: the indoor 16-beam LiDAR run over seeds, mapped in process by 3D graph\n"
      "SLAM with each matcher (and one without the floor constraint): points per filter stage, time per\n"
      "registration, ATE and elevation drift against the truth, pictures (docs/mapping3d.md)");
  mc->add_option("--scenario", m->config.scenario, "the scenario")->default_str(m->config.scenario);
  mc->add_option("--seeds", m->config.seeds, "how many seeds")->default_str("10");
  mc->add_option("--seed-base", m->config.seed_base, "the first seed")->default_str("0");
  mc->add_option("--matchers", m->config.matchers, "3D matchers (comma-separated)")->delimiter(',')->default_str("icp,gicp,ndt,ndt_mt");
  mc->add_option("--no-floor-matcher", m->config.no_floor_matcher, "the matcher also run without the floor constraint (none: no such run)")
      ->default_str("gicp");
  mc->add_option("--set", m->sets, "a scenario key=value (repeatable)")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  mc->add_option("--slam-set", m->slam_sets, "a 3D SLAM parameter key=value (repeatable)")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  mc->add_option("--out", m->out, "folder for mapping3d.md, mapping3d.json, runs.csv and the figures");
  mc->add_flag("--json", m->json, "print the JSON report instead of the Markdown");
  mc->add_flag("--force", m->force, "overwrite the results in --out");
  mc->add_flag("--quiet", m->quiet, "no progress on stderr");
  mc->callback([m, &ctx] { run_bench_mapping3d(*m, ctx); });
}

}  // namespace starnav::cli
