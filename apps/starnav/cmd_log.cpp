// starnav log info: what a robot log holds (CARMEN .clf / .log, gzipped or not; the text extracts
// of ODOMETRY / LASERSCAN lines; ROS 1 bags), read as starnav's SLAM and mapping read it
// (logs/log_file.hpp, docs/slam.md).
//
//   starnav log info FILE [--json] [--range-max M] [--scan-topic T] [--odom-topic T] [--flaser-angles]
#include <iostream>
#include <memory>
#include <string>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/logs/log_file.hpp"

namespace starnav::cli {

namespace {

struct LogInfoOptions {
  std::string file;
  bool json = false;
  double range_max = 0.0;
  CLI::Option* range_max_opt = nullptr;
  std::string scan_topic;
  std::string odom_topic;
  bool flaser_angles = false;
};

}  // namespace

void register_log_commands(CLI::App& app, Context& ctx) {
  auto* log = app.add_subcommand("log", "robot logs: CARMEN, text extracts, ROS 1 bags");
  log->require_subcommand(1);
  auto o = std::make_shared<LogInfoOptions>();
  auto* info = log->add_subcommand("info", "what a log holds: scans, beams, odometry, time span, laser pose, skipped lines");
  info->add_option("FILE", o->file, "the log (.clf, .log, .gz, .txt, .bag)")->required();
  info->add_flag("--json", o->json, "one JSON object instead of text");
  o->range_max_opt = info->add_option("--range-max", o->range_max,
                                      "readings at or beyond M metres returned nothing (default: the log's own, or "
                                      "inferred for FLASER logs: docs/slam.md)");
  info->add_option("--scan-topic", o->scan_topic, "bags: the sensor_msgs/LaserScan topic (default: the only one)");
  info->add_option("--odom-topic", o->odom_topic, "bags: the nav_msgs/Odometry topic (default: the only one)");
  info->add_flag("--flaser-angles", o->flaser_angles,
                 "bags converted from CARMEN FLASER logs: FLASER's beam angles instead of the converter's (docs/slam.md)");
  info->callback([o, &ctx] {
    LogReadOptions options;
    if (o->range_max_opt->count() > 0) {
      if (!(o->range_max > 0)) throw Error("expected metres > 0", {}, 0, "--range-max");
      options.range_max_m = o->range_max;
    }
    options.scan_topic = o->scan_topic;
    options.odom_topic = o->odom_topic;
    options.flaser_beam_angles = o->flaser_angles;
    options.warn = print_warning;
    const RobotLog log = read_robot_log(o->file, options);
    std::cout << (o->json ? log_info_json(log) : log_info_text(log));
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
