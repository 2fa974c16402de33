#include "starnav/harness/robot_log_recorder.hpp"

#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/encoder_odometry.hpp"

namespace starnav {

namespace {

std::int64_t stamp_us(double t_s) { return static_cast<std::int64_t>(std::llround(t_s * 1e6)); }

// The line number the next reading gets, counting every reading recorded so far.
std::size_t next_source_index(const RobotLog& log) { return log.odometry.size() + log.scans.size() + log.truth.size() + 1; }

}  // namespace

bool RobotLogRecorder::can_record(const ScenarioSpec& spec) {
  return spec.lidar && spec.lidar->config.lines() == 1 && spec.encoders.has_value();
}

RobotLogRecorder::RobotLogRecorder(Simulation& sim) : log_(std::make_shared<RobotLog>()) {
  const ScenarioSpec& spec = sim.spec();
  if (!can_record(spec)) throw Error("needs a 2D LiDAR (one line) and wheel encoders to record a robot log", spec.file, 0, "sensors");
  const LidarConfig& lidar = spec.lidar->config;
  log_->path = "log.clf";
  log_->format = "carmen";
  log_->laser_in_base = lidar.mount.to_pose2();
  log_->params["simulated_from"] = spec.file;
  auto last = std::make_shared<LogOdometry>();
  last->pose = spec.start;
  attach_encoder_odometry(sim, [log = log_, last](const EncoderSample& e, const Pose2& pose) {
    LogOdometry o;
    o.stamp_us = stamp_us(e.t_s);
    o.pose = pose;
    const double dt = static_cast<double>(o.stamp_us - last->stamp_us) * 1e-6;
    if (dt > 0 && !log->odometry.empty()) {
      const Pose2 d = last->pose.inverse().compose(o.pose);
      o.tv_mps = d.x / dt;
      o.rv_radps = wrap_angle(d.yaw) / dt;
    }
    o.source_index = next_source_index(*log);
    *last = o;
    log->odometry.push_back(o);
  });
  const Simulation* s = &sim;
  sim.lidar_feed("lidar").subscribe(SampleStage::Record, [log = log_, s, lidar, last](const LidarScan& scan) {
    LogScan out;
    out.stamp_us = stamp_us(scan.time);
    // Beam i points at +fov/2 - i delta: reversed, the angles increase from -fov/2.
    out.angle_min_rad = lidar.azimuth(scan.beams - 1);
    out.angle_increment_rad = lidar.delta();
    out.range_min_m = lidar.range_min;
    out.range_max_m = lidar.range_max;
    out.ranges_m.resize(static_cast<std::size_t>(scan.beams));
    for (int i = 0; i < scan.beams; ++i) {
      const double r = scan.range(0, scan.beams - 1 - i);
      out.ranges_m[static_cast<std::size_t>(i)] = static_cast<float>(std::isfinite(r) && r < lidar.range_max ? r : lidar.range_max);
    }
    out.source_index = next_source_index(*log);
    log->scans.push_back(std::move(out));
    LogTruePose t;
    t.stamp_us = stamp_us(scan.time);
    t.pose = s->vehicle().state().pose.to_pose2();
    t.odometry = last->pose;
    log->truth.push_back(t);
  });
}

}  // namespace starnav
