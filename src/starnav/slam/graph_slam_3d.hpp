#pragma once
// 3D graph SLAM as hdl_graph_slam does it (Koide et al.; Ou et al. 2022 section 2;
// docs/mapping3d.md), one frame at a time:
//  1. each frame is prefiltered (range window, voxel grid, radius outliers) and registered onto
//     the last key frame by the chosen 3D scan matcher (scan-to-key-frame odometry), starting from
//     the wheel odometry's motion when the frame carries odometry, else from the last motion;
//  2. a new key frame when the sensor has moved keyframe_delta_trans_m or turned
//     keyframe_delta_angle_deg since the last one; an odometry edge joins it to the last key frame;
//  3. the floor: RANSAC on the key frame's points in a height band around the floor's expected
//     height below the sensor (normal within floor_normal_max_deg of the sensor's up, at least
//     floor_min_points inliers), added as a plane edge to the fixed global floor z = 0;
//  4. loop closures: earlier key frames within loop_distance_m of the new one (estimated poses)
//     after at least loop_accum_distance_m of travel between them, at least loop_min_interval_m
//     after the last closure, registered from the estimated relative pose; accepted when the
//     fitness score is below loop_fitness_max_m2 (Huber-robust edges);
//  5. the pose graph (slam/pose_graph_3d) is optimised after every closure and at the end.
// The map frame is the floor's: z = 0 on the floor, z up; the first key frame's sensor pose is the
// LiDAR's mount above the origin (its height and tilt from the first floor fit when there is one).
//
// Through the Slam role (`graph3d` in the registry, whose factory builds the two 3D scan matchers
// by name): clouds (CloudMessage: sensor-frame points, the mount) registered with the latest
// odometry as the guess; the mount of the first cloud unless the constructor was given one.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/ransac_plane.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/params.hpp"
#include "starnav/slam/pose_graph_3d.hpp"
#include "starnav/slam/slam.hpp"

namespace starnav {

struct GraphSlam3dConfig {
  PrefilterConfig prefilter = [] {
    PrefilterConfig p;
    p.window.min_range_m = 0.5;  // the robot's own body
    p.window.max_range_m = 40.0;
    p.voxel_leaf_m = 0.1;  // hdl_graph_slam's downsample_resolution
    p.outlier_radius_m = 0.5;
    p.outlier_min_neighbours = 2;
    return p;
  }();
  double keyframe_delta_trans_m = 1.0;   // hdl: 2.0 in the graph; indoors smaller
  double keyframe_delta_angle_rad = 0.5;  // hdl: 2.0 rad
  // Edge uncertainties (1 sigma): registration edges, and the floor (angles in rad, d in m).
  double odometry_sigma_m = 0.02, odometry_sigma_rad = 0.01;
  bool floor = true;
  double floor_height_band_m = 0.2;    // +- around the expected floor below the sensor
  double floor_normal_max_rad = 20.0 * kPi / 180.0;  // hdl_graph_slam's normal_filter_thresh
  int floor_min_points = 200;          // hdl's floor_pts_thresh is 512, for denser clouds
  double floor_ransac_threshold_m = 0.02;  // hdl: 0.1; a tight band keeps the feet of walls out
  double floor_sigma = 0.02;           // rad and m
  bool loops = true;
  double loop_distance_m = 3.0;        // hdl: 15 m outdoors
  double loop_accum_distance_m = 8.0;  // hdl: 25 m
  double loop_min_interval_m = 2.0;    // hdl: 15 m
  double loop_fitness_max_m2 = 0.05;
  std::uint64_t seed = 0;              // RANSAC's draws
  void validate() const;
};
const ParamTable<GraphSlam3dConfig>& graph_slam_3d_params();

struct Slam3dFrameResult {
  std::size_t frame = 0;
  double t_s = 0.0;
  std::size_t keyframe = 0;          // the key frame it was registered onto
  Rigid3 relative = Rigid3::Identity();  // the frame in that key frame's frame
  std::size_t raw_points = 0, windowed = 0, voxelised = 0, filtered_points = 0;
  double match_s = 0.0, fitness = 0.0;
  int iterations = 0;
  bool converged = false;
  bool keyframe_created = false;
};

struct Slam3dLoop {
  std::size_t from = 0, to = 0;  // key frames
  double fitness = 0.0;
};

class GraphSlam3d final : public Slam {
 public:
  // `mount`: the sensor in base_link (used with wheel odometry and for the first pose); without
  // one, the first cloud message's. `make_matcher` builds the 3D scan matcher (twice: odometry and
  // loop closures keep their own references); whoever builds the SLAM picks it (the registry's
  // factory by name).
  using MatcherFactory = std::function<std::unique_ptr<ScanMatcher3d>()>;
  GraphSlam3d(const GraphSlam3dConfig& config, const MatcherFactory& make_matcher);
  GraphSlam3d(const GraphSlam3dConfig& config, const Pose3& mount, const MatcherFactory& make_matcher);
  // One frame (sensor-frame points) at t_s, with the base's wheel odometry pose when known; returns
  // true when it became a key frame. Needs the mount.
  bool add(double t_s, std::span<const Vec3> points, const std::optional<Pose2>& odometry = std::nullopt);
  // Optimises the graph a last time.
  void finish() override;

  // The Slam role.
  std::string_view name() const override { return "graph3d"; }
  SlamSpace space() const override { return SlamSpace::ThreeD; }
  void on_odometry(const OdometryMessage& odometry) override { odometry_ = odometry.pose; }
  bool on_cloud(const CloudMessage& cloud) override;
  std::vector<SlamPose> trajectory() const override;
  // The octree of the key frames projected to a grid of params.resolution_m (GridProjectionConfig's
  // default band).
  OccupancyGrid map(const OccupancyMappingParams& params) const override;
  OctreeMap map_3d(const OctreeMapConfig& config) const override;
  const std::vector<Slam3dKeyframe>& keyframes_3d() const override { return keyframes_; }
  // Key frames as nodes (their base poses, planar), registration edges Local, closures Loop (score:
  // the registration's fitness, m^2).
  SlamGraph graph() const override;
  // frames, keyframes, loop_closures, floor_edges, optimisations, optimise_s; the prefilter's
  // points over all frames (raw_points, windowed_points, voxelised_points, filtered_points) and
  // the registrations' time (match_s), and their means per frame (mean_raw_points,
  // mean_filtered_points, mean_match_s). Totals so far: a caller who wants a frame's figures takes
  // the difference across its on_cloud.
  std::vector<std::pair<std::string, double>> statistics() const override;

  const std::vector<Slam3dKeyframe>& keyframes() const { return keyframes_; }
  const std::vector<Slam3dFrameResult>& frames() const { return frames_; }
  const std::vector<Slam3dLoop>& loops() const { return loops_; }
  // Every frame's sensor pose in the map frame, from its key frame's current pose.
  std::vector<Rigid3> sensor_poses() const;
  const std::vector<PoseGraph3Edge>& edges() const { return edges_; }
  const std::vector<PlaneEdge3>& plane_edges() const { return plane_edges_; }
  double optimise_s() const { return optimise_s_; }
  int optimisations() const { return optimisations_; }

 private:
  void add_keyframe(std::size_t frame, double t_s, PointCloud cloud, const Rigid3& relative, double moved_m);
  std::optional<Plane3> detect_floor(const PointCloud& cloud);
  // The information of a registration edge (odometry and loop closures alike).
  Eigen::Matrix<double, 6, 6> registration_information() const;
  void detect_loops();
  void optimise();
  void count(const Slam3dFrameResult& frame);

  struct Slam3dTotals {
    std::size_t raw = 0, windowed = 0, voxelised = 0, kept = 0;
    double match_s = 0.0;
  };

  GraphSlam3dConfig c_;
  std::optional<Pose3> mount_;
  std::optional<Pose2> odometry_;  // the latest (the role's input)
  std::unique_ptr<ScanMatcher3d> matcher_;
  std::unique_ptr<ScanMatcher3d> loop_matcher_;
  std::vector<Slam3dKeyframe> keyframes_;
  std::vector<Slam3dFrameResult> frames_;
  std::vector<Slam3dLoop> loops_;
  std::vector<PoseGraph3Edge> edges_;
  std::vector<PlaneEdge3> plane_edges_;
  Rng rng_;
  std::optional<Pose2> keyframe_odometry_;  // the wheel odometry at the last key frame
  Rigid3 last_relative_ = Rigid3::Identity();  // the last frame in the last key frame's frame
  Rigid3 last_step_ = Rigid3::Identity();      // the motion between the last two frames
  double accum_distance_m_ = 0.0;
  double last_loop_accum_m_ = -1e300;
  double optimise_s_ = 0.0;
  int optimisations_ = 0;
  Slam3dTotals totals_;  // over frames_
};

SlamDef graph_slam_3d();

}  // namespace starnav
