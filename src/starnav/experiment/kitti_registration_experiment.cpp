#include "starnav/experiment/kitti_registration_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/cloud/kitti_dataset.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/cloud/ransac_plane.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

namespace fs = std::filesystem;

namespace {

ParamSetting matcher_setting(const std::string& key, const std::string& value) {
  ParamSetting s;
  s.key = key;
  s.value = value;
  s.field = key;
  return s;
}

std::string frame_file(const std::string& dir, int k, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d%s", k, ext);
  return (fs::path(dir) / name).string();
}

double median_of(std::vector<double> v) { return sample_stats(std::move(v)).median; }

}  // namespace

std::vector<MatcherVariant> standard_matcher_variants() {
  return {
      {"icp", "icp", {}},
      {"icp_plane", "icp", {matcher_setting("metric", "point_to_plane")}},
      {"gicp", "gicp", {}},
      {"vgicp", "vgicp", {}},
      {"ndt", "ndt", {}},
      {"ndt_mt", "ndt_mt", {}},
      // PCL's (through its plugin) with the limits of starnav's above: 64 iterations, pairs within 1 m,
      // steps down to 0.1 mm and 1e-4 rad (PCL's own defaults stop ICP and NDT far from the answer).
      {"pcl_icp", "pcl_icp",
       {matcher_setting("max_iterations", "64"), matcher_setting("max_correspondence_distance_m", "1"),
        matcher_setting("transformation_epsilon", "1e-8")}},
      {"pcl_gicp", "pcl_gicp",
       {matcher_setting("max_iterations", "64"), matcher_setting("max_correspondence_distance_m", "1"),
        matcher_setting("transformation_epsilon", "1e-4"), matcher_setting("rotation_epsilon", "1e-4")}},
      {"pcl_ndt", "pcl_ndt", {matcher_setting("max_iterations", "64"), matcher_setting("transformation_epsilon", "1e-8")}},
  };
}

std::vector<MatcherVariant> matcher_variants(const std::vector<std::string>& labels, const std::string& field) {
  const std::vector<MatcherVariant> all = standard_matcher_variants();
  std::vector<MatcherVariant> out;
  for (const std::string& l : labels) {
    auto it = std::find_if(all.begin(), all.end(), [&](const MatcherVariant& v) { return v.label == l; });
    if (it == all.end()) {
      std::string known;
      for (const MatcherVariant& v : all) known += (known.empty() ? "" : ", ") + v.label;
      throw Error("unknown matcher '" + printable(l, 40) + "' (" + known + ")", "", 0, field);
    }
    out.push_back(*it);
  }
  return out;
}

void KittiRegistrationConfig::validate() const {
  require(!sequences.empty(), "--sequences", "needs at least one sequence");
  require(!matchers.empty(), "--matchers", "needs at least one matcher");
  (void)matcher_variants(matchers, "--matchers");
  require(frames >= 2 && frames <= 10000, "--frames", "must be in [2, 10000]");
  for (const std::string& s : sequences) (void)kitti_velodyne_to_camera(s);
  try {
    prefilter.validate();
  } catch (const Error& e) {
    throw Error(e.message(), "", 0, "prefilter." + e.field());
  }
}

namespace {

// The RANSAC floor of one frame (hdl_graph_slam's detector on KITTI's geometry) against the
// frame's ground-labelled points.
KittiFloorResult kitti_floor(const std::string& seq, int frame, const PointCloud& raw, const std::string& labels_file,
                             std::uint64_t seed) {
  KittiFloorResult fl;
  fl.sequence = seq;
  fl.frame = frame;
  PointCloud band;
  for (const Vec3& p : raw)
    if (p.z() > -3.0 && p.z() < -0.8 && p.head<2>().norm() > 3.0 && p.head<2>().norm() < 40.0) band.push_back(p);
  fl.band_points = band.size();
  RansacPlaneConfig rc;
  rc.distance_threshold_m = 0.1;  // hdl_graph_slam's floor_detection default
  rc.iterations = 500;
  rc.min_inliers = 512;  // hdl_graph_slam's floor_pts_thresh
  rc.max_axis_angle_rad = 20.0 * kPi / 180.0;
  Rng rng(seed + static_cast<std::uint64_t>(frame));
  const RansacPlane plane = ransac_plane(voxel_downsample(band, 0.2), rc, rng);
  fl.found = plane.found;
  if (!plane.found) return fl;
  fl.normal_x = plane.plane.normal.x();
  fl.normal_y = plane.plane.normal.y();
  fl.normal_z = plane.plane.normal.z();
  fl.d = plane.plane.d;
  fl.inliers = plane.inliers.size();
  const std::vector<std::uint16_t> labels = read_kitti_labels(labels_file);
  if (labels.size() != raw.size())
    throw Error(std::to_string(labels.size()) + " labels for " + std::to_string(raw.size()) + " points", labels_file);
  std::vector<double> all, near;
  PointCloud ground;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (!is_kitti_ground_class(labels[i])) continue;
    const double e = std::abs(plane.plane.signed_distance(raw[i]));
    all.push_back(e);
    ground.push_back(raw[i]);
    if (raw[i].head<2>().norm() < 20.0) near.push_back(e);
  }
  fl.ground_points = all.size();
  if (all.empty()) return fl;
  fl.median_ground_distance_m = median_of(all);
  fl.median_ground_distance_20m = near.empty() ? 0.0 : median_of(near);
  LeastMedianPlaneConfig lc;
  lc.iterations = 2000;
  lc.stride = 7;  // the search's medians over a seventh of the points; the final one over all
  lc.max_axis_angle_rad = rc.max_axis_angle_rad;
  Rng lrng(seed + static_cast<std::uint64_t>(frame));
  const LeastMedianPlane lm = least_median_plane(ground, lc, lrng);
  fl.least_median_ground_distance_m = lm.found ? lm.median_distance_m : 0.0;
  return fl;
}

}  // namespace

KittiRegistrationResult run_kitti_registration(const KittiRegistrationConfig& config, const KittiProgress& progress) {
  config.validate();
  KittiRegistrationResult r;
  r.config = config;
  const std::vector<MatcherVariant> variants = matcher_variants(config.matchers, "--matchers");
  if (!fs::is_directory(config.dataset)) throw Error("is not a folder", config.dataset, 0, "--dataset");
  const std::size_t total = config.sequences.size() * static_cast<std::size_t>(config.frames - 1) * variants.size();
  std::size_t done = 0;
  double raw_sum = 0.0, kept_sum = 0.0;
  std::size_t frames_read = 0;
  for (const std::string& seq : config.sequences) {
    const fs::path dir = fs::path(config.dataset) / "sequences" / seq;
    // SemanticKITTI's poses on 00 (KITTI's ground truth disagrees with the scans there), else KITTI's.
    const bool semantic = seq == "00";
    const std::vector<Rigid3> poses =
        semantic ? read_kitti_poses((dir / "poses.txt").string())
                 : read_kitti_poses((fs::path(config.dataset) / "ground_truth" / "egusa" / (seq + ".txt")).string(), true);
    r.references.push_back(semantic ? "semantickitti" : "kitti_gt");
    if (poses.size() < static_cast<std::size_t>(config.frames))
      throw Error("holds " + std::to_string(poses.size()) + " poses, fewer than --frames", (dir / "poses.txt").string());
    const Rigid3 tr = kitti_velodyne_to_camera(seq);
    std::vector<PointCloud> clouds;
    for (int k = 0; k < config.frames; ++k) {
      const std::string file = frame_file((dir / "velodyne").string(), k, ".bin.gz");
      PointCloudFile f = read_point_cloud(fs::exists(file) ? file : frame_file((dir / "velodyne").string(), k, ".bin"));
      PrefilterCounts counts;
      clouds.push_back(prefilter_cloud(f.points, config.prefilter, &counts));
      raw_sum += static_cast<double>(counts.raw);
      kept_sum += static_cast<double>(counts.kept);
      ++frames_read;
      const std::string labels_file = frame_file((dir / "labels").string(), k, ".label.gz");
      if (fs::exists(labels_file)) r.floors.push_back(kitti_floor(seq, k, f.points, labels_file, config.seed));
    }
    for (const MatcherVariant& v : variants) {
      auto matcher = find_scan_matcher_3d(v.matcher).make({}, v.settings);
      if (matcher->threads() > 1) r.threads.emplace_back(v.label, matcher->threads());
      for (int k = 0; k + 1 < config.frames; ++k) {
        if (progress) progress(done, total, seq + " " + v.label + " " + std::to_string(k));
        const Rigid3 truth = kitti_lidar_pose(poses[static_cast<std::size_t>(k)], tr).inverse() *
                             kitti_lidar_pose(poses[static_cast<std::size_t>(k + 1)], tr);
        const CloudMatch m = register_clouds(*matcher, clouds[static_cast<std::size_t>(k)], clouds[static_cast<std::size_t>(k + 1)]);
        const Rigid3 error = truth.inverse() * m.transform;
        KittiPairResult p;
        p.sequence = seq;
        p.matcher = v.label;
        p.frame = k;
        p.reference_points = clouds[static_cast<std::size_t>(k)].size();
        p.scan_points = clouds[static_cast<std::size_t>(k + 1)].size();
        p.translation_error_m = translation_norm(error);
        p.rotation_error_deg = rotation_angle(error) * 180.0 / kPi;
        p.reference_motion_m = translation_norm(truth);
        p.time_s = m.time_s;
        p.fitness = m.fitness;
        p.iterations = m.iterations;
        p.converged = m.converged;
        r.pairs.push_back(p);
        ++done;
      }
    }
  }
  if (progress) progress(done, total, "done");
  r.mean_raw_points = raw_sum / static_cast<double>(std::max<std::size_t>(1, frames_read));
  r.mean_filtered_points = kept_sum / static_cast<double>(std::max<std::size_t>(1, frames_read));
  for (const MatcherVariant& v : variants) {
    KittiMatcherSummary s;
    s.matcher = v.label;
    std::vector<double> t, rot, time, iters;
    for (const KittiPairResult& p : r.pairs) {
      if (p.matcher != v.label) continue;
      t.push_back(p.translation_error_m);
      rot.push_back(p.rotation_error_deg);
      time.push_back(p.time_s);
      iters.push_back(p.iterations);
      s.converged += p.converged;
    }
    s.pairs = static_cast<int>(t.size());
    const SampleStats st = sample_stats(t), sr = sample_stats(rot);
    s.mean_translation_m = st.mean;
    s.max_translation_m = st.max;
    s.mean_rotation_deg = sr.mean;
    s.max_rotation_deg = sr.max;
    s.median_time_s = sample_stats(time).median;
    s.mean_iterations = sample_stats(iters).mean;
    r.summaries.push_back(s);
  }
  return r;
}

std::string kitti_registration_markdown(const KittiRegistrationResult& r) {
  const KittiRegistrationConfig& c = r.config;
  std::string s = "# Scan-to-scan registration on KITTI odometry\n\n";
  s += "Sequences";
  for (std::size_t i = 0; i < c.sequences.size(); ++i)
    s += std::string(i ? "," : "") + " " + c.sequences[i] + " (" + r.references[i] + ")";
  s += "; frames 0-" + std::to_string(c.frames - 1) + ", each pair from the identity. Prefilter: range " +
       format_fixed(c.prefilter.window.min_range_m, 1) + "-" + format_fixed(c.prefilter.window.max_range_m, 1) + " m, voxel " +
       format_fixed(c.prefilter.voxel_leaf_m, 2) + " m: " + format_fixed(r.mean_raw_points, 0) + " -> " +
       format_fixed(r.mean_filtered_points, 0) + " points per frame.";
  std::string pooled;
  for (const auto& [label, n] : r.threads) pooled += (pooled.empty() ? "" : ", ") + label + " on " + std::to_string(n) + " threads";
  s += (pooled.empty() ? " Every matcher on one thread." : " " + pooled + ", the others on one.") + std::string("\n\n");
  s += "| matcher | pairs | converged | translation error mean / max (cm) | rotation error mean / max (deg) | median time (ms) | "
       "iterations |\n|---|---|---|---|---|---|---|\n";
  for (const KittiMatcherSummary& m : r.summaries)
    s += "| " + m.matcher + " | " + std::to_string(m.pairs) + " | " + std::to_string(m.converged) + " | " +
         format_fixed(100 * m.mean_translation_m, 2) + " / " + format_fixed(100 * m.max_translation_m, 2) + " | " +
         format_fixed(m.mean_rotation_deg, 3) + " / " + format_fixed(m.max_rotation_deg, 3) + " | " +
         format_fixed(1000 * m.median_time_s, 1) + " | " + format_fixed(m.mean_iterations, 1) + " |\n";
  s += "\nFloor (RANSAC on every frame: points 0.8-3 m below the sensor and 3-40 m away, 0.2 m voxels, 0.1 m threshold, "
       "normal within 20 deg of vertical, at least 512 inliers) against SemanticKITTI's ground labels: the median distance "
       "of the ground points to the plane, per frame; beside it the least median any plane reaches on the same points "
       "(least-median-of-squares search), the bound of every floor fit:\n\n"
       "| sequence | frames | found | median distance, median / max over frames (cm) | frames <= 5 cm | within 20 m, "
       "median (cm) | least median of any plane, median / max (cm) | frames whose bound is <= 5 cm |\n"
       "|---|---|---|---|---|---|---|---|\n";
  for (const std::string& seq : r.config.sequences) {
    std::vector<double> med, near, bound;
    int found = 0, frames = 0, within = 0, bound_within = 0;
    for (const KittiFloorResult& f : r.floors) {
      if (f.sequence != seq) continue;
      ++frames;
      if (!f.found || f.ground_points == 0) continue;
      ++found;
      med.push_back(f.median_ground_distance_m);
      near.push_back(f.median_ground_distance_20m);
      bound.push_back(f.least_median_ground_distance_m);
      within += f.median_ground_distance_m <= 0.05;
      bound_within += f.least_median_ground_distance_m <= 0.05;
    }
    if (frames == 0) continue;
    const auto cm = [](const std::vector<double>& v) { return v.empty() ? std::string("-") : format_fixed(100 * median_of(v), 2); };
    const auto cm_max = [](const std::vector<double>& v) {
      return v.empty() ? std::string("-") : format_fixed(100 * *std::max_element(v.begin(), v.end()), 2);
    };
    s += "| " + seq + " | " + std::to_string(frames) + " | " + std::to_string(found) + " | " + cm(med) + " / " + cm_max(med) +
         " | " + std::to_string(within) + " | " + cm(near) + " | " + cm(bound) + " / " + cm_max(bound) + " | " +
         std::to_string(bound_within) + " |\n";
  }
  return s;
}

std::string kitti_registration_json(const KittiRegistrationResult& r) {
  nlohmann::ordered_json j;
  j["dataset"] = r.config.dataset;
  j["sequences"] = r.config.sequences;
  j["references"] = r.references;
  j["frames"] = r.config.frames;
  j["mean_raw_points"] = r.mean_raw_points;
  j["mean_filtered_points"] = r.mean_filtered_points;
  nlohmann::ordered_json threads = nlohmann::ordered_json::object();
  for (const auto& [label, n] : r.threads) threads[label] = n;
  j["threads"] = threads;  // matchers that ran on more than one thread
  nlohmann::ordered_json ms = nlohmann::ordered_json::array();
  for (const KittiMatcherSummary& m : r.summaries)
    ms.push_back({{"matcher", m.matcher},
                  {"pairs", m.pairs},
                  {"converged", m.converged},
                  {"mean_translation_error_m", m.mean_translation_m},
                  {"max_translation_error_m", m.max_translation_m},
                  {"mean_rotation_error_deg", m.mean_rotation_deg},
                  {"max_rotation_error_deg", m.max_rotation_deg},
                  {"median_time_s", m.median_time_s},
                  {"mean_iterations", m.mean_iterations}});
  j["matchers"] = ms;
  nlohmann::ordered_json fl = nlohmann::ordered_json::array();
  for (const KittiFloorResult& f : r.floors)
    fl.push_back({{"sequence", f.sequence},
                  {"frame", f.frame},
                  {"found", f.found},
                  {"normal", {f.normal_x, f.normal_y, f.normal_z}},
                  {"d_m", f.d},
                  {"inliers", f.inliers},
                  {"ground_points", f.ground_points},
                  {"median_ground_distance_m", f.median_ground_distance_m},
                  {"median_ground_distance_within_20m_m", f.median_ground_distance_20m},
                  {"least_median_ground_distance_m", f.least_median_ground_distance_m}});
  j["floor"] = fl;
  return j.dump(2) + "\n";
}

std::string kitti_registration_csv(const KittiRegistrationResult& r) {
  std::string s =
      "sequence,frame,matcher,reference_points,scan_points,reference_motion_m,translation_error_m,rotation_error_deg,"
      "time_s,fitness_m2,iterations,converged\n";
  for (const KittiPairResult& p : r.pairs)
    s += p.sequence + ',' + std::to_string(p.frame) + ',' + p.matcher + ',' + std::to_string(p.reference_points) + ',' +
         std::to_string(p.scan_points) + ',' + format_fixed6(p.reference_motion_m) + ',' + format_fixed6(p.translation_error_m) +
         ',' + format_fixed6(p.rotation_error_deg) + ',' + format_fixed6(p.time_s) + ',' + format_fixed6(p.fitness) + ',' +
         std::to_string(p.iterations) + ',' + (p.converged ? "1" : "0") + '\n';
  return s;
}

}  // namespace starnav
