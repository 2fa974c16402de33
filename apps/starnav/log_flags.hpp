#pragma once
// The flags of every command that reads a robot log (log info, map build, slam run, slam odometry,
// slam eval --log, localize), defined once: the topics of a bag that are read (logs/bag_log.hpp)
// and, for the commands that use the scans' ranges, the no-return range and FLASER's beam angles.
#include <CLI/CLI.hpp>

#include <string>

#include "starnav/logs/carmen_log.hpp"

namespace starnav::cli {

struct LogReadFlags {
  std::string scan_topic, odom_topic, imu_topic, truth_topic;
  double range_max = 0.0;
  CLI::Option* range_max_opt = nullptr;  // null: the command has no --range-max
  bool flaser_angles = false;
};

enum class LogFlagSet {
  Topics,        // the bag's topics only (the laser's mount: slam eval --log)
  TopicsAndScans  // also --range-max and --flaser-angles
};

void add_log_read_flags(CLI::App* cmd, LogReadFlags& flags, LogFlagSet set = LogFlagSet::TopicsAndScans);
// The reader's options; Error naming the flag for a bad value.
LogReadOptions log_read_options(const LogReadFlags& flags);

}  // namespace starnav::cli
