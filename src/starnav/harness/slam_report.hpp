#pragma once
// `starnav slam run` as one library call: a log read, a registered SLAM method run over it, its
// trajectory evaluated against a benchmark relation file (base and laser poses), the map rendered
// from every scan at its SLAM pose, and the run's outputs: trajectory.csv, map.yaml + .pgm,
// pose_graph.json, map.png (the map with the trajectory and the loop closures), summary.json,
// and the run record the viewer reads (steps.jsonl, world.json, run.json).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/params.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/logs/robot_log.hpp"
#include "starnav/slam/benchmark_relations.hpp"
#include "starnav/slam/relative_pose_error.hpp"
#include "starnav/slam/log_mapping.hpp"
#include "starnav/slam/slam.hpp"
#include "starnav/slam/trajectory_error.hpp"

namespace starnav {

struct SlamRunRequest {
  std::string log;                        // path
  LogReadOptions read;                    // reader options (FLASER beam angles)
  std::string method = "graph";           // a registered SLAM method
  std::vector<ParamSetting> settings;     // its parameters
  std::string relations;                  // optional benchmark relation file
  OccupancyMappingParams mapping;         // the written map
  bool record_steps = true;               // the viewer's steps (steps.jsonl): poses, scans, map updates
};

// One mapped scan as the viewer replays it: the base pose, the scan's end points (world frame,
// every k-th beam: at most kStepHits) and the map cells it changed (lattice indices).
struct SlamViewStep {
  std::int64_t stamp_us = 0;
  Pose2 base;
  std::vector<Vec2> hits;
  std::vector<MapCellChange> changes;
};

struct SlamRunResult {
  std::string log;
  std::string method;
  std::size_t scans = 0;                 // in the log
  double log_duration_s = 0.0;
  std::vector<TrajectoryPose> trajectory;
  SlamGraph graph;
  std::vector<std::pair<std::string, double>> statistics;
  OccupancyGrid map;
  double cpu_s = 0.0, wall_s = 0.0;      // the SLAM run (thread CPU, wall), reading and mapping aside
  std::size_t peak_rss_bytes = 0;        // of the process while reading, running and mapping
  Pose2 laser_in_base;
  std::optional<RelativePoseError> rpe, rpe_laser;  // with relations; laser: when the mount is not zero
  // With relations: the odometry alone on them, evaluated as the run's evaluated pose is (the
  // laser's where the log states a mount), and the relations SLAM gets wrong by more than it.
  std::optional<RelativePoseError> rpe_odometry;
  std::size_t worse_than_odometry = 0, worse_than_odometry_by_1m = 0;
  std::optional<RelationSpans> rpe_spans;  // the evaluated pose's error on short and long relations
  const RelativePoseError& rpe_evaluated() const { return rpe_laser ? *rpe_laser : *rpe; }
  // Logs with ground truth (simulated): the absolute trajectory error of SLAM and of the odometry.
  std::optional<AbsoluteTrajectoryError> ate, ate_odometry;
  std::vector<SlamViewStep> steps;       // with record_steps, in log order
  double real_time_factor() const { return cpu_s > 0 ? log_duration_s / cpu_s : 0.0; }
};

SlamRunResult run_slam_on_file(const SlamRunRequest& request,
                               const std::function<void(std::size_t, std::size_t)>& progress = {});

// `starnav slam relations`: a simulated log read and its truth at every scan (the laser's pose)
// made into relations by the benchmark's rule (slam/benchmark_relations.hpp).
BenchmarkRelations log_benchmark_relations(const std::string& log, const LogReadOptions& read, const RelationRule& rule);

nlohmann::ordered_json slam_summary_json(const SlamRunResult& r);
nlohmann::ordered_json relation_spans_json(const RelationSpans& spans);
// A relative-pose error as summary.json and bench slam's JSON write it: translation_m and
// rotation_deg (mean, sd, max; the translation's 95th percentile too), count, relations, unmatched.
nlohmann::ordered_json rpe_summary_json(const RelativePoseError& e);
std::string slam_summary_text(const SlamRunResult& r);
// nodes (t_s, x, y, yaw), edges (from, to, kind, measurement, score), submap anchors.
std::string pose_graph_json(const SlamGraph& graph);
// The map with the trajectory (blue), loop closures (lines from the submap's anchor to the node).
void write_slam_picture(const SlamRunResult& r, const std::string& path);
// The files a SLAM run writes into its folder: trajectory.csv, map.yaml + map.pgm,
// pose_graph.json, map.png, summary.json, and the run record: steps.jsonl, world.json, run.json.
const std::vector<std::string>& slam_output_files();
// The run record of a SLAM run (docs/run-records.md, kind "slam"): steps.jsonl, one line per
// mapped scan (t_s on the log's clock, pose, hits, changed: cells of the final map's grid,
// loop_closures found when the scan's node was added), and world.json (the final map's grid, all
// unknown at first, and the start).
std::string slam_steps_jsonl(const SlamRunResult& r);
std::string slam_world_json(const SlamRunResult& r);
// Every output into `dir` (created), with run.json last.
void write_slam_outputs(const SlamRunResult& r, const std::string& dir);

// The process's peak resident set since the last reset_peak_rss() (Linux VmHWM; bytes, 0 where
// unknown), and its reset (where the kernel allows it; otherwise the peak since the start).
std::size_t peak_rss_bytes();
void reset_peak_rss();

}  // namespace starnav
