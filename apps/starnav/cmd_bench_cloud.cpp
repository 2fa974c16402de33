// starnav bench kitti: scan-to-scan registration of the 3D matchers on real KITTI frames and the
// RANSAC floor against SemanticKITTI's ground labels (experiment/kitti_registration_experiment).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/experiment/kitti_registration_experiment.hpp"

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
  if (!o.out.empty()) check_out_dir(o.out, o.force);
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
    if (!o.quiet) std::cerr << "bench kitti: wrote " << o.out << "/{kitti.md, kitti.json, pairs.csv}\n";
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
  cmd->add_option("--matchers", o->config.matchers, "icp, icp_plane, gicp, ndt, ndt_mt (comma-separated)")
      ->delimiter(',')
      ->default_str("icp,icp_plane,gicp,ndt,ndt_mt");
  cmd->add_option("--frames", o->config.frames, "frames per sequence (pairs: frames - 1)")->default_str("10");
  cmd->add_option("--voxel-m", o->voxel_m, "the prefilter's voxel leaf (m)")->default_str("0.25");
  cmd->add_option("--out", o->out, "folder for kitti.md, kitti.json and pairs.csv");
  cmd->add_flag("--json", o->json, "print the JSON report instead of the Markdown");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_kitti(*o, ctx); });
}

}  // namespace starnav::cli
