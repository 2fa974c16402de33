#pragma once
// The local half of a graph SLAM (the front end of Cartographer's design, Hess et al. 2016): each
// scan is matched, from the odometry's guess, against a local map of the scans kept just before
// it, with the scan matcher (the correlative one); the scan is kept (a node) when the robot has moved far enough
// since the last node, and the local map is the likelihood field of the last `window_nodes`
// nodes' points. Every scan gets a pose (the benchmark's relations refer to any scan); drift
// accumulates without loop closure, which the global half (pose graph, loop closure) removes.
// The matcher is the ScanMatcher role, given by whoever builds the local SLAM (it must prepare
// references: the local map is one, matched in the matcher's configured window).
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/logs/robot_log.hpp"
#include "starnav/sense/sensor_messages.hpp"
#include "starnav/slam/correlative_scan_matcher.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/scan_matcher.hpp"

namespace starnav {

struct LocalSlamConfig {
  double min_range_m = 0.1;          // readings used by the matcher
  double max_range_m = 30.0;
  double voxel_m = 0.05;             // scan points thinned to one per voxel before matching
  double node_distance_m = 0.2;      // keep a scan as a node after this much motion ...
  double node_angle_rad = 0.0873;    // ... or this much turning (5 deg)
  int window_nodes = 60;             // nodes in the local map
  int rebuild_every = 2;             // nodes between rebuilds of the local map
  void validate() const;
};
const ParamTable<LocalSlamConfig>& local_slam_params();

// The settings the local SLAM's correlative matcher is tuned with where they differ from the
// matcher's own defaults: a prior toward the odometry's guess in position (10 per m^2: a near-tie
// along a corridor goes to the guess), none in yaw (walls fix the yaw better than slipping wheels
// do). Graph SLAM's factory gives these to the matcher before the user's `local.matcher.*`.
const std::vector<ParamSetting>& local_slam_matcher_settings();
// The correlative matcher's configuration with them (its window, field resolution and spread).
CorrelativeMatcherConfig local_slam_matcher_config();

// The front end, one scan at a time: the local map's frame is the odometry's start, never
// corrected by the back end (which keeps its own map frame).
class LocalSlam {
 public:
  // `matcher` (which must prepare references) must outlive the local SLAM.
  LocalSlam(const LocalSlamConfig& config, const ScanMatcher& matcher);
  struct Step {
    Pose2 pose;          // base_link in the local frame
    bool node = false;   // kept: its points join the local map
    bool matched = false, attempted = false;
  };
  // `points`: the scan's points in its sensor frame (scan_points); `odometry` the odometry pose at
  // its time `stamp_us`; `mount` the sensor's pose on the base.
  //
  // The guess is the last pose moved by the odometry's increment. Where that increment and the
  // motion at the last scans' velocity differ by more than half the search window (odometry that
  // froze, then jumped: mit-csail has both), the scan is also matched from the constant-velocity
  // guess, and the better score wins.
  Step add(const std::vector<Vec2>& points, const Pose2& odometry, const Pose2& mount, std::int64_t stamp_us);
  const LocalSlamConfig& config() const { return c_; }

 private:
  LocalSlamConfig c_;
  const ScanMatcher& matcher_;
  MatchWindow window_;  // the matcher's configured window
  std::optional<Pose2> last_odom_, last_pose_, last_node_pose_;
  std::optional<Pose2> velocity_;  // the last scans' motion per second (body frame)
  std::int64_t last_stamp_us_ = 0;
  std::deque<std::vector<Vec2>> nodes_;  // world points of the last nodes
  std::unique_ptr<ScanReference> local_map_;
  int since_rebuild_ = 0;
};

struct LocalSlamResult {
  std::vector<TrajectoryPose> poses;  // one base pose per scan with a usable odometry, in scan order
  std::vector<std::size_t> nodes;     // indices into poses of the kept scans
  std::size_t matched = 0, unmatched = 0;  // scans the matcher converged on, or not (odometry kept)
  double cpu_s = 0.0;                 // thread CPU time of the run
};

// Runs over every scan of `log` in file order with `matcher`. Scans without an odometry pose
// (neither in the line nor interpolated) are left out. `progress(done, total)` is called every 100
// scans.
LocalSlamResult run_local_slam(const RobotLog& log, const LocalSlamConfig& config, const ScanMatcher& matcher,
                               const std::function<void(std::size_t, std::size_t)>& progress = {});

// The points of a scan in its sensor frame: returned readings within [min, max] range, thinned
// to one per voxel (the first in beam order).
std::vector<Vec2> scan_points(const ScanMessage& scan, double min_range_m, double max_range_m, double voxel_m);

}  // namespace starnav
