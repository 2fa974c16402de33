#pragma once
// Scan-to-scan registration on real data: the KITTI odometry frames of
// ../shared/datasets/lidar3d/kitti_odometry_mini (sequences 00, 05, 07, ten consecutive Velodyne
// HDL-64E scans each: 27 pairs). Each matcher registers frame k+1 onto frame k from the identity
// (no odometry guess) after the same prefilter; the error is the rigid difference to the
// reference motion L_k^-1 L_{k+1}, L = P Tr (SemanticKITTI's poses on sequence 00, where KITTI's
// ground truth is known to be off over these frames; KITTI's GNSS/INS ground truth on 05 and 07).
// The floor: RANSAC on every frame (a height band below the sensor, normal within 20 degrees of
// vertical), scored by the distance of SemanticKITTI's ground-labelled points to it, beside the
// least median any plane reaches on those points.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/core/params.hpp"

namespace starnav {

// A matcher as the experiment runs it: a label, a registry name and its settings.
struct MatcherVariant {
  std::string label;
  std::string matcher;
  std::vector<ParamSetting> settings;
};
// icp, icp_plane (point_to_plane), gicp, vgicp, ndt, ndt_mt (and PCL's with its plugin).
std::vector<MatcherVariant> standard_matcher_variants();
// The standard variants named in `labels` (comma-separated on the CLI); Error naming `field` for
// an unknown label.
std::vector<MatcherVariant> matcher_variants(const std::vector<std::string>& labels, const std::string& field);

struct KittiRegistrationConfig {
  std::string dataset = "../shared/datasets/lidar3d/kitti_odometry_mini";
  std::vector<std::string> sequences = {"00", "05", "07"};
  std::vector<std::string> matchers = {"icp", "icp_plane", "gicp", "ndt", "ndt_mt"};
  int frames = 10;  // per sequence: frames 0 .. frames-1, frames-1 pairs
  PrefilterConfig prefilter = [] {
    PrefilterConfig p;
    p.window.min_range_m = 3.0;  // the car's roof and body
    p.window.max_range_m = 80.0;
    p.voxel_leaf_m = 0.25;
    p.outlier_radius_m = 0.0;
    return p;
  }();
  std::uint64_t seed = 0;  // RANSAC's draws
  void validate() const;
};

struct KittiPairResult {
  std::string sequence, matcher;
  int frame = 0;  // the pair (frame, frame + 1)
  std::size_t reference_points = 0, scan_points = 0;
  double translation_error_m = 0.0, rotation_error_deg = 0.0;
  double reference_motion_m = 0.0;  // how far the sensor moved
  double time_s = 0.0, fitness = 0.0;
  int iterations = 0;
  bool converged = false;
};

struct KittiMatcherSummary {
  std::string matcher;
  int pairs = 0, converged = 0;
  double mean_translation_m = 0.0, max_translation_m = 0.0;
  double mean_rotation_deg = 0.0, max_rotation_deg = 0.0;
  double median_time_s = 0.0, mean_iterations = 0.0;
};

struct KittiFloorResult {
  std::string sequence;
  int frame = 0;
  bool found = false;
  double normal_x = 0, normal_y = 0, normal_z = 1, d = 0;
  std::size_t band_points = 0, inliers = 0, ground_points = 0;
  double median_ground_distance_m = 0.0;       // every ground-labelled point
  double median_ground_distance_20m = 0.0;     // those within 20 m of the sensor
  // The least median any one plane reaches on the same ground points (least_median_plane, normal
  // within 20 degrees of vertical): roads, sidewalks and terrain are not one plane, and where
  // this is above a target, no floor fit can meet it.
  double least_median_ground_distance_m = 0.0;
};

struct KittiRegistrationResult {
  KittiRegistrationConfig config;
  std::vector<std::string> references;  // per sequence: "semantickitti" | "kitti_gt"
  double mean_raw_points = 0.0, mean_filtered_points = 0.0;
  std::vector<std::pair<std::string, unsigned>> threads;  // matchers on more than one thread (label, threads)
  std::vector<KittiPairResult> pairs;
  std::vector<KittiMatcherSummary> summaries;
  std::vector<KittiFloorResult> floors;  // per sequence and frame
};

using KittiProgress = std::function<void(std::size_t done, std::size_t total, const std::string& what)>;
KittiRegistrationResult run_kitti_registration(const KittiRegistrationConfig& config, const KittiProgress& progress = {});
std::string kitti_registration_markdown(const KittiRegistrationResult& result);
std::string kitti_registration_json(const KittiRegistrationResult& result);
std::string kitti_registration_csv(const KittiRegistrationResult& result);

}  // namespace starnav
