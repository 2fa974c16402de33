#pragma once
// The SLAM role, one for 2D and 3D (Cartographer's TrajectoryBuilderInterface idea): sensor
// messages in (sense/sensor_messages.hpp, in time order, as a SensorBus delivers them), a
// trajectory, a map, a pose graph and statistics out, incrementally.
//
//  - Input: on_odometry (the odom -> base pose), then the scan or cloud taken at its time; a method
//    uses the latest odometry it has when a scan arrives (sense/sensor_source.hpp says why that is
//    the odometry at the scan's time for recordings and simulation alike). A method maps planar
//    scans or 3D clouds, which space() says (the typed capability callers ask instead of testing
//    names): a planar method takes on_scan, a 3D method on_cloud; the other call is an Error.
//    on_imu is there for methods that use an IMU (none does yet). finish() after the last message.
//  - trajectory(): one SlamPose per scan or frame the method placed (a planar method places every
//    scan after the first odometry), in the map frame, revised when the back end optimises. Each
//    pose carries both views: the base's planar pose (x, y, yaw) and the sensor's pose in space.
//    A planar method's own view is the planar one (the sensor's is it composed with the mount, at
//    z = 0); a 3D method's own view is the sensor's (the planar one is its base's projection).
//  - map(): a 2D occupancy grid for both (a planar method's kept scans at their poses; a 3D
//    method's octree projected to the grid); map_3d() and keyframes_3d(): the 3D methods' octree
//    and key frames (the clouds at their optimised poses).
//  - graph(): the pose graph behind the trajectory (empty for methods without one): its nodes in
//    the planar view.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "starnav/cloud/octree_map.hpp"
#include "starnav/cloud/point_cloud.hpp"
#include "starnav/cloud/ransac_plane.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sense/sensor_messages.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/occupancy_mapping.hpp"
#include "starnav/slam/scan_matcher.hpp"

namespace starnav {

// What a SLAM method maps: planar scans into a plane, or 3D clouds into space.
enum class SlamSpace : std::uint8_t { Planar, ThreeD };
const char* slam_space_name(SlamSpace space);  // "planar", "3d"

// One pose of a SLAM trajectory, both views (above), in the map frame.
struct SlamPose {
  double t_s = 0.0;            // the scan's or frame's time
  std::int64_t stamp_us = 0;   // the same in whole microseconds (a log's stamp)
  Pose2 base;                  // base_link, planar
  Rigid3 sensor = Rigid3::Identity();  // the sensor that took the scan or cloud
};
// The planar view of a trajectory (trajectory.csv, the benchmark's relations).
std::vector<TrajectoryPose> planar_trajectory(const std::vector<SlamPose>& poses);
// A message time (seconds) in whole microseconds, the nearest; exact back to a log's stamp
// (stamp_us * 1e-6) for every stamp up to the year 2096.
std::int64_t microseconds_of(double t_s);

enum class SlamEdgeKind : std::uint8_t { Local, Loop, Global };
std::string slam_edge_kind_name(SlamEdgeKind kind);

struct SlamGraphEdge {
  std::size_t from = 0, to = 0;  // node indices
  SlamEdgeKind kind = SlamEdgeKind::Local;
  Pose2 measurement;  // `to` in the frame of `from`
  double score = 0.0; // the matcher's score (loop and global closures)
};

struct SlamGraph {
  std::vector<TrajectoryPose> nodes;  // base poses of the kept scans (key frames), optimised
  std::vector<SlamGraphEdge> edges;
  std::vector<std::size_t> submap_anchors;  // node index of each submap's frame
  std::size_t closures() const;              // edges that are not Local
};

// A 3D method's key frame: its cloud (prefiltered, sensor frame) at its optimised sensor pose.
struct Slam3dKeyframe {
  std::size_t frame = 0;  // index of the frame it came from
  double t_s = 0.0;
  Rigid3 pose = Rigid3::Identity();  // the sensor in the map frame (optimised)
  PointCloud cloud;                  // prefiltered, sensor frame
  double accum_distance_m = 0.0;     // travelled before it
  std::optional<Plane3> floor;       // as fitted in its frame
};

// Key frames' clouds at their poses into an octree (rays clear free space): a 3D method's map_3d().
OctreeMap keyframes_octree(const std::vector<Slam3dKeyframe>& keyframes, const OctreeMapConfig& config);

class Slam {
 public:
  virtual ~Slam() = default;
  virtual std::string_view name() const = 0;
  virtual SlamSpace space() const = 0;

  virtual void on_odometry(const OdometryMessage& odometry) = 0;
  virtual void on_imu(const ImuMessage& /*imu*/) {}
  // Planar methods: one scan; true when it was kept (a node of the pose graph).
  virtual bool on_scan(const ScanMessage& scan);
  // 3D methods: one cloud; true when it became a key frame.
  virtual bool on_cloud(const CloudMessage& cloud);
  // After the last message: the final optimisation.
  virtual void finish() {}

  virtual std::vector<SlamPose> trajectory() const = 0;
  virtual OccupancyGrid map(const OccupancyMappingParams& params) const = 0;
  // 3D methods: the key frames' clouds into an octree (rays clear free space); planar: Error.
  virtual OctreeMap map_3d(const OctreeMapConfig& config) const;
  // 3D methods: the key frames (empty for planar methods).
  virtual const std::vector<Slam3dKeyframe>& keyframes_3d() const;
  virtual SlamGraph graph() const { return {}; }
  // Named counters and times of the run so far (method-specific; "cpu_s" totals in seconds).
  virtual std::vector<std::pair<std::string, double>> statistics() const { return {}; }
};

// The scan matcher a SLAM method is composed with: by name (empty: the method's own default) with
// its settings; `field` names where it was chosen, for errors.
struct SlamMatcherChoice {
  std::string name;
  std::vector<ParamSetting> settings;
  std::string field = "matcher";
};

// What a SLAM method's factory is given besides its settings: the matcher to compose it with, and
// the factories that build matchers (the registry fills them in with its own; a test may give
// others).
struct SlamContext {
  std::string file;
  std::uint64_t seed = 0;
  SlamMatcherChoice matcher;
  std::function<std::unique_ptr<ScanMatcher>(const SlamMatcherChoice&)> make_scan_matcher;
  std::function<std::unique_ptr<ScanMatcher3d>(const SlamMatcherChoice&)> make_scan_matcher_3d;
};
using SlamDef = ComponentDef<Slam, SlamContext>;

}  // namespace starnav
