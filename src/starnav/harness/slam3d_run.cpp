#include "starnav/harness/slam3d_run.hpp"

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/cloud/lidar_recording_source.hpp"
#include "starnav/harness/slam_run.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav {

namespace {

double yaw_of(const Rigid3& t) { return std::atan2(t.linear()(1, 0), t.linear()(0, 0)); }

std::string pose_cells(const Rigid3& t) {
  const Eigen::Quaterniond q(t.linear());
  return format_fixed6(t.translation().x()) + "," + format_fixed6(t.translation().y()) + "," +
         format_fixed6(t.translation().z()) + "," + format_fixed6(q.w()) + "," + format_fixed6(q.x()) + "," +
         format_fixed6(q.y()) + "," + format_fixed6(q.z());
}

}  // namespace

Slam3dErrors slam3d_errors(const std::vector<Rigid3>& estimate, const std::vector<Rigid3>& truth) {
  Slam3dErrors e;
  if (estimate.empty() || estimate.size() != truth.size()) throw Error("the estimate and the truth differ in length");
  Rigid3 align = Rigid3::Identity();
  align.linear() = Eigen::AngleAxisd(yaw_of(truth.front()) - yaw_of(estimate.front()), Vec3::UnitZ()).toRotationMatrix();
  align.translation() = truth.front().translation() - align.linear() * estimate.front().translation();
  align.translation().z() = 0.0;  // both map frames have the floor at z = 0
  double sq = 0.0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const Vec3 t = truth[i].translation(), est = align * estimate[i].translation();
    sq += (t - est).squaredNorm();
    e.elevation_drift_m = std::max(e.elevation_drift_m, std::abs(t.z() - est.z()));
    if (i > 0) e.driven_m += (t - truth[i - 1].translation()).norm();
  }
  e.ate_rmse_m = std::sqrt(sq / static_cast<double>(estimate.size()));
  e.final_error_m = (truth.back().translation() - align * estimate.back().translation()).norm();
  e.alignment = align;
  return e;
}

Slam3dRunResult run_slam3d(const std::string& input, const Slam3dRunConfig& config, const Slam3dProgress& progress) {
  Slam3dRunResult r;
  // Built first: a bad setting or matcher is reported before the recording is read.
  SlamChoice choice;
  choice.method = "graph3d";
  choice.settings = config.settings;
  choice.matcher = {config.matcher, config.matcher_settings, config.matcher_field};
  std::unique_ptr<Slam> slam = make_slam(choice);
  const LidarRecording recording = open_lidar_recording(input, config.recording);
  r.input = recording.frames;
  r.input_kind = recording.kind;
  r.matcher = config.matcher;
  if (r.input.frames.empty()) throw Error("holds no frames", input);
  if (config.max_frames > 0 && r.input.frames.size() > static_cast<std::size_t>(config.max_frames))
    r.input.frames.resize(static_cast<std::size_t>(config.max_frames));
  LidarRecordingSource source(recording, r.input.frames.size());
  const SlamDriveTimes times = drive_slam(*slam, source, {}, progress);
  r.wall_s = times.wall_s;
  r.mapping_s = times.slam_wall_s;
  r.duration_s = r.input.frames.back().t_s - r.input.frames.front().t_s;
  for (const SlamPose& p : slam->trajectory()) r.trajectory.push_back(p.sensor);
  r.keyframes = slam->keyframes_3d();
  r.graph = slam->graph();
  for (const auto& [name, value] : slam->statistics()) {
    if (name == "frames") r.frames = static_cast<std::size_t>(value);
    if (name == "floor_edges") r.plane_edges = static_cast<std::size_t>(value);
    if (name == "mean_raw_points") r.mean_raw_points = value;
    if (name == "mean_filtered_points") r.mean_filtered_points = value;
    if (name == "mean_match_s") r.mean_match_s = value;
  }
  r.has_truth = true;
  for (const LidarFrameRecord& f : r.input.frames) r.has_truth = r.has_truth && f.truth.has_value();
  if (r.has_truth) {
    const Rigid3 mount = to_rigid(r.input.mount);
    std::vector<Rigid3> truth;
    for (const LidarFrameRecord& f : r.input.frames) truth.push_back(to_rigid(*f.truth) * mount);
    const Slam3dErrors e = slam3d_errors(r.trajectory, truth);
    r.ate_rmse_m = e.ate_rmse_m;
    r.elevation_drift_m = e.elevation_drift_m;
    r.final_error_m = e.final_error_m;
    r.driven_m = e.driven_m;
    r.truth_alignment = e.alignment;
  }
  return r;
}

std::string slam3d_trajectory_csv(const Slam3dRunResult& r) {
  std::string s = "frame,t_s,x_m,y_m,z_m,qw,qx,qy,qz";
  if (r.has_truth) s += ",true_x_m,true_y_m,true_z_m,true_qw,true_qx,true_qy,true_qz";
  s += "\n";
  const Rigid3 mount = to_rigid(r.input.mount);
  for (std::size_t i = 0; i < r.trajectory.size(); ++i) {
    s += std::to_string(i);
    s += ',';
    s += format_fixed6(r.input.frames[i].t_s);
    s += ',';
    s += pose_cells(r.trajectory[i]);
    if (r.has_truth) {
      s += ',';
      s += pose_cells(to_rigid(*r.input.frames[i].truth) * mount);
    }
    s += '\n';
  }
  return s;
}

std::string slam3d_keyframes_csv(const Slam3dRunResult& r) {
  std::string s = "keyframe,frame,t_s,x_m,y_m,z_m,qw,qx,qy,qz,points,floor,floor_nx,floor_ny,floor_nz,floor_d_m\n";
  for (std::size_t k = 0; k < r.keyframes.size(); ++k) {
    const Slam3dKeyframe& kf = r.keyframes[k];
    s += std::to_string(k) + "," + std::to_string(kf.frame) + "," + format_fixed6(kf.t_s) + "," + pose_cells(kf.pose) + "," +
         std::to_string(kf.cloud.size()) + "," + (kf.floor ? "1" : "0");
    if (kf.floor)
      // Appended piece by piece: g++ 12 warns falsely (-Wrestrict) on a literal + a temporary string.
      s.append(",").append(format_fixed6(kf.floor->normal.x())).append(",").append(format_fixed6(kf.floor->normal.y()))
          .append(",").append(format_fixed6(kf.floor->normal.z())).append(",").append(format_fixed6(kf.floor->d));
    else
      s += ",,,,";
    s += "\n";
  }
  return s;
}

std::string slam3d_summary_json(const Slam3dRunResult& r) {
  nlohmann::ordered_json j;
  j["input"] = r.input.dir;
  j["input_kind"] = r.input_kind;
  j["matcher"] = r.matcher;
  j["frames"] = r.frames;
  j["keyframes"] = r.keyframes.size();
  j["loop_closures"] = r.graph.closures();
  j["floor_edges"] = r.plane_edges;
  j["mean_raw_points"] = r.mean_raw_points;
  j["mean_filtered_points"] = r.mean_filtered_points;
  j["mean_match_s"] = r.mean_match_s;
  j["recording_s"] = r.duration_s;
  j["mapping_s"] = r.mapping_s;
  j["wall_s"] = r.wall_s;
  j["real_time_factor"] = r.mapping_s > 0 ? r.duration_s / r.mapping_s : 0.0;
  if (r.has_truth) {
    j["driven_m"] = r.driven_m;
    j["ate_rmse_m"] = r.ate_rmse_m;
    j["elevation_drift_m"] = r.elevation_drift_m;
    j["final_error_m"] = r.final_error_m;
  }
  return j.dump(2) + "\n";
}

OctreeMap slam3d_octree(const std::vector<Slam3dKeyframe>& keyframes, const Slam3dMapConfig& config) {
  return keyframes_octree(keyframes, config.octree);
}

PlanOutcome slam3d_plan(const OccupancyGrid& grid, const Vec2& start, const Vec2& goal, double inflation_m) {
  const auto s = grid.geometry().world_to_cell(start);
  const auto g = grid.geometry().world_to_cell(goal);
  if (!s) throw Error("the first key frame lies outside the map", "", 0, "--plan-to");
  if (!g) throw Error("the goal lies outside the map", "", 0, "--plan-to");
  PlanRequest rq;
  rq.planner = "ou2022";
  rq.options.ou2022.inflation.radius_m = inflation_m;
  return plan_on_grid(grid, *s, *g, rq);
}

void write_slam3d_picture(const Slam3dRunResult& r, const OccupancyGrid& grid, const std::vector<Vec2>& path,
                          const std::string& path_svg) {
  viz::MapPicture pic(grid, {.title = "3D graph SLAM: the 2D grid of the octree map, " + r.matcher});
  if (r.has_truth) {
    const Rigid3 mount = to_rigid(r.input.mount);
    const Rigid3 to_map = r.truth_alignment.inverse();
    std::vector<Vec2> truth;
    for (const LidarFrameRecord& f : r.input.frames) truth.push_back((to_map * (to_rigid(*f.truth) * mount)).translation().head<2>());
    pic.add_polyline(truth, {.colour = {0, 0, 0, 255}, .width_px = 1.5, .dashed = true}, "truth");
  }
  std::vector<Vec2> est;
  for (const Rigid3& t : r.trajectory) est.push_back(t.translation().head<2>());
  pic.add_polyline(est, {.colour = {0, 114, 178, 255}, .width_px = 2.0}, "trajectory");
  std::vector<Vec2> kfs;
  for (const Slam3dKeyframe& k : r.keyframes) kfs.push_back(k.pose.translation().head<2>());
  pic.add_points(kfs, {}, "key frames");
  if (!path.empty()) pic.add_polyline(path, {.colour = {213, 94, 0, 255}, .width_px = 2.5}, "improved A* path");
  if (lower_extension(path_svg) == ".png") {
    pic.write_png(path_svg);
  } else {
    pic.write_svg(path_svg);
  }
}

}  // namespace starnav
