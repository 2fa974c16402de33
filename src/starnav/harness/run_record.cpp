#include "starnav/harness/run_record.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <variant>

#include "starnav/core/record_format.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/sim/simulation.hpp"
#include "starnav/view/run_folder.hpp"

namespace starnav {

namespace {

using Json = nlohmann::ordered_json;


Json vec3_json(const Vec3& v) { return Json::array({round_mm(v.x()), round_mm(v.y()), round_mm(v.z())}); }

// A time that may be infinite (an obstacle that never disappears): null.
Json time_json(double t) { return std::isfinite(t) ? Json(round_mm(t)) : Json(nullptr); }

Json pose2_json(const Pose2& p) { return Json::array({round_mm(p.x), round_mm(p.y), round_mm(p.yaw)}); }

// One part: its kind and its numbers in a fixed order (docs/run-records.md).
Json part_json(const Primitive& part) {
  return std::visit(
      [](const auto& p) -> Json {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, Box>) {
          return Json::array({"box", round_mm(p.center.x()), round_mm(p.center.y()), round_mm(p.center.z()), round_mm(p.size.x()),
                              round_mm(p.size.y()), round_mm(p.size.z()), round_mm(p.roll), round_mm(p.pitch), round_mm(p.yaw)});
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          return Json::array({"cylinder", round_mm(p.base.x()), round_mm(p.base.y()), round_mm(p.base.z()), round_mm(p.radius),
                              round_mm(p.height)});
        } else if constexpr (std::is_same_v<T, Prism>) {
          return Json::array({"prism", round_mm(p.base.x()), round_mm(p.base.y()), round_mm(p.base.z()), round_mm(p.yaw),
                              round_mm(p.base_width), round_mm(p.height), round_mm(p.apex_offset), round_mm(p.length)});
        } else {
          return Json::array({"sphere", round_mm(p.center.x()), round_mm(p.center.y()), round_mm(p.center.z()), round_mm(p.radius)});
        }
      },
      part);
}

Json obstacle_json(const Obstacle& o) {
  Json j;
  j["name"] = o.name;
  j["appear_s"] = time_json(o.appear);
  j["disappear_s"] = time_json(o.disappear);
  j["anchor"] = vec3_json(o.anchor);
  if (o.velocity != Vec3::Zero()) j["velocity"] = vec3_json(o.velocity);
  if (!o.waypoints.empty()) {
    Json w = Json::array();
    for (const Waypoint& p : o.waypoints) w.push_back({round_mm(p.time), round_mm(p.position.x()), round_mm(p.position.y()), round_mm(p.position.z())});
    j["waypoints"] = std::move(w);
  }
  Json parts = Json::array();
  for (const Primitive& p : o.parts) parts.push_back(part_json(p));
  j["parts"] = std::move(parts);
  return j;
}

Json geometry_json(const GridGeometry& g) {
  return Json{{"width", g.width}, {"height", g.height}, {"resolution_m", g.resolution}, {"origin", pose2_json(g.origin)}};
}

// The terrain, every stride-th sample in x and y (row-major from the origin corner, null where
// unobserved): a mesh for the eye, not a map to plan on.
Json terrain_json(const ElevationMap& map) {
  const int stride = std::max(1, static_cast<int>(std::ceil(static_cast<double>(std::max(map.width(), map.height())) /
                                                            kWorldTerrainMaxSide)));
  const int w = (map.width() + stride - 1) / stride, h = (map.height() + stride - 1) / stride;
  Json j = geometry_json(map.geometry());
  j["stride"] = stride;
  j["samples_x"] = w;
  j["samples_y"] = h;
  Json heights = Json::array();
  for (int sy = 0; sy < h; ++sy)
    for (int sx = 0; sx < w; ++sx) {
      const int ix = sx * stride, iy = sy * stride;
      if (map.observed_at(ix, iy) && std::isfinite(map.height_at(ix, iy)))
        heights.push_back(round_mm(map.height_at(ix, iy)));
      else
        heights.push_back(nullptr);
    }
  j["heights"] = std::move(heights);
  return j;
}

Json robot_json(const RobotConfig& r) {
  return Json{{"drive", drive_kind_name(r.drive)},
              {"body_length_m", r.body_length_m},
              {"body_width_m", r.body_width_m},
              {"body_height_m", r.body_height_m},
              {"ground_clearance_m", r.ground_clearance_m},
              {"wheel_radius_m", r.wheel_radius_m},
              {"half_track_m", r.half_track_m},
              {"half_wheelbase_m", r.half_wheelbase_m},
              {"body_center_x_m", r.drive == DriveKind::Ackermann ? r.half_wheelbase_m : 0.0}};
}

// Run-length pairs [value, count, value, count, ...] of a row-major grid.
Json run_lengths_json(const std::vector<std::int8_t>& cells) {
  Json out = Json::array();
  for (std::size_t i = 0; i < cells.size();) {
    std::size_t j = i;
    while (j < cells.size() && cells[j] == cells[i]) ++j;
    out.push_back(static_cast<int>(cells[i]));
    out.push_back(j - i);
    i = j;
  }
  return out;
}

}  // namespace

std::string world_json(const Simulation& sim, const NavigationRun* navigation) {
  const ScenarioSpec& spec = sim.spec();
  Json j;
  j["schema"] = "starnav-world";
  j["version"] = kRunRecordVersion;
  if (sim.terrain_map()) j["terrain"] = terrain_json(*sim.terrain_map());
  Json obstacles = Json::array();
  for (const Obstacle& o : sim.world().obstacles()) obstacles.push_back(obstacle_json(o));
  j["obstacles"] = std::move(obstacles);
  j["robot"] = robot_json(spec.vehicle.robot);
  j["start"] = pose2_json(spec.start);
  if (!spec.reference_line.empty()) {
    Json line = Json::array();
    for (const Vec2& p : spec.reference_line) line.push_back({round_mm(p.x()), round_mm(p.y())});
    j["reference_line"] = std::move(line);
  }
  if (spec.navigation) {
    Json goals = Json::array();
    for (const ScenarioGoal& g : spec.navigation->goals)
      goals.push_back({round_mm(g.position.x()), round_mm(g.position.y()), g.yaw_rad ? Json(round_mm(*g.yaw_rad)) : Json(nullptr)});
    j["goals"] = std::move(goals);
  }
  if (navigation) {
    Json map = geometry_json(navigation->navigator().map().geometry());
    map["initial"] = run_lengths_json(navigation->initial_occupancy());
    j["nav_map"] = std::move(map);
  }
  return j.dump() + "\n";
}

namespace {

Json run_about(const Simulation& sim, bool live) {
  const ScenarioSpec& spec = sim.spec();
  Json j;
  j["scenario"] = {{"name", spec.name}, {"file", std::filesystem::path(spec.file).filename().string()}};
  j["seed"] = spec.seed;
  j["dt_s"] = spec.dt_s;
  j["duration_s"] = live ? spec.duration_s : sim.time();
  if (live) j["live"] = true;
  return j;
}

}  // namespace

std::string map_world_json(const OccupancyGrid& map, bool known, const Pose2& start) { return map_world_json(&map, known, start); }

std::string map_world_json(const OccupancyGrid* map, bool known, const Pose2& start) {
  Json j;
  j["schema"] = "starnav-world";
  j["version"] = kRunRecordVersion;
  j["obstacles"] = Json::array();
  j["robot"] = robot_json(RobotConfig{});
  j["start"] = pose2_json(start);
  if (map) {
    Json m = geometry_json(map->geometry());
    if (known) {
      m["initial"] = run_lengths_json(std::vector<std::int8_t>(map->data().begin(), map->data().end()));
    } else {
      m["initial"] = {-1, map->cell_count()};
    }
    j["nav_map"] = std::move(m);
  }
  return j.dump() + "\n";
}

void write_log_run_record(const std::string& dir, const std::string& kind, const std::string& log, const std::string& method,
                          std::int64_t first_us, std::int64_t last_us, const std::string& steps_jsonl,
                          const std::string& world_json) {
  const std::filesystem::path d(dir);
  write_file_bytes((d / "steps.jsonl").string(), steps_jsonl);
  write_file_bytes((d / "world.json").string(), world_json);
  Json about;
  about["log"] = {{"name", std::filesystem::path(log).filename().string()}, {"method", method}};
  about["start_s"] = round_mm(static_cast<double>(first_us) * 1e-6);
  about["duration_s"] = static_cast<double>(last_us - first_us) * 1e-6;
  write_run_manifest(dir, kind, about.dump());
}

std::string run_about_json(const Simulation& sim, bool live) { return run_about(sim, live).dump(); }

std::string live_run_manifest_json(const Simulation& sim, const std::string& kind) {
  Json j;
  j["schema"] = "starnav-run";
  j["version"] = kRunRecordVersion;
  j["kind"] = kind;
  const Json about = run_about(sim, true);
  for (const auto& [key, value] : about.items()) j[key] = value;
  j["files"] = {"world.json"};
  return j.dump(2) + "\n";
}

std::string pose_step_json_line(double t_s, const Pose3& pose) {
  const Vec3 rpy = pose.rpy();
  Json j;
  j["t_s"] = round_mm(t_s);
  j["pose"] = {round_mm(pose.position.x()), round_mm(pose.position.y()), round_mm(pose.position.z()),
               round_mm(rpy.x()),           round_mm(rpy.y()),           round_mm(rpy.z())};
  return j.dump();
}

ScanStepRecorder::ScanStepRecorder(Simulation& sim, const LocalizationChain* chain, std::size_t max_particles) {
  // A record: the localizer (SampleStage::Estimate) has seen the scan, its estimate includes it.
  sim.lidar_feed("lidar").subscribe(SampleStage::Record, [this, &sim, chain, max_particles](const LidarScan& scan) {
    NavStepRecord r;
    r.t_s = scan.time;
    r.pose = sim.vehicle().state().pose;
    r.returns = scan.points_world.size();
    const std::size_t every = std::max<std::size_t>(1, (scan.points_world.size() + kStepHits - 1) / kStepHits);
    for (std::size_t i = 0; i < scan.points_world.size(); i += every) r.hits.push_back(scan.points_world[i]);
    if (chain) {
      r.estimate = chain->localizer().estimate().pose;
      r.particles = chain->localizer().belief_samples(max_particles);
    }
    lines_.push_back(step_record_json(r));
    if (on_line) on_line(lines_.back());
  });
}

std::string ScanStepRecorder::steps_jsonl() const {
  std::string out;
  for (const std::string& l : lines_) out += l + '\n';
  return out;
}

void write_run_record(const Simulation& sim, const NavigationRun* navigation, const std::string& dir) {
  write_file_bytes((std::filesystem::path(dir) / "world.json").string(), world_json(sim, navigation));
  write_run_manifest(dir, navigation ? "navigation" : "simulation", run_about_json(sim, false));
}

}  // namespace starnav
