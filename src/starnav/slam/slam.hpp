#pragma once
// The SLAM role: scans and odometry in, a trajectory and a map out, incrementally. Each call to
// add() gives one scan with the odometry pose at its time and the laser's mount; trajectory() is
// one base pose per scan added (map frame), revised when the back end optimises (loop closures);
// map() renders the occupancy grid of the kept scans at their current poses; graph() is the pose
// graph behind the trajectory (empty for methods without one).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/logs/robot_log.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/occupancy_mapping.hpp"

namespace starnav {

enum class SlamEdgeKind : std::uint8_t { Local, Loop, Global };
std::string slam_edge_kind_name(SlamEdgeKind kind);

struct SlamGraphEdge {
  std::size_t from = 0, to = 0;  // node indices
  SlamEdgeKind kind = SlamEdgeKind::Local;
  Pose2 measurement;  // `to` in the frame of `from`
  double score = 0.0; // the matcher's score (loop and global closures)
};

struct SlamGraph {
  std::vector<TrajectoryPose> nodes;  // base poses of the kept scans, optimised
  std::vector<SlamGraphEdge> edges;
  std::vector<std::size_t> submap_anchors;  // node index of each submap's frame
  std::size_t closures() const;              // edges that are not Local
};

class Slam {
 public:
  virtual ~Slam() = default;
  virtual std::string_view name() const = 0;
  // One scan; returns true when it was kept (a node of the trajectory).
  virtual bool add(const LogScan& scan, const Pose2& odometry, const Pose2& laser_in_base) = 0;
  // After the last scan: the final optimisation.
  virtual void finish() {}
  virtual std::vector<TrajectoryPose> trajectory() const = 0;
  virtual OccupancyGrid map(const OccupancyMappingParams& params) const = 0;
  virtual SlamGraph graph() const { return {}; }
  // Named counters and times of the run so far (method-specific; "cpu_s" totals in seconds).
  virtual std::vector<std::pair<std::string, double>> statistics() const { return {}; }
};

struct SlamContext {
  std::string file;
  std::uint64_t seed = 0;
};
using SlamDef = ComponentDef<Slam, SlamContext>;

}  // namespace starnav
