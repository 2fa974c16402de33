#include "starnav/slam/local_slam.hpp"

#include <cmath>
#include <deque>
#include <unordered_set>

#include "starnav/core/angle.hpp"
#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/logs/robot_log_source.hpp"

namespace starnav {

const ParamTable<LocalSlamConfig>& local_slam_params() {
  static const ParamTable<LocalSlamConfig> table = [] {
    using C = LocalSlamConfig;
    ParamTable<C> t;
    t.real("min_range_m", &C::min_range_m, closed(0.0, 100.0), "m", "readings nearer than this are not matched");
    t.real("max_range_m", &C::max_range_m, closed(0.1, 1000.0), "m", "readings farther than this are not matched");
    t.real("voxel_m", &C::voxel_m, closed(0.0, 1.0), "m", "scan points thinned to one per voxel of this size (0: all)");
    t.real("node_distance_m", &C::node_distance_m, closed(0.0, 10.0), "m", "motion that makes a scan a node");
    t.real("node_angle_deg", &C::node_angle_rad, closed(0.0, 180.0), "deg", "turning that makes a scan a node", kPi / 180.0);
    t.integer("window_nodes", &C::window_nodes, closed(1, 1000), "", "nodes whose points make the local map");
    t.integer("rebuild_every", &C::rebuild_every, closed(1, 1000), "", "nodes between rebuilds of the local map");
    return t;
  }();
  return table;
}

void LocalSlamConfig::validate() const {
  require(std::isfinite(min_range_m) && min_range_m >= 0 && min_range_m < max_range_m, "min_range_m", "must be >= 0 and below max_range_m");
  require(std::isfinite(max_range_m) && max_range_m <= 1000, "max_range_m", "must be at most 1000 m");
  require(std::isfinite(voxel_m) && voxel_m >= 0 && voxel_m <= 1, "voxel_m", "must be in [0, 1] m");
  require(std::isfinite(node_distance_m) && node_distance_m >= 0, "node_distance_m", "must be >= 0");
  require(std::isfinite(node_angle_rad) && node_angle_rad >= 0, "node_angle_deg", "must be >= 0");
  require(window_nodes >= 1 && window_nodes <= 1000, "window_nodes", "must be in [1, 1000]");
  require(rebuild_every >= 1 && rebuild_every <= 1000, "rebuild_every", "must be in [1, 1000]");
}

const std::vector<ParamSetting>& local_slam_matcher_settings() {
  static const std::vector<ParamSetting> settings = {{"prior_linear_weight", "10", {}, 0, "local.matcher.prior_linear_weight"}};
  return settings;
}

CorrelativeMatcherConfig local_slam_matcher_config() {
  return configured(correlative_matcher_params(), local_slam_matcher_settings(), {});
}

std::vector<Vec2> scan_points(const ScanMessage& scan, double min_range_m, double max_range_m, double voxel_m) {
  std::vector<Vec2> out;
  std::unordered_set<std::uint64_t> seen;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    if (!scan.returned(i)) continue;
    const double r = scan.ranges_m[i];
    if (r < min_range_m || r > max_range_m) continue;
    const double a = scan.angle(i);
    const Vec2 p(r * std::cos(a), r * std::sin(a));
    if (voxel_m > 0) {
      const auto vx = static_cast<std::int32_t>(std::floor(p.x() / voxel_m)), vy = static_cast<std::int32_t>(std::floor(p.y() / voxel_m));
      const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(vx)) << 32) | static_cast<std::uint32_t>(vy);
      if (!seen.insert(key).second) continue;
    }
    out.push_back(p);
  }
  return out;
}

LocalSlam::LocalSlam(const LocalSlamConfig& config, const ScanMatcher& matcher)
    : c_(config), matcher_(matcher), window_(matcher.window()) {
  c_.validate();
  if (!matcher_.supports_reference())
    throw Error("scan matcher '" + std::string(matcher_.name()) + "' prepares no reference to match scans against a local map", {}, 0,
                "matcher");
}

LocalSlam::Step LocalSlam::add(const std::vector<Vec2>& points, const Pose2& odom, const Pose2& mount, std::int64_t stamp_us) {
  Step step;
  const Pose2 odom_increment = last_odom_ ? last_odom_->inverse().compose(odom) : Pose2();
  step.pose = last_pose_ ? last_pose_->compose(odom_increment) : odom;
  const double dt = last_pose_ ? static_cast<double>(stamp_us - last_stamp_us_) * 1e-6 : 0.0;
  std::optional<Pose2> steady;  // the constant-velocity guess, when the odometry disagrees with it
  if (velocity_ && dt > 0 && dt < 2.0) {
    const Pose2 v(velocity_->x * dt, velocity_->y * dt, velocity_->yaw * dt);
    const Pose2 gap = v.inverse().compose(odom_increment);
    if (gap.translation().norm() > 0.5 * window_.linear_m || std::abs(gap.yaw) > 0.5 * window_.angular_rad)
      steady = last_pose_->compose(v);
  }
  if (local_map_ && points.size() >= 10) {
    step.attempted = true;
    ScanMatch m = local_map_->match(points, step.pose.compose(mount));
    if (steady) {
      const ScanMatch alt = local_map_->match(points, steady->compose(mount));
      if (alt.score > m.score) m = alt, step.pose = *steady;
    }
    if (m.converged) {
      step.pose = m.transform.compose(mount.inverse());
      step.matched = true;
    }
  }
  if (last_pose_ && dt > 1e-3) {
    const Pose2 moved = last_pose_->inverse().compose(step.pose);
    velocity_ = Pose2(moved.x / dt, moved.y / dt, moved.yaw / dt);
  }
  if (dt > 1e-3 || !last_pose_) last_stamp_us_ = stamp_us;
  last_pose_ = step.pose;
  last_odom_ = odom;
  const bool node = !last_node_pose_ ||
                    last_node_pose_->inverse().compose(step.pose).translation().norm() >= c_.node_distance_m ||
                    std::abs(wrap_angle(step.pose.yaw - last_node_pose_->yaw)) >= c_.node_angle_rad;
  if (!node || points.empty()) return step;
  step.node = true;
  last_node_pose_ = step.pose;
  std::vector<Vec2> world;
  world.reserve(points.size());
  const Pose2 sensor = step.pose.compose(mount);
  for (const Vec2& p : points) world.push_back(sensor.transform(p));
  nodes_.push_back(std::move(world));
  if (static_cast<int>(nodes_.size()) > c_.window_nodes) nodes_.pop_front();
  if (!local_map_ || ++since_rebuild_ >= c_.rebuild_every) {
    since_rebuild_ = 0;
    std::vector<Vec2> all;
    for (const auto& w : nodes_) all.insert(all.end(), w.begin(), w.end());
    // Scans land up to the window beyond the points that are there.
    local_map_ = matcher_.prepare(all, window_.linear_m, 2);
  }
  return step;
}

LocalSlamResult run_local_slam(const RobotLog& log, const LocalSlamConfig& c, const ScanMatcher& matcher,
                               const std::function<void(std::size_t, std::size_t)>& progress) {
  LocalSlam local(c, matcher);
  const double t0 = thread_cpu_s();
  const Pose2 mount = log.laser_in_base.value_or(Pose2());
  const Pose3 mount3 = log_laser_mount(log);
  LocalSlamResult out;
  for_each_scan_with_odometry(
      log,
      [&](const LogScan& scan, const Pose2& odom) {
        const ScanMessage message = scan_message(scan, mount3, "lidar");
        const LocalSlam::Step step = local.add(scan_points(message, c.min_range_m, c.max_range_m, c.voxel_m), odom, mount, scan.stamp_us);
        out.matched += step.matched;
        out.unmatched += step.attempted && !step.matched;
        out.poses.push_back({scan.stamp_us, step.pose});
        if (step.node) out.nodes.push_back(out.poses.size() - 1);
      },
      progress);
  out.cpu_s = thread_cpu_s() - t0;
  return out;
}

}  // namespace starnav
