#include "log_flags.hpp"

#include "cli_util.hpp"
#include "starnav/core/error.hpp"

namespace starnav::cli {

void add_log_read_flags(CLI::App* cmd, LogReadFlags& f, LogFlagSet set) {
  cmd->add_option("--scan-topic", f.scan_topic, "bags: the sensor_msgs/LaserScan topic (default: the only one)");
  cmd->add_option("--odom-topic", f.odom_topic,
                  "bags: the nav_msgs/Odometry topic, or a tf2_msgs/TFMessage topic whose odom -> base_link transforms\n"
                  "are the odometry (default: the only Odometry topic, else /tf)");
  cmd->add_option("--imu-topic", f.imu_topic, "bags: the sensor_msgs/Imu topic (default: the only one)");
  cmd->add_option("--truth-topic", f.truth_topic,
                  "bags: a ground-truth topic (nav_msgs/Odometry, geometry_msgs/PoseStamped or PoseWithCovarianceStamped;\n"
                  "default: none)");
  if (set == LogFlagSet::TopicsAndScans) {
    f.range_max_opt = cmd->add_option("--range-max", f.range_max,
                                      "readings at or beyond M metres returned nothing (default: the log's own, or inferred\n"
                                      "for FLASER logs: docs/slam.md)");
    cmd->add_flag("--flaser-angles", f.flaser_angles,
                  "bags converted from CARMEN FLASER logs: FLASER's beam angles instead of the converter's (docs/slam.md)");
  }
}

LogReadOptions log_read_options(const LogReadFlags& f) {
  LogReadOptions o;
  o.scan_topic = f.scan_topic;
  o.odom_topic = f.odom_topic;
  o.imu_topic = f.imu_topic;
  o.truth_topic = f.truth_topic;
  if (f.range_max_opt && f.range_max_opt->count() > 0) {
    if (!(f.range_max > 0)) throw Error("expected metres > 0", {}, 0, "--range-max");
    o.range_max_m = f.range_max;
  }
  o.flaser_beam_angles = f.flaser_angles;
  o.warn = print_warning;
  return o;
}

}  // namespace starnav::cli
