#include "starnav/harness/slam_report.hpp"

#include <malloc.h>
#include <sys/resource.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/harness/run_record.hpp"
#include "starnav/harness/slam_run.hpp"
#include "starnav/logs/robot_log_source.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav {

nlohmann::ordered_json rpe_summary_json(const RelativePoseError& e) {
  nlohmann::ordered_json j;
  j["translation_m"] = {{"mean", e.translation_m.mean}, {"sd", e.translation_m.sd}, {"p95", e.translation_p95_m}, {"max", e.translation_m.max}};
  j["rotation_deg"] = {{"mean", e.rotation_deg.mean}, {"sd", e.rotation_deg.sd}, {"max", e.rotation_deg.max}};
  j["count"] = e.translation_m.n;
  j["relations"] = e.relations;
  j["unmatched"] = e.unmatched;
  return j;
}

namespace {

bool is_zero(const Pose2& p) { return p.x == 0.0 && p.y == 0.0 && p.yaw == 0.0; }

}  // namespace

std::size_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return static_cast<std::size_t>(std::strtoull(line.c_str() + 6, nullptr, 10)) * 1024;
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return static_cast<std::size_t>(u.ru_maxrss) * 1024;  // Linux reports KiB
}

void reset_peak_rss() {
  malloc_trim(0);  // hand freed memory back, so the resident set starts from what is in use
  std::ofstream clear("/proc/self/clear_refs");
  if (clear) clear << "5";  // resets VmHWM to the current resident set
}

SlamRunResult run_slam_on_file(const SlamRunRequest& q, const std::function<void(std::size_t, std::size_t)>& progress) {
  reset_peak_rss();
  std::vector<PoseRelation> relations;
  if (!q.relations.empty()) relations = read_relations(q.relations);
  q.mapping.validate();
  // The method and its parameters (what their searches would cost) are judged before the log is read.
  SlamChoice choice;
  choice.method = q.method;
  choice.settings = q.settings;
  choice.file = q.log;
  std::unique_ptr<Slam> slam = make_slam(choice);
  if (slam->space() != SlamSpace::Planar)
    throw Error("'" + q.method + "' maps 3D clouds, not a log's planar scans (starnav slam3d runs it)", {}, 0, "--method");
  const RobotLog log = read_robot_log(q.log, q.read);
  SlamRunResult r;
  r.log = q.log;
  r.method = std::string(slam->name());
  r.scans = log.scans.size();
  const RobotLogSummary s = summarise_log(log);
  r.log_duration_s = static_cast<double>(s.last_us - s.first_us) * 1e-6;
  r.laser_in_base = log.laser_in_base.value_or(Pose2());
  RobotLogSource source(log);
  const SlamDriveTimes times = drive_slam(*slam, source, {}, progress);
  r.cpu_s = times.cpu_s;
  r.wall_s = times.wall_s;
  r.trajectory = planar_trajectory(slam->trajectory());
  if (r.trajectory.empty()) throw Error("no scan has an odometry pose to start from", q.log, 0, "LOG");
  r.graph = slam->graph();
  r.statistics = slam->statistics();
  MapScanObserver observer;
  if (q.record_steps)
    observer = [&r](const LogScan& scan, const Pose2& base, const Pose2& sensor, const std::vector<MapCellChange>& changes) {
      SlamViewStep step;
      step.stamp_us = scan.stamp_us;
      step.base = base;
      step.changes = changes;
      step.hits = scan.end_points(sensor, kStepHits);
      r.steps.push_back(std::move(step));
    };
  r.map = map_log(log, r.trajectory, q.mapping, observer).grid;
  r.peak_rss_bytes = peak_rss_bytes();
  if (!log.truth.empty()) {
    r.ate = absolute_trajectory_error(r.trajectory, log);
    r.ate_odometry = absolute_trajectory_error(odometry_trajectory(log), log);
  }
  if (!relations.empty()) {
    r.rpe = relative_pose_error(r.trajectory, relations);
    if (!is_zero(r.laser_in_base)) r.rpe_laser = relative_pose_error(r.trajectory, relations, r.laser_in_base);
    r.rpe_odometry = relative_pose_error(odometry_trajectory(log), relations, r.rpe_laser ? r.laser_in_base : Pose2());
    r.worse_than_odometry = relations_worse_than(r.rpe_evaluated(), *r.rpe_odometry);
    r.worse_than_odometry_by_1m = relations_worse_than(r.rpe_evaluated(), *r.rpe_odometry, 1.0);
    r.rpe_spans = relation_spans(r.rpe_evaluated(), relations);
  }
  return r;
}

BenchmarkRelations log_benchmark_relations(const std::string& log, const LogReadOptions& read, const RelationRule& rule) {
  return make_benchmark_relations(log_truth_at_scans(read_robot_log(log, read)), rule);
}

nlohmann::ordered_json slam_summary_json(const SlamRunResult& r) {
  nlohmann::ordered_json j;
  j["log"] = r.log;
  j["method"] = r.method;
  j["scans"] = r.scans;
  j["poses"] = r.trajectory.size();
  j["nodes"] = r.graph.nodes.size();
  j["loop_closures"] = r.graph.closures();
  j["log_duration_s"] = r.log_duration_s;
  j["cpu_s"] = r.cpu_s;
  j["wall_s"] = r.wall_s;
  j["real_time_factor"] = r.real_time_factor();
  j["peak_rss_mb"] = static_cast<double>(r.peak_rss_bytes) / 1e6;
  nlohmann::ordered_json st;
  for (const auto& [k, v] : r.statistics) st[k] = v;
  j["statistics"] = st;
  j["laser_in_base"] = {r.laser_in_base.x, r.laser_in_base.y, r.laser_in_base.yaw};
  const auto ate = [](const AbsoluteTrajectoryError& e) {
    return nlohmann::ordered_json{{"rmse_m", e.rmse_m},
                                  {"translation_m", {{"mean", e.translation_m.mean}, {"max", e.translation_m.max}}},
                                  {"rotation_deg", {{"mean", e.rotation_deg.mean}, {"max", e.rotation_deg.max}}},
                                  {"poses", e.translation_m.n}};
  };
  if (r.ate) j["ate"] = ate(*r.ate);
  if (r.ate_odometry) j["ate_odometry"] = ate(*r.ate_odometry);
  if (r.rpe) j["rpe_base"] = rpe_summary_json(*r.rpe);
  if (r.rpe_laser) j["rpe_laser"] = rpe_summary_json(*r.rpe_laser);
  if (r.rpe_odometry) {
    j["rpe_odometry"] = rpe_summary_json(*r.rpe_odometry);
    j["worse_than_odometry"] = r.worse_than_odometry;
    j["worse_than_odometry_by_1m"] = r.worse_than_odometry_by_1m;
  }
  if (r.rpe_spans) j["rpe_spans"] = relation_spans_json(*r.rpe_spans);
  return j;
}

nlohmann::ordered_json relation_spans_json(const RelationSpans& s) {
  const auto part = [](const SampleStats& v, double p95) {
    return nlohmann::ordered_json{{"relations", v.n}, {"mean", v.mean}, {"p95", p95}, {"max", v.max}};
  };
  nlohmann::ordered_json j;
  j["max_short_s"] = kShortRelationS;
  j["short_m"] = part(s.short_m, s.short_p95_m);
  j["long_m"] = part(s.long_m, s.long_p95_m);
  return j;
}

std::string slam_summary_text(const SlamRunResult& r) {
  std::ostringstream o;
  o << "slam (" << r.method << "): " << r.trajectory.size() << " poses, " << r.graph.nodes.size() << " nodes, " << r.graph.closures()
    << " loop closures; " << format_fixed(r.cpu_s, 2) << " s CPU for " << format_fixed(r.log_duration_s, 1) << " s of log ("
    << format_fixed(r.real_time_factor(), 1) << "x real time), peak memory " << format_fixed(static_cast<double>(r.peak_rss_bytes) / 1e6, 0)
    << " MB\n";
  const auto line = [&](const char* what, const RelativePoseError& e) {
    o << "rpe (" << what << "): translation " << format_fixed(e.translation_m.mean, 4) << " m (sd " << format_fixed(e.translation_m.sd, 4)
      << "), rotation " << format_fixed(e.rotation_deg.mean, 3) << " deg (sd " << format_fixed(e.rotation_deg.sd, 3) << ") over "
      << e.translation_m.n << " relations, p95 " << format_fixed(e.translation_p95_m, 4) << " m, max " << format_fixed(e.translation_m.max, 4)
      << " m";
    if (e.unmatched) o << ", " << e.unmatched << " unmatched";
    o << "\n";
  };
  const auto ate_line = [&](const char* what, const AbsoluteTrajectoryError& e) {
    o << "ate (" << what << "): RMSE " << format_fixed(e.rmse_m, 4) << " m, mean " << format_fixed(e.translation_m.mean, 4) << " m, max "
      << format_fixed(e.translation_m.max, 4) << " m, yaw mean " << format_fixed(e.rotation_deg.mean, 3) << " deg over " << e.translation_m.n
      << " poses\n";
  };
  if (r.ate) ate_line("slam", *r.ate);
  if (r.ate_odometry) ate_line("odometry", *r.ate_odometry);
  if (r.rpe) line("base", *r.rpe);
  if (r.rpe_laser) line("laser", *r.rpe_laser);
  if (r.rpe_odometry) {
    line(r.rpe_laser ? "odometry, laser" : "odometry", *r.rpe_odometry);
    o << "relations worse than the odometry's: " << r.worse_than_odometry << " (by more than 1 m: " << r.worse_than_odometry_by_1m << ")\n";
  }
  if (r.rpe_spans)
    o << "short relations (at most " << format_fixed(kShortRelationS, 0) << " s apart): " << r.rpe_spans->short_m.n << ", mean "
      << format_fixed(r.rpe_spans->short_m.mean, 4) << " m; long: " << r.rpe_spans->long_m.n << ", mean "
      << format_fixed(r.rpe_spans->long_m.mean, 4) << " m, max " << format_fixed(r.rpe_spans->long_m.max, 4) << " m\n";
  return o.str();
}

std::string pose_graph_json(const SlamGraph& g) {
  nlohmann::ordered_json j;
  nlohmann::ordered_json nodes = nlohmann::ordered_json::array();
  for (const TrajectoryPose& n : g.nodes) nodes.push_back({format_stamp_us(n.stamp_us), n.pose.x, n.pose.y, n.pose.yaw});
  nlohmann::ordered_json edges = nlohmann::ordered_json::array();
  for (const SlamGraphEdge& e : g.edges)
    edges.push_back({{"from", e.from},
                     {"to", e.to},
                     {"kind", slam_edge_kind_name(e.kind)},
                     {"measurement", {e.measurement.x, e.measurement.y, e.measurement.yaw}},
                     {"score", e.score}});
  j["node_fields"] = {"t_s", "x_m", "y_m", "yaw_rad"};
  j["nodes"] = std::move(nodes);
  j["edges"] = std::move(edges);
  j["submap_anchors"] = g.submap_anchors;
  return j.dump(1) + "\n";
}

void write_slam_picture(const SlamRunResult& r, const std::string& path) {
  viz::PictureOptions options;
  options.title = std::filesystem::path(r.log).filename().string() + ": " + r.method + " SLAM";
  viz::MapPicture pic(r.map, options);
  std::vector<Vec2> trajectory;
  trajectory.reserve(r.trajectory.size());
  for (const TrajectoryPose& p : r.trajectory) trajectory.push_back(p.pose.translation());
  bool labelled = false;
  for (const SlamGraphEdge& e : r.graph.edges) {
    if (e.kind == SlamEdgeKind::Local) continue;
    pic.add_polyline({r.graph.nodes[e.from].pose.translation(), r.graph.nodes[e.to].pose.translation()},
                     {.colour = {213, 94, 0, 255}, .width_px = 0.5, .opacity = 0.12}, labelled ? "" : "loop closures");
    labelled = true;
  }
  // The trajectory over the closures (there may be thousands of them, drawn faint).
  pic.add_polyline(std::move(trajectory), {.colour = {0, 114, 178, 255}, .width_px = 1.2, .opacity = 0.9}, "trajectory");
  if (path.size() > 4 && path.substr(path.size() - 4) == ".svg") pic.write_svg(path);
  else pic.write_png(path);
}

const std::vector<std::string>& slam_output_files() {
  static const std::vector<std::string> files = {"trajectory.csv", "map.yaml",   "map.pgm",    "pose_graph.json", "map.png",
                                                 "summary.json",   "steps.jsonl", "world.json", "run.json"};
  return files;
}

std::string slam_steps_jsonl(const SlamRunResult& r) {
  if (r.steps.empty()) return {};
  const GridGeometry& g = r.map.geometry();
  const auto lattice_x0 = static_cast<std::int64_t>(std::llround(g.origin.x / g.resolution));
  const auto lattice_y0 = static_cast<std::int64_t>(std::llround(g.origin.y / g.resolution));
  // Each loop closure shows when the later of its two nodes was added.
  std::map<std::int64_t, std::vector<std::pair<Vec2, Vec2>>> closures_at;
  for (const SlamGraphEdge& e : r.graph.edges) {
    if (e.kind == SlamEdgeKind::Local) continue;
    const TrajectoryPose& a = r.graph.nodes[e.from];
    const TrajectoryPose& b = r.graph.nodes[e.to];
    closures_at[std::max(a.stamp_us, b.stamp_us)].emplace_back(a.pose.translation(), b.pose.translation());
  }
  std::string out;
  for (const SlamViewStep& s : r.steps) {
    nlohmann::ordered_json j;
    j["t_s"] = round_mm(static_cast<double>(s.stamp_us) * 1e-6);  // the log's clock, as trajectory.csv
    j["pose"] = {round_mm(s.base.x), round_mm(s.base.y), 0.0, 0.0, 0.0, round_mm(wrap_angle(s.base.yaw))};
    nlohmann::ordered_json hits = nlohmann::ordered_json::array();
    for (const Vec2& h : s.hits) hits.push_back({round_cm(h.x()), round_cm(h.y()), 0.0});
    j["hits"] = std::move(hits);
    nlohmann::ordered_json changed = nlohmann::ordered_json::array();
    for (const MapCellChange& c : s.changes)
      changed.push_back({c.ix - lattice_x0, c.iy - lattice_y0, static_cast<int>(c.value)});
    j["changed"] = std::move(changed);
    if (const auto it = closures_at.find(s.stamp_us); it != closures_at.end()) {
      nlohmann::ordered_json loops = nlohmann::ordered_json::array();
      for (const auto& [a, b] : it->second) loops.push_back({round_mm(a.x()), round_mm(a.y()), round_mm(b.x()), round_mm(b.y())});
      j["loop_closures"] = std::move(loops);
    }
    out += j.dump() + '\n';
  }
  return out;
}

std::string slam_world_json(const SlamRunResult& r) {
  return map_world_json(r.map, false, r.trajectory.empty() ? Pose2() : r.trajectory.front().pose);
}

void write_slam_outputs(const SlamRunResult& r, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const fs::path d(dir);
  write_file_bytes((d / "trajectory.csv").string(), trajectory_csv(r.trajectory));
  write_ros_map(r.map, (d / "map.yaml").string());
  write_file_bytes((d / "pose_graph.json").string(), pose_graph_json(r.graph));
  write_slam_picture(r, (d / "map.png").string());
  write_file_bytes((d / "summary.json").string(), slam_summary_json(r).dump(1) + "\n");
  if (!r.steps.empty())
    write_log_run_record(dir, "slam", r.log, r.method, r.steps.front().stamp_us, r.steps.back().stamp_us, slam_steps_jsonl(r),
                         slam_world_json(r));
}

}  // namespace starnav
