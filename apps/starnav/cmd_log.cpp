// starnav log info: what a robot log holds (CARMEN .clf / .log, gzipped or not; the text extracts
// of ODOMETRY / LASERSCAN lines; ROS 1 bags; ROS 2 recordings: MCAP, SQLite3, rosbag2 folders), read as starnav's SLAM and mapping read it
// (logs/log_file.hpp, docs/slam.md).
//
//   starnav log info FILE|BAG_FOLDER [--json] [--range-max M] [--scan-topic T] [--odom-topic T] [--imu-topic T]
//                    [--truth-topic T] [--flaser-angles]
#include <iostream>
#include <memory>
#include <string>

#include "cli_util.hpp"
#include "commands.hpp"
#include "log_flags.hpp"
#include "starnav/core/error.hpp"
#include "starnav/logs/log_file.hpp"

namespace starnav::cli {

namespace {

struct LogInfoOptions {
  std::string file;
  bool json = false;
  LogReadFlags read;
};

}  // namespace

void register_log_commands(CLI::App& app, Context& ctx) {
  auto* log = app.add_subcommand("log", "robot logs: CARMEN, text extracts, ROS 1 bags, ROS 2 recordings (MCAP, SQLite3)");
  log->require_subcommand(1);
  auto o = std::make_shared<LogInfoOptions>();
  auto* info = log->add_subcommand("info", "what a log holds: scans, beams, odometry, time span, laser pose, a bag's topics");
  info->add_option("FILE", o->file, "the log (.clf, .log, .gz, .txt, .bag, .mcap, .db3, or a rosbag2 folder)")->required();
  info->add_flag("--json", o->json, "one JSON object instead of text");
  add_log_read_flags(info, o->read);
  info->callback([o, &ctx] {
    LogReadOptions options = log_read_options(o->read);
    options.allow_no_scans = true;  // a bag's topics are worth listing without scans
    const RobotLog log = read_robot_log(o->file, options);
    std::cout << (o->json ? log_info_json(log) : log_info_text(log));
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
