// starnav map build: an occupancy map from a robot log with known poses (slam/log_mapping.hpp,
// docs/slam.md), saved as map_server YAML + PGM.
//
//   starnav map build LOG --poses log|odometry|truth|TRAJECTORY.csv --out map.yaml
//                     [--resolution R] [--set key=value ...] [--range-max M] [--flaser-angles] [--scan-topic T]
//                     [--odom-topic T] [--imu-topic T] [--truth-topic T]
//                     [--trajectory-out FILE.csv] [--json] [--force]
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "log_flags.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/slam/log_mapping.hpp"

namespace starnav::cli {

namespace {

struct MapBuildOptions {
  std::string log;
  std::string poses = "log";
  std::string out;
  std::string trajectory_out;
  double resolution = OccupancyMappingParams{}.resolution_m;
  std::vector<std::string> sets;
  LogReadFlags read;
  bool json = false;
  bool force = false;
};

void run_map_build(const MapBuildOptions& o, Context& ctx) {
  OccupancyMappingParams params;
  params.resolution_m = o.resolution;
  const std::vector<ParamSetting> settings = parse_set_options(o.sets);
  params = configured(occupancy_mapping_params(), settings, {}, params);
  try {
    params.validate();
  } catch (const Error& e) {
    if (e.field() == "resolution_m") throw Error(e.message(), {}, 0, "--resolution");
    rethrow_at_setting(e, settings);
  }
  if (!o.out.empty()) {
    for (const std::string& f : map_output_files(o.out, MapFormat::RosMap)) check_output_path(f, o.force, "--out");
  }
  if (!o.trajectory_out.empty()) check_output_path(o.trajectory_out, o.force, "--trajectory-out");
  std::vector<CommandFile> files{{o.log, "LOG", false}};
  if (o.poses != "log" && o.poses != "odometry" && o.poses != "truth") files.push_back({o.poses, "--poses", false});
  add_map_files(files, o.out, MapFormat::RosMap, std::nullopt, "--out");
  if (!o.trajectory_out.empty()) files.push_back({o.trajectory_out, "--trajectory-out"});
  check_distinct_files(files);
  const RobotLog log = read_robot_log(o.log, log_read_options(o.read));
  LogMapResult r;
  if (o.poses == "log") r = map_log(log, LogPoseSource::Log, params);
  else if (o.poses == "odometry") r = map_log(log, LogPoseSource::Odometry, params);
  else if (o.poses == "truth") r = map_log(log, LogPoseSource::Truth, params);
  else r = map_log(log, read_trajectory_csv(o.poses), params);
  if (r.scans_mapped == 0) throw Error("no scan of the log has a pose in " + o.poses, o.log, 0, "--poses");
  write_ros_map(r.grid, o.out);
  if (!o.trajectory_out.empty()) write_text_file(o.trajectory_out, trajectory_csv(r.base_poses), "--trajectory-out");
  const OccupancyCounts counts = r.grid.counts();
  if (o.json) {
    nlohmann::ordered_json j;
    j["map"] = o.out;
    j["scans_mapped"] = r.scans_mapped;
    j["scans_without_pose"] = r.scans_without_pose;
    j["width"] = r.grid.width();
    j["height"] = r.grid.height();
    j["resolution_m"] = r.grid.resolution();
    j["origin_m"] = {r.grid.origin().x, r.grid.origin().y};
    j["free"] = counts.free;
    j["occupied"] = counts.occupied;
    j["unknown"] = counts.unknown;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "mapped " << r.scans_mapped << " scans" << (r.scans_without_pose ? " (" + std::to_string(r.scans_without_pose) + " without a pose)" : "")
              << " into " << r.grid.width() << " x " << r.grid.height() << " cells of " << r.grid.resolution() << " m: "
              << counts.occupied << " occupied, " << counts.free << " free\nwrote " << o.out << "\n";
  }
  ctx.exit_code = 0;
}

}  // namespace

void register_map_build(CLI::App& map, Context& ctx) {
  auto o = std::make_shared<MapBuildOptions>();
  auto* cmd = map.add_subcommand("build", "an occupancy map from a robot log with known poses (map_server YAML + PGM)");
  cmd->add_option("LOG", o->log, "the log (CARMEN .clf/.log/.gz, ROS 1 .bag, ROS 2 .mcap/.db3/folder, text extract)")->required();
  cmd->add_option("--poses", o->poses,
                  "log (the laser poses its lines carry, e.g. a corrected log's; else odometry), odometry, truth "
                  "(TRUEPOS), or a trajectory CSV t_s,x_m,y_m,yaw_rad (default log)");
  cmd->add_option("--out", o->out, "the map's YAML (the PGM beside it)")->required();
  cmd->add_option("--resolution", o->resolution, "cell size, metres (default 0.05)");
  cmd->add_option("--set", o->sets, "a mapping parameter key=value (repeatable; keys in docs/slam.md)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  add_log_read_flags(cmd, o->read);
  cmd->add_option("--trajectory-out", o->trajectory_out, "also write the base poses of the mapped scans (CSV)");
  cmd->add_flag("--json", o->json, "one JSON object instead of text");
  cmd->add_flag("--force", o->force, "overwrite existing outputs");
  cmd->callback([o, &ctx] { run_map_build(*o, ctx); });
}

}  // namespace starnav::cli
