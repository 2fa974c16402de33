// starnav slam3d: 3D graph SLAM on a LiDAR recording (docs/mapping3d.md).
//
//   starnav slam3d INPUT --out DIR [--matcher icp|gicp|ndt|ndt_mt] [--set key=value ...]
//                        [--matcher-set key=value ...] [--frames N] [--poses FILE] [--mount X,Y,Z,R,P,Y]
//                        [--cloud-topic T] [--odom-topic T] [--truth-topic T] [--plan-to X,Y] [--no-map] [--json] [--force]
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/slam3d_record.hpp"
#include "starnav/harness/slam3d_run.hpp"

namespace starnav::cli {

namespace {

struct Slam3dOptions {
  std::string input, out, matcher = "ndt_mt";
  std::vector<std::string> sets, matcher_sets;
  int frames = 0;
  double map_resolution_m = 0.05, band_min_m = 0.1, band_max_m = 0.6, inflation_m = 0.35;
  std::string plan_to;
  std::string poses, mount, cloud_topic, odom_topic, truth_topic;
  double rate_hz = 10.0;
  bool no_map = false, json = false, force = false, quiet = false;
};

void run_slam3d(const Slam3dOptions& o, Context& ctx) {
  Slam3dRunConfig c;
  c.matcher = o.matcher;
  c.max_frames = o.frames;
  c.settings = parse_set_options(o.sets);
  c.matcher_settings = parse_set_options(o.matcher_sets);
  if (o.frames < 0) throw Error("must be >= 0", "", 0, "--frames");
  if (!(o.inflation_m >= 0 && o.inflation_m <= 10)) throw Error("must be in [0, 10] m", "", 0, "--inflation-m");
  {
    OctreeMapConfig oc;
    oc.resolution_m = o.map_resolution_m;
    GridProjectionConfig gc;
    gc.min_height_m = o.band_min_m;
    gc.max_height_m = o.band_max_m;
    try {
      oc.validate();
      gc.validate();
    } catch (const Error& e) {
      throw Error(e.message(), "", 0, e.field() == "resolution_m" ? "--map-resolution-m" : "--band-m");
    }
  }
  c.recording.poses = o.poses;
  c.recording.rate_hz = o.rate_hz;
  c.recording.bag = {o.cloud_topic, o.odom_topic, o.truth_topic};
  if (!o.mount.empty()) {
    const std::vector<double> m = parse_number_list(o.mount, "--mount", 6, "X,Y,Z,ROLL,PITCH,YAW (m, degrees)");
    c.recording.mount = Pose3::from_rpy(Vec3(m[0], m[1], m[2]), m[3] * kPi / 180, m[4] * kPi / 180, m[5] * kPi / 180);
  }
  if (!(std::isfinite(o.rate_hz) && o.rate_hz > 0 && o.rate_hz <= 10000)) throw Error("must be in (0, 10000] Hz", "", 0, "--rate-hz");
  const OutputFolder out_folder = check_out_dir(o.out, o.force);
  const OutputListing listing(o.out);
  ProgressBar bar("slam3d", 1, o.quiet);
  const Slam3dRunResult r = run_slam3d(o.input, c, [&](std::size_t done, std::size_t total) {
    bar.set_total(total);
    bar.update(done, "frame " + std::to_string(done));
  });
  bar.finish();
  Slam3dOutputConfig out;
  out.map = !o.no_map;
  out.map_config.octree.resolution_m = o.map_resolution_m;
  out.map_config.grid.min_height_m = o.band_min_m;
  out.map_config.grid.max_height_m = o.band_max_m;
  out.inflation_m = o.inflation_m;
  if (!o.plan_to.empty() && !o.no_map) {
    const std::vector<double> g = parse_number_list(o.plan_to, "--plan-to", 2, "X,Y (metres, map frame)");
    out.plan_to = Vec2(g[0], g[1]);
  }
  const Slam3dOutputs written = write_slam3d_outputs(r, o.input, o.out, out);
  std::string plan_line;
  if (written.plan)
    plan_line = written.plan->result.found() ? "; improved A* path " + format_readable(written.plan->metrics.length) + " m"
                                             : "; improved A*: no path";
  if (o.json) {
    std::cout << slam3d_summary_json(r);
  } else {
    std::cout << "slam3d: " << r.frames << " frames, " << r.keyframes.size() << " key frames, " << r.graph.closures()
              << " loop closures, " << r.plane_edges << " floor edges; mapping " << format_fixed(r.mapping_s, 2) << " s for "
              << format_fixed(r.duration_s, 1) << " s of recording";
    if (r.has_truth)
      std::cout << "; ATE " << format_fixed(100.0 * r.ate_rmse_m, 2) << " cm over " << format_fixed(r.driven_m, 2)
                << " m, elevation drift " << format_fixed(100.0 * r.elevation_drift_m, 2) << " cm";
    std::cout << plan_line << "\n";
  }
  listing.print(o.json, o.quiet);
  ctx.exit_code = 0;
}

}  // namespace

void register_slam3d_command(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<Slam3dOptions>();
  auto* cmd = app.add_subcommand(
      "slam3d",
      "3D graph SLAM (hdl_graph_slam's pipeline, Ou et al. 2022 section 2) on a LiDAR recording: a frames folder\n"
      "(sensor-frame clouds, frames.csv and sensor.yaml, as `starnav sim` writes them with outputs.lidar_frames; a\n"
      "simulator run folder works too), a folder of PCD / PLY / KITTI .bin clouds with a poses file (a KITTI\n"
      "sequence folder works as it is), or a ROS 1 bag of sensor_msgs/PointCloud2 with its odometry and /tf_static;\n"
      "the trajectory, the key frames with their floors, the octree and the 2D grid, and the error against the\n"
      "reference when the recording has one (docs/mapping3d.md)");
  cmd->add_option("INPUT", o->input, "a frames folder, a simulator run folder, a folder of cloud files or a ROS 1 bag")->required();
  cmd->add_option("--out", o->out, "folder for trajectory.csv, keyframes.csv, summary.json and the run record `starnav view` reads")
      ->required();
  cmd->add_option("--matcher", o->matcher, "icp, gicp, vgicp, ndt or ndt_mt")->default_str("ndt_mt");
  cmd->add_option("--set", o->sets, "a SLAM parameter key=value (repeatable; docs/parameters.md, \"3D graph SLAM\")")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--matcher-set", o->matcher_sets, "a matcher parameter key=value (repeatable; docs/parameters.md)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--frames", o->frames, "use the first N frames only (0: all)")->default_str("0");
  cmd->add_option("--poses", o->poses, "cloud files: the sensor's reference poses (KITTI 12 or 13 columns, or TUM t x y z qx qy qz qw; default: poses.txt beside them)");
  cmd->add_option("--mount", o->mount, "X,Y,Z,ROLL,PITCH,YAW: the sensor on the base (m, degrees; Z its height above the floor), overriding sensor.yaml and /tf_static");
  cmd->add_option("--rate-hz", o->rate_hz, "cloud files without times.txt or timed poses: the frame rate")->default_str("10");
  cmd->add_option("--cloud-topic", o->cloud_topic, "bag: the sensor_msgs/PointCloud2 topic (needed when there are several)");
  cmd->add_option("--odom-topic", o->odom_topic, "bag: the nav_msgs/Odometry topic of the wheel odometry (the registration's guess)");
  cmd->add_option("--truth-topic", o->truth_topic, "bag: a nav_msgs/Odometry topic with the base's true pose (for the errors)");
  cmd->add_option("--map-resolution-m", o->map_resolution_m, "the octree's voxel size")->default_str("0.05");
  cmd->add_option("--band-m", o->band_min_m, "the 2D grid's height band above the floor: its bottom")->default_str("0.1");
  cmd->add_option("--band-top-m", o->band_max_m, "... and its top (the robot's height)")->default_str("0.6");
  cmd->add_option("--plan-to", o->plan_to, "X,Y (map frame: the floor under the first frame's sensor is the origin, x its heading): plan with the improved A* (ou2022) on the 2D grid from the first key frame");
  cmd->add_option("--inflation-m", o->inflation_m, "the planner's inflation radius")->default_str("0.35");
  cmd->add_flag("--no-map", o->no_map, "skip the octree, the 2D grid and the picture");
  cmd->add_flag("--json", o->json, "print the JSON summary");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_slam3d(*o, ctx); });
}

}  // namespace starnav::cli
