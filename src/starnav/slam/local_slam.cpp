#include "starnav/slam/local_slam.hpp"

#include <cmath>
#include <deque>
#include <unordered_set>

#include "starnav/core/angle.hpp"
#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"

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
    t.real("matcher.resolution_m", [](C& c) -> double& { return c.matcher.resolution_m; }, closed(0.005, 1.0), "m",
           "the matcher's field cell");
    t.real("matcher.sigma_m", [](C& c) -> double& { return c.matcher.sigma_m; }, closed(0.005, 1.0), "m",
           "the matcher's likelihood spread");
    t.real("matcher.window_linear_m", [](C& c) -> double& { return c.matcher.window_linear_m; }, closed(0.0, 10.0), "m",
           "the matcher's search window, +- in x and y");
    t.real("matcher.window_angular_deg", [](C& c) -> double& { return c.matcher.window_angular_rad; }, closed(0.0, 180.0),
           "deg", "the matcher's search window, +- in yaw", kPi / 180.0);
    t.real("matcher.min_score", [](C& c) -> double& { return c.matcher.min_score; }, closed(0.0, 1.0), "",
           "least score to take the matcher's pose");
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
  matcher.validate();
}

std::vector<Vec2> scan_points(const LogScan& scan, double min_range_m, double max_range_m, double voxel_m) {
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

LocalSlamResult run_local_slam(const RobotLog& log, const LocalSlamConfig& c,
                               const std::function<void(std::size_t, std::size_t)>& progress) {
  c.validate();
  const double t0 = thread_cpu_s();
  CorrelativeScanMatcher matcher(c.matcher);
  const Pose2 mount = log.laser_in_base.value_or(Pose2());
  const std::vector<LogOdometry> odometry = sort_by_time(log.odometry);
  LocalSlamResult out;
  std::optional<Pose2> last_odom, last_pose, last_node_pose;
  std::deque<std::vector<Vec2>> window;  // world points of the last nodes
  CorrelativeScanMatcher::Field field;
  bool have_field = false;
  int since_rebuild = 0;
  const double margin = 3 * c.matcher.sigma_m + c.matcher.window_linear_m + c.matcher.resolution_m;
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    if (progress && k % 100 == 0) progress(k, log.scans.size());
    const LogScan& scan = log.scans[k];
    const std::optional<Pose2> odom = scan_odometry(scan, odometry);
    if (!odom) continue;
    // The guess: the last pose moved by the odometry's increment since.
    Pose2 pose = last_pose ? last_pose->compose(last_odom->inverse().compose(*odom)) : *odom;
    const std::vector<Vec2> points = scan_points(scan, c.min_range_m, c.max_range_m, c.voxel_m);
    if (have_field && points.size() >= 10) {
      const ScanMatch m = matcher.match_to_field(field, points, pose.compose(mount));
      if (m.converged) {
        pose = m.transform.compose(mount.inverse());
        ++out.matched;
      } else {
        ++out.unmatched;
      }
    }
    last_pose = pose;
    last_odom = odom;
    out.poses.push_back({scan.stamp_us, pose});
    const bool node = !last_node_pose || (last_node_pose->inverse().compose(pose).translation().norm() >= c.node_distance_m) ||
                      std::abs(wrap_angle(pose.yaw - last_node_pose->yaw)) >= c.node_angle_rad;
    if (!node || points.empty()) continue;
    last_node_pose = pose;
    out.nodes.push_back(out.poses.size() - 1);
    std::vector<Vec2> world;
    world.reserve(points.size());
    const Pose2 sensor = pose.compose(mount);
    for (const Vec2& p : points) world.push_back(sensor.transform(p));
    window.push_back(std::move(world));
    if (static_cast<int>(window.size()) > c.window_nodes) window.pop_front();
    if (!have_field || ++since_rebuild >= c.rebuild_every) {
      since_rebuild = 0;
      std::vector<Vec2> all;
      for (const auto& w : window) all.insert(all.end(), w.begin(), w.end());
      Vec2 lo = all.front(), hi = all.front();
      for (const Vec2& p : all) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      field = matcher.field_of_points(all, lo - Vec2::Constant(margin), hi + Vec2::Constant(margin));
      have_field = true;
    }
  }
  if (progress) progress(log.scans.size(), log.scans.size());
  out.cpu_s = thread_cpu_s() - t0;
  return out;
}

}  // namespace starnav
