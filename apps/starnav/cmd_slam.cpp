// starnav slam: 2D SLAM on robot logs and its evaluation (docs/slam.md).
//
//   starnav slam eval TRAJECTORY RELATIONS [--laser-offset X[,Y[,YAW_DEG]] | --log LOG] [--json]
//   starnav slam odometry LOG --out TRAJECTORY.csv [--force]     (the odometry-only baseline)
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/relative_pose_error.hpp"

namespace starnav::cli {

namespace {

struct SlamEvalOptions {
  std::string trajectory;
  std::string relations;
  std::string laser_offset;
  std::string log;
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
  if (!o.log.empty()) offset = read_robot_log(o.log).laser_in_base.value_or(Pose2());
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
  std::string out;
  bool force = false;
};

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
  eval->add_flag("--json", e->json, "one JSON object instead of text");
  eval->callback([e, &ctx] { run_slam_eval(*e, ctx); });

  auto od = std::make_shared<SlamOdometryOptions>();
  auto* odo = slam->add_subcommand("odometry", "the odometry-only trajectory of a log (one base pose per scan), the baseline SLAM improves on");
  odo->add_option("LOG", od->log, "the log")->required();
  odo->add_option("--out", od->out, "trajectory CSV t_s,x_m,y_m,yaw_rad")->required();
  odo->add_flag("--force", od->force, "overwrite --out");
  odo->callback([od, &ctx] {
    check_output_path(od->out, od->force, "--out");
    const std::vector<TrajectoryPose> t = odometry_trajectory(read_robot_log(od->log));
    if (t.empty()) throw Error("no scan has an odometry pose", od->log, 0, "LOG");
    write_text_file(od->out, trajectory_csv(t), "--out");
    std::cout << "wrote " << od->out << " (" << t.size() << " poses)\n";
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
