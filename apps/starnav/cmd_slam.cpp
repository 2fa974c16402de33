// starnav slam: 2D SLAM on robot logs and its evaluation (docs/slam.md).
//
//   starnav slam eval TRAJECTORY RELATIONS [--laser-offset X[,Y[,YAW_DEG]] | --log LOG] [--json]
//   starnav slam odometry LOG --out TRAJECTORY.csv [--force]     (the odometry-only baseline)
//   starnav slam run LOG --out DIR [--set key=value ...] [--relations FILE] [--flaser-angles] [--json] [--force]
//   (every command reading a log takes log_flags.hpp's --scan-topic, --odom-topic, --imu-topic, --truth-topic)
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "log_flags.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/harness/slam_report.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/relative_pose_error.hpp"
#include "starnav/slam/trajectory_error.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;

struct SlamEvalOptions {
  std::string trajectory;
  std::string relations;
  std::string laser_offset;
  std::string log;
  LogReadFlags read;
  bool json = false;
};

Pose2 parse_offset(const std::string& text) {
  const std::size_t commas = static_cast<std::size_t>(std::count(text.begin(), text.end(), ','));
  if (commas > 2) throw Error("expected X[,Y[,YAW_DEG]], got '" + printable(text, 60) + "'", {}, 0, "--laser-offset");
  const std::vector<double> v = parse_number_list(text, "--laser-offset", commas + 1, "X[,Y[,YAW_DEG]] (metres, degrees)");
  return Pose2(v[0], v.size() > 1 ? v[1] : 0.0, v.size() > 2 ? deg_to_rad(v[2]) : 0.0);
}

void run_slam_eval(const SlamEvalOptions& o, Context& ctx) {
  if (!o.laser_offset.empty() && !o.log.empty()) throw Error("give --laser-offset or --log, not both", {}, 0, "--log");
  std::optional<Pose2> offset;
  if (!o.laser_offset.empty()) offset = parse_offset(o.laser_offset);
  if (!o.log.empty()) {
    LogReadOptions read = log_read_options(o.read);
    read.allow_no_scans = true;  // the mount may come from a bag's /tf_static alone
    offset = read_robot_log(o.log, read).laser_in_base.value_or(Pose2());
  }
  const std::vector<TrajectoryPose> trajectory = read_trajectory_csv(o.trajectory);
  const std::vector<PoseRelation> relations = read_relations(o.relations);
  const RelativePoseError base = relative_pose_error(trajectory, relations);
  std::optional<RelativePoseError> laser;
  if (offset) laser = relative_pose_error(trajectory, relations, *offset);
  std::cout << (o.json ? rpe_json(base, laser, offset.value_or(Pose2())) : rpe_text(base, laser, offset.value_or(Pose2())));
  ctx.exit_code = 0;
}

struct SlamOdometryOptions {
  std::string log;
  LogReadFlags read;
  std::string out;
  bool force = false;
};

struct SlamRunOptions {
  std::string log;
  std::string out;
  std::vector<std::string> sets;
  std::string relations;
  std::string method = "graph";
  LogReadFlags read;
  bool json = false;
  bool force = false;
  bool quiet = false;
};

void run_slam(const SlamRunOptions& o, Context& ctx) {
  SlamRunRequest q;
  q.log = o.log;
  q.read = log_read_options(o.read);
  q.method = o.method;
  q.settings = parse_set_options(o.sets);
  q.relations = o.relations;
  if (fs::exists(o.out) && !fs::is_directory(o.out)) throw Error("is not a directory", o.out, 0, "--out");
  const fs::path dir(o.out);
  if (fs::exists(dir))
    for (const std::string& f : slam_output_files())
      if (fs::exists(dir / f) && !o.force) throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
  const OutputFolder out_folder(o.out, "--out");
  const OutputListing listing(o.out);
  ProgressBar bar("slam", 1, o.quiet);
  const SlamRunResult r = run_slam_on_file(q, [&](std::size_t done, std::size_t total) {
    bar.set_total(total);
    bar.update(done, "scans");
  });
  bar.finish();
  write_slam_outputs(r, o.out);
  if (o.json) {
    std::cout << slam_summary_json(r).dump() << "\n";
  } else {
    std::cout << slam_summary_text(r);
  }
  listing.print(o.json, o.quiet);
  ctx.exit_code = 0;
}

}  // namespace

void register_slam_commands(CLI::App& app, Context& ctx) {
  auto* slam = app.add_subcommand("slam", "2D SLAM on robot logs and its evaluation (docs/slam.md)");
  slam->require_subcommand(1);
  auto e = std::make_shared<SlamEvalOptions>();
  auto* eval = slam->add_subcommand(
      "eval",
      "relative-pose error (Kuemmerle et al. 2009) of a trajectory against a benchmark relation file: translation (m)\n"
      "and rotation (deg) mean, sd, max and count, for the base poses and, with a laser offset, for the laser's");
  eval->add_option("TRAJECTORY", e->trajectory, "CSV t_s,x_m,y_m,yaw_rad, one base pose per scan")->required();
  eval->add_option("RELATIONS", e->relations, "relation file: t_i t_j dx dy dz droll dpitch dyaw per line")->required();
  eval->add_option("--laser-offset", e->laser_offset, "the laser's mount on the base, X[,Y[,YAW_DEG]]: also evaluate the laser poses");
  eval->add_option("--log", e->log, "take the laser's mount from this log (PARAM robot_frontlaser_offset, /tf_static)");
  add_log_read_flags(eval, e->read, LogFlagSet::Topics);
  eval->add_flag("--json", e->json, "one JSON object instead of text");
  eval->callback([e, &ctx] { run_slam_eval(*e, ctx); });

  auto ro = std::make_shared<SlamRunOptions>();
  auto* run = slam->add_subcommand("run", "2D SLAM on a robot log: local matching, submaps, loop closure, pose graph (docs/slam.md);\n"
                                          "writes trajectory.csv, map.yaml + pgm, pose_graph.json, map.png, summary.json");
  run->add_option("LOG", ro->log, "the log (CARMEN .clf/.gz, ROS 1 .bag, ROS 2 .mcap/.db3/folder, text extract)")->required();
  run->add_option("--out", ro->out, "output folder")->required();
  run->add_option("--set", ro->sets, "a parameter key=value (repeatable; keys in docs/slam.md)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  run->add_option("--relations", ro->relations, "also evaluate against this benchmark relation file");
  run->add_option("--method", ro->method, "the SLAM method (starnav params --role slam)")->default_str("graph");
  add_log_read_flags(run, ro->read);
  run->add_flag("--json", ro->json, "print the summary as one JSON object");
  run->add_flag("--force", ro->force, "overwrite the outputs in --out");
  run->add_flag("--quiet", ro->quiet, "no progress on stderr");
  run->callback([ro, &ctx] { run_slam(*ro, ctx); });

  struct WallsOptions {
    std::string truth;
    std::vector<std::string> built;
    std::size_t count = 12;
    bool json = false;
  };
  auto wo = std::make_shared<WallsOptions>();
  auto* walls = slam->add_subcommand("walls",
                                     "distances between opposite walls in built maps against the true map (the paper's Tables 2-3):\n"
                                     "free runs between two walls along rows and columns of the true map that every built map saw,\n"
                                     "measured again in each (e.g. the odometry's map and the SLAM map side by side)");
  walls->add_option("TRUTH", wo->truth, "the true map (map_server YAML)")->required();
  walls->add_option("BUILT", wo->built, "built maps (map_server YAML) in the true map's frame")->required();
  walls->add_option("--count", wo->count, "distances, spread over the map (default 12)");
  walls->add_flag("--json", wo->json, "one JSON object instead of the table");
  walls->callback([wo, &ctx] {
    if (wo->count < 1 || wo->count > 10000) throw Error("expected a count in [1, 10000]", {}, 0, "--count");
    const OccupancyGrid truth = read_ros_map(wo->truth);
    std::vector<OccupancyGrid> built;
    for (const std::string& b : wo->built) built.push_back(read_ros_map(b));
    std::vector<const OccupancyGrid*> maps;
    std::vector<std::string> names;
    for (std::size_t i = 0; i < built.size(); ++i) maps.push_back(&built[i]), names.push_back(fs::path(wo->built[i]).stem().string());
    WallDistanceOptions options;
    options.count = wo->count;
    const std::vector<WallDistance> probes = wall_distances(truth, maps, options);
    if (probes.empty()) throw Error("no free run of 1 to 20 m between two walls of the true map was seen by every built map", wo->truth, 0, "BUILT");
    std::cout << (wo->json ? wall_distances_json(probes, names) : wall_distances_text(probes, names));
    ctx.exit_code = 0;
  });

  auto od = std::make_shared<SlamOdometryOptions>();
  auto* odo = slam->add_subcommand("odometry", "the odometry-only trajectory of a log (one base pose per scan), the baseline SLAM improves on");
  odo->add_option("LOG", od->log, "the log")->required();
  odo->add_option("--out", od->out, "trajectory CSV t_s,x_m,y_m,yaw_rad")->required();
  odo->add_flag("--force", od->force, "overwrite --out");
  add_log_read_flags(odo, od->read);
  odo->callback([od, &ctx] {
    check_output_path(od->out, od->force, "--out");
    check_distinct_files({{od->log, "LOG", false}, {od->out, "--out"}});
    const std::vector<TrajectoryPose> t = odometry_trajectory(read_robot_log(od->log, log_read_options(od->read)));
    if (t.empty()) throw Error("no scan has an odometry pose", od->log, 0, "LOG");
    write_text_file(od->out, trajectory_csv(t), "--out");
    std::cout << "wrote " << od->out << " (" << t.size() << " poses)\n";
    ctx.exit_code = 0;
  });
  register_slam_benchmark_commands(slam, ctx);
}

}  // namespace starnav::cli
