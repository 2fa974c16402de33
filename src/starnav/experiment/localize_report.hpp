#pragma once
// `starnav localize` as one library call: AMCL (estimate/amcl) run over a recorded 2D laser log
// on a known map, its estimate at every scan, and its error against a reference log of corrected
// poses (a corrected CARMEN log: the laser poses its lines carry). The raw and the corrected
// scans are paired by identical ranges (readings at 1 cm), never by stamps, and only unique
// pairs count. Outputs: trajectory.csv, errors.csv, summary.json, map.png, and a run record.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/logs/robot_log.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// Where the particles start: a Gaussian cloud around a given base pose (the amcl initial_sigma_*
// parameters, Nav2's 0.5 m and 15 deg by default), uniform over the free space, or a cloud
// around the reference pose of the first raw scan that has a corrected twin (the run starts at
// that scan).
enum class LocalizeStart : std::uint8_t { Pose, Global, FirstMatched };
struct LocalizeInitial {
  LocalizeStart kind = LocalizeStart::FirstMatched;
  Pose2 pose;  // Pose: the base pose in the map frame
};
const char* localize_start_name(LocalizeStart s);  // "pose", "global", "first"

// AMCL's defaults on a recorded log, applied before the user's --set. A log has no real-time
// constraint, so the filter updates at every scan with 180 beams and a tighter sigma_hit (on the
// intel log: 0.078-0.082 m median error where Nav2's online defaults give 0.13 m); a global start
// adds the particles and recovery of the search phase. The simulator's online AMCL keeps Nav2's.
std::vector<ParamSetting> localize_log_defaults(LocalizeStart start);

struct LocalizeRunRequest {
  std::string log;                     // path
  LogReadOptions read;                 // reader options (FLASER beam angles)
  std::string map;                     // an occupancy map (map_server YAML, MovingAI, ...)
  std::string reference;               // optional: a log whose scans carry corrected laser poses
  LocalizeInitial initial;
  std::vector<ParamSetting> settings;  // the amcl localizer's parameters, keys relative to its section ("alpha1")
  std::uint64_t seed = 1;
  bool record_steps = true;            // the viewer's steps (steps.jsonl): one per filter update
};

// The estimate at one scan (the base pose: map <- odom of the last filter update applied to the
// odometry at the scan, as the amcl localizer reports it).
struct LocalizePose {
  std::int64_t stamp_us = 0;
  std::size_t scan = 0;  // index in the log
  Pose2 pose;
  bool converged = false;
  bool updated = false;  // a filter update happened at this scan
  int particles = 0;
};

// One raw scan with a corrected twin: the laser poses of the estimate and of the reference.
struct LocalizeError {
  std::int64_t stamp_us = 0;
  std::size_t scan = 0;
  Pose2 estimate, reference;  // laser poses, map frame
  double err_m = 0.0, err_deg = 0.0;
  bool converged = false;          // the filter's own flag at this scan
  bool after_convergence = false;  // at or after the scan where it first converged
};

struct LocalizeErrorStats {
  std::size_t n = 0;
  double median = 0.0, p90 = 0.0, max = 0.0;  // 0 when n = 0
};
// median, 90th percentile (linear between order statistics) and maximum.
LocalizeErrorStats localize_error_stats(std::vector<double> values);

// For each scan of `raw`, the index of the one scan of `reference` with the same readings
// (lround(r * 100) of every range, so %.2f and %g prints of one reading agree) that carries a
// laser pose, when exactly one raw scan and exactly one such reference scan share those readings.
std::vector<std::optional<std::size_t>> match_scans_by_ranges(const RobotLog& raw, const RobotLog& reference);

struct LocalizeRunResult {
  std::string log, map, reference;
  LocalizeInitial initial;
  Pose2 initial_pose;                    // the base pose the cloud started around (not for global)
  std::uint64_t seed = 1;
  std::size_t scans = 0;                 // in the log
  std::size_t start_scan = 0;            // the first scan run
  std::size_t scans_without_odometry = 0;
  double log_duration_s = 0.0;
  Pose2 laser_in_base;                   // the raw log's
  std::size_t reference_scans = 0;       // scans of the reference carrying a pose
  std::size_t matched = 0;               // raw scans with a unique corrected twin (in the whole log)
  int updates = 0;
  std::optional<int> converged_at_update;  // the filter update after which it first converged
  std::optional<std::size_t> converged_at_scan;
  std::vector<LocalizePose> trajectory;  // every scan run that has an odometry pose
  std::vector<LocalizeError> errors;     // the matched scans among them
  LocalizeErrorStats after_m, after_deg;  // over the errors after convergence
  LocalizeErrorStats all_m, all_deg;      // over every error
  double update_cpu_s = 0.0;             // thread CPU in Amcl::update calls that updated
  double cpu_s = 0.0, wall_s = 0.0;      // the whole run over the scans
  std::vector<std::pair<std::string, std::string>> amcl;       // every amcl parameter as used (initial aside)
  std::vector<std::pair<std::string, std::string>> overrides;  // the settings given
  OccupancyGrid grid;                    // the map (for the picture)
  std::vector<std::string> step_lines;   // with record_steps: steps.jsonl's lines (docs/run-records.md)
  double cpu_per_update_ms() const { return updates > 0 ? 1e3 * update_cpu_s / updates : 0.0; }
};

// The run on logs and a map in memory (`reference` may be null: no errors, and `first` is then
// an Error). Throws Error for bad settings, an unusable start or a log without odometry.
LocalizeRunResult run_localize(const RobotLog& log, const OccupancyGrid& map, const OccupancyThresholds& thresholds,
                               const RobotLog* reference, const LocalizeRunRequest& request,
                               const std::function<void(std::size_t, std::size_t)>& progress = {});
// Reads the log, the map and the reference named in `request`, then run_localize.
LocalizeRunResult run_localize_on_file(const LocalizeRunRequest& request,
                                       const std::function<void(std::size_t, std::size_t)>& progress = {});

nlohmann::ordered_json localize_summary_json(const LocalizeRunResult& r);
std::string localize_summary_text(const LocalizeRunResult& r);
// t_s,x_m,y_m,yaw_rad,converged,particles: the base pose at every scan run.
std::string localize_trajectory_csv(const LocalizeRunResult& r);
// t_s,err_m,err_deg,converged: the matched scans.
std::string localize_errors_csv(const LocalizeRunResult& r);
// The map with the estimated trajectory (blue) and the reference poses (orange).
void write_localize_picture(const LocalizeRunResult& r, const std::string& path);
// trajectory.csv, errors.csv, summary.json, map.png, and the run record the viewer reads
// (steps.jsonl, world.json, run.json; kind "localization").
const std::vector<std::string>& localize_output_files();
// Every output into `dir` (created).
void write_localize_outputs(const LocalizeRunResult& r, const std::string& dir);

}  // namespace starnav
