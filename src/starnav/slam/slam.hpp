#pragma once
// The SLAM role: scans and odometry in, a trajectory and a map out, incrementally. Each call to
// add() gives one scan (points in the sensor frame) with the odometry pose at its time; the
// trajectory is one pose per kept scan (map frame), revised when the back end optimises (loop
// closures); map() renders the occupancy grid of the current trajectory.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

struct SlamScan {
  double t_s = 0.0;
  Pose2 odometry;                  // odom frame, at t_s
  Pose2 sensor_in_base;            // the LiDAR's mount (base_link)
  std::vector<Vec2> points;        // sensor frame
  double max_range_m = 0.0;        // beams at or beyond it returned nothing
};

struct SlamPose {
  double t_s = 0.0;
  Pose2 pose;  // base_link in the map frame
};

class Slam {
 public:
  virtual ~Slam() = default;
  virtual std::string_view name() const = 0;
  // One scan; returns true when it was kept (a node of the trajectory).
  virtual bool add(const SlamScan& scan) = 0;
  virtual std::vector<SlamPose> trajectory() const = 0;
  // The occupancy map of the kept scans at their current poses.
  virtual OccupancyGrid map(double resolution_m) const = 0;
};

struct SlamContext {
  std::string file;
  std::uint64_t seed = 0;
};
using SlamDef = ComponentDef<Slam, SlamContext>;

}  // namespace starnav
