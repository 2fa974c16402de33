#include "starnav/harness/slam3d_record.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/harness/run_record.hpp"
#include "starnav/io/ros_map.hpp"

namespace starnav {

namespace {

using Json = nlohmann::ordered_json;

// [x, y, z, roll, pitch, yaw] of a rigid transform (R = Rz(yaw) Ry(pitch) Rx(roll)), to the mm.
Json pose_json(const Rigid3& t) {
  const Eigen::Matrix3d& r = t.linear();
  const Vec3 p = t.translation();
  return {round_mm(p.x()),
          round_mm(p.y()),
          round_mm(p.z()),
          round_mm(std::atan2(r(2, 1), r(2, 2))),
          round_mm(std::asin(std::clamp(-r(2, 0), -1.0, 1.0))),
          round_mm(std::atan2(r(1, 0), r(0, 0)))};
}

// The base's pose from the sensor's: the mount (the sensor in base_link) taken off.
Rigid3 base_of(const Rigid3& sensor, const Slam3dRunResult& r) { return sensor * to_rigid(r.input.mount).inverse(); }

}  // namespace

std::string slam3d_steps_jsonl(const Slam3dRunResult& r, const std::vector<Vec2>& path) {
  std::map<std::size_t, const Slam3dKeyframe*> keyframe_at;  // by frame
  for (const Slam3dKeyframe& k : r.keyframes) keyframe_at[k.frame] = &k;
  // A loop closure shows at the frame of its later key frame.
  std::map<std::size_t, std::vector<const SlamGraphEdge*>> loops_at;
  for (const SlamGraphEdge& l : r.graph.edges)
    if (l.kind != SlamEdgeKind::Local && l.from < r.keyframes.size() && l.to < r.keyframes.size())
      loops_at[std::max(r.keyframes[l.from].frame, r.keyframes[l.to].frame)].push_back(&l);
  std::string out;
  const std::size_t n = std::min(r.trajectory.size(), r.input.frames.size());
  for (std::size_t i = 0; i < n; ++i) {
    Json j;
    j["t_s"] = round_mm(r.input.frames[i].t_s);
    j["pose"] = pose_json(base_of(r.trajectory[i], r));
    if (const auto k = keyframe_at.find(i); k != keyframe_at.end()) {
      const PointCloud& cloud = k->second->cloud;
      const std::size_t every = std::max<std::size_t>(1, (cloud.size() + kStepHits - 1) / kStepHits);
      Json hits = Json::array();
      for (std::size_t p = 0; p < cloud.size(); p += every) {
        const Vec3 w = k->second->pose * cloud[p];
        hits.push_back({round_cm(w.x()), round_cm(w.y()), round_cm(w.z())});
      }
      j["returns"] = cloud.size();
      j["hits"] = std::move(hits);
    }
    if (const auto l = loops_at.find(i); l != loops_at.end()) {
      Json loops = Json::array();
      for (const SlamGraphEdge* loop : l->second) {
        const Vec3 a = base_of(r.keyframes[loop->from].pose, r).translation(), b = base_of(r.keyframes[loop->to].pose, r).translation();
        loops.push_back({round_mm(a.x()), round_mm(a.y()), round_mm(b.x()), round_mm(b.y())});
      }
      j["loop_closures"] = std::move(loops);
    }
    // The path is planned on the finished map: it appears at the end.
    if (!path.empty() && i + 1 == n) {
      j["path_id"] = 1;
      Json points = Json::array();
      for (const Vec2& q : path) points.push_back({round_mm(q.x()), round_mm(q.y())});
      j["path"] = std::move(points);
    }
    out += j.dump() + '\n';
  }
  return out;
}

void write_slam3d_run_record(const std::string& dir, const std::string& input, const Slam3dRunResult& r, const OccupancyGrid* grid,
                             const std::vector<Vec2>& path) {
  if (r.trajectory.empty() || r.input.frames.empty()) throw Error("no frames to record", dir, 0, "--out");
  // The input's own name (a folder given with a trailing slash too).
  std::filesystem::path name = std::filesystem::path(input).lexically_normal();
  if (name.filename().empty()) name = name.parent_path();
  const auto us = [](double t) { return static_cast<std::int64_t>(std::llround(t * 1e6)); };
  const std::size_t last = std::min(r.trajectory.size(), r.input.frames.size()) - 1;
  const Rigid3 start = base_of(r.trajectory.front(), r);
  const Pose2 start_pose(start.translation().x(), start.translation().y(), std::atan2(start.linear()(1, 0), start.linear()(0, 0)));
  std::string method = "graph_slam_3d, ";  // appended: g++ 12 warns falsely (-Wrestrict) on a literal + string
  method += r.matcher;
  write_log_run_record(dir, "slam3d", name.string(), method, us(r.input.frames.front().t_s),
                       us(r.input.frames[last].t_s), slam3d_steps_jsonl(r, path), map_world_json(grid, true, start_pose));
}

namespace {

void write_slam3d_text(const std::filesystem::path& path, const std::string& text, const std::string& field) {
  try {
    write_file_atomically(path.string(), text);
  } catch (const Error& e) {
    throw Error(e.message(), path.string(), 0, field);
  }
}

}  // namespace

Slam3dOutputs write_slam3d_outputs(const Slam3dRunResult& r, const std::string& input, const std::string& dir,
                                   const Slam3dOutputConfig& config) {
  namespace fs = std::filesystem;
  Slam3dOutputs out;
  fs::create_directories(dir);
  const fs::path d(dir);
  write_slam3d_text(d / "trajectory.csv", slam3d_trajectory_csv(r), config.field);
  write_slam3d_text(d / "keyframes.csv", slam3d_keyframes_csv(r), config.field);
  write_slam3d_text(d / "summary.json", slam3d_summary_json(r), config.field);
  std::optional<OccupancyGrid> grid;
  if (config.map) {
    const OctreeMap octree = slam3d_octree(r.keyframes, config.map_config);
    octree.write((d / "map.bt").string());
    grid = octree.project_to_grid(config.map_config.grid);
    write_ros_map(*grid, (d / "map.yaml").string());
    if (config.plan_to) {
      out.plan = slam3d_plan(*grid, r.keyframes.front().pose.translation().head<2>(), *config.plan_to, config.inflation_m);
      if (out.plan->result.found()) {
        out.path = out.plan->path();
        std::string csv = "x_m,y_m\n";
        for (const Vec2& q : out.path) csv += std::to_string(q.x()) + "," + std::to_string(q.y()) + "\n";
        write_slam3d_text(d / "path.csv", csv, config.field);
      }
    }
    write_slam3d_picture(r, *grid, out.path, (d / "map.svg").string());
    write_slam3d_picture(r, *grid, out.path, (d / "map.png").string());
  }
  // The run record `starnav view` reads; last, as run.json lists the folder.
  write_slam3d_run_record(dir, input, r, grid ? &*grid : nullptr, out.path);
  return out;
}

}  // namespace starnav
