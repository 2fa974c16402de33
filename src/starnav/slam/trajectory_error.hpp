#pragma once
// Errors of a trajectory or a map where the truth is known (simulated logs):
//  - the absolute trajectory error against the log's ground truth (TRUEPOS readings interpolated
//    at each pose's stamp), in the frame the trajectory is in, without alignment: SLAM and
//    odometry both start at the odometry's first pose, which the simulator sets to the truth, so
//    an alignment would only hide drift;
//  - wall distances (the paper's Tables 2-3 measure a built map so): distances between opposite
//    walls measured along rows and columns of the true map, and the same lines measured in a
//    built map.
#include <cstddef>
#include <string>
#include <vector>

#include "starnav/core/statistics.hpp"
#include "starnav/logs/robot_log.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/slam/log_mapping.hpp"

namespace starnav {

struct AbsoluteTrajectoryError {
  SampleStats translation_m;  // per pose: distance to the truth
  SampleStats rotation_deg;   // per pose: |yaw - true yaw|
  double rmse_m = 0.0;
  std::size_t unmatched = 0;  // poses outside the truth's time span
};
// Throws Error (field "TRUEPOS") when the log holds no ground truth.
AbsoluteTrajectoryError absolute_trajectory_error(const std::vector<TrajectoryPose>& trajectory, const RobotLog& log);

struct WallDistance {
  bool along_x = true;          // measured along a row (x) or a column (y)
  Vec2 midpoint;                // world, between the two walls
  double true_m = 0.0;          // between the walls' inner faces in the true map
  std::vector<double> built_m;  // the same line in each built map
  double error_m(std::size_t map = 0) const { return built_m[map] - true_m; }
};

struct WallDistanceOptions {
  std::size_t count = 12;      // probes, spread evenly over the candidates every built map saw
  double min_length_m = 1.0;   // free runs between walls at least this long ...
  double max_length_m = 20.0;  // ... and at most this long
  int stride_cells = 10;       // candidate rows and columns every this many cells
};

// Candidates on `truth` (runs of free cells between two occupied cells, map_server thresholds)
// measured again in every built map, from the run's midpoint outward to the first occupied cell
// on each side (a line that meets an unknown cell or starts in an occupied one was not seen);
// `count` of the candidates every built map saw, spread evenly, so that all maps are compared on
// the same lines. All maps unrotated (origin yaw 0; Error otherwise).
std::vector<WallDistance> wall_distances(const OccupancyGrid& truth, const std::vector<const OccupancyGrid*>& built,
                                         const WallDistanceOptions& options = {});

// Mean absolute error of built map `map` over the probes; text and JSON tables (`names`: one per
// built map).
double wall_distance_mean_abs_error(const std::vector<WallDistance>& probes, std::size_t map = 0);
std::string wall_distances_text(const std::vector<WallDistance>& probes, const std::vector<std::string>& names);
std::string wall_distances_json(const std::vector<WallDistance>& probes, const std::vector<std::string>& names);

}  // namespace starnav
