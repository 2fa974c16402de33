#pragma once
// The scan-matcher role: the rigid transform that best lays one 2D scan onto another scan (or
// onto a map), with a score. ICP, correlative and branch-and-bound matchers implement it (the
// SLAM issue); the 3D registrations (ICP, GICP, NDT) get their own 3D twin with the 3D mapping
// issue. Points are in each scan's sensor frame; the transform maps `scan` into `reference`'s
// frame: reference_point ~= transform * scan_point.
#include <cstdint>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

struct ScanMatch {
  bool converged = false;
  Pose2 transform;                                        // scan frame -> reference frame
  double score = 0.0;                                     // matcher-defined; documented by each matcher
  double rms_m = 0.0;                                     // RMS distance of matched points (m)
  int iterations = 0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of (x, y, yaw), when the matcher gives one
};

class ScanMatcher {
 public:
  virtual ~ScanMatcher() = default;
  virtual std::string_view name() const = 0;
  // `scan` onto `reference`, starting from `guess`.
  virtual ScanMatch match(std::span<const Vec2> reference, std::span<const Vec2> scan, const Pose2& guess) = 0;
  // `scan` (sensor frame) onto an occupancy map, starting from `guess` (the sensor's pose in the
  // map frame); the result's transform is the sensor's pose in the map frame. Matchers that
  // cannot match against a map say so: supports_map() false, and match_to_map throws Error.
  virtual bool supports_map() const { return false; }
  virtual ScanMatch match_to_map(const OccupancyGrid& map, std::span<const Vec2> scan, const Pose2& guess);
};

struct ScanMatcherContext {
  std::string file;
};
using ScanMatcherDef = ComponentDef<ScanMatcher, ScanMatcherContext>;

}  // namespace starnav
