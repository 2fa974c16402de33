#pragma once
// 3D graph SLAM on a LiDAR recording (cloud/lidar_recording.hpp: a frames folder as `starnav sim`
// writes it, a folder of cloud files with a poses file, or a ROS 1 bag of PointCloud2): the
// `graph3d` SLAM method with its matcher by name from the registry, driven frame by frame through
// the Slam role (harness/slam_run.hpp), and, when the frames carry the truth, the trajectory
// error. `starnav slam3d` is this call plus its files.
//
// The error: the estimated sensor poses against the true ones (base_link truth composed with the
// mount), after aligning the first pose in position and heading (both map frames have the floor
// as z = 0, so height and tilt need no alignment); ATE is the RMS of the position errors, the
// elevation drift the largest |z error|.
#include <functional>
#include <string>
#include <vector>

#include "starnav/cloud/lidar_recording.hpp"
#include "starnav/cloud/octree_map.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/plan_pipeline.hpp"
#include "starnav/slam/slam.hpp"

namespace starnav {

struct Slam3dRunConfig {
  std::vector<ParamSetting> settings;  // graph3d's (docs/parameters.md)
  std::string matcher = "ndt_mt";
  std::string matcher_field = "--matcher";  // what an unknown matcher's error names
  std::vector<ParamSetting> matcher_settings;
  int max_frames = 0;  // 0: all
  LidarRecordingOptions recording;
};

struct Slam3dRunResult {
  LidarFrameFolder input;
  std::string input_kind;  // LidarRecording::kind
  std::string matcher;
  std::vector<Rigid3> trajectory;  // per frame, the sensor in the map frame
  std::vector<Slam3dKeyframe> keyframes;
  SlamGraph graph;  // key frames as nodes; the loop closures are its Loop edges, between key frames
  std::size_t frames = 0, plane_edges = 0;
  double mean_raw_points = 0.0, mean_filtered_points = 0.0, mean_match_s = 0.0;  // per frame
  double wall_s = 0.0;        // the whole run, reading the clouds included
  double mapping_s = 0.0;     // GraphSlam3d alone (prefilter, registration, graph), the pipeline's cost
  double duration_s = 0.0;    // the recording's length (last frame time - first)
  bool has_truth = false;
  double ate_rmse_m = 0.0, elevation_drift_m = 0.0, final_error_m = 0.0;
  double driven_m = 0.0;      // along the true trajectory
  Rigid3 truth_alignment = Rigid3::Identity();  // map frame -> the truth's frame (x, y, heading)
};

// The errors of an estimated sensor trajectory against the true one (same length, same frames),
// as described at the top.
struct Slam3dErrors {
  double ate_rmse_m = 0.0, elevation_drift_m = 0.0, final_error_m = 0.0, driven_m = 0.0;
  Rigid3 alignment = Rigid3::Identity();  // map frame -> the truth's frame
};
Slam3dErrors slam3d_errors(const std::vector<Rigid3>& estimate, const std::vector<Rigid3>& truth);

// The map of a run: every key frame's cloud inserted at its optimised pose into an octree (rays
// clear free space), and the octree's projection to the planner's 2D grid.
struct Slam3dMapConfig {
  OctreeMapConfig octree = [] {
    OctreeMapConfig c;
    c.max_range_m = 10.0;  // long rays cost the most and add little indoors
    return c;
  }();
  GridProjectionConfig grid;
};
OctreeMap slam3d_octree(const std::vector<Slam3dKeyframe>& keyframes, const Slam3dMapConfig& config);

// The paper's last step: the improved A* (planner ou2022, inflated by `inflation_m`) on the grid
// from the first key frame's position to `goal`. Error naming "--plan-to" when the goal lies
// outside the grid.
PlanOutcome slam3d_plan(const OccupancyGrid& grid, const Vec2& start, const Vec2& goal, double inflation_m);

// The grid from above with the trajectory (and the truth when known), the key frames and a path;
// SVG, or PNG when the name ends in .png.
void write_slam3d_picture(const Slam3dRunResult& r, const OccupancyGrid& grid, const std::vector<Vec2>& path,
                          const std::string& path_svg);

using Slam3dProgress = std::function<void(std::size_t done, std::size_t total)>;
Slam3dRunResult run_slam3d(const std::string& input, const Slam3dRunConfig& config, const Slam3dProgress& progress = {});

std::string slam3d_trajectory_csv(const Slam3dRunResult& r);  // t_s, x..z, qw..qz (and the truth when known)
std::string slam3d_keyframes_csv(const Slam3dRunResult& r);
std::string slam3d_summary_json(const Slam3dRunResult& r);

}  // namespace starnav
