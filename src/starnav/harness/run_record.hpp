#pragma once
// The run record a viewer reads (docs/run-records.md): run.json names the run and what its folder
// holds; world.json is the simulated world (terrain, obstacles with their lifetimes and motions,
// the robot's body, the start, the goals and, for navigation, the navigator's grid and its prior
// occupancy). steps.jsonl (navigation_run.hpp) and trajectory.csv carry the run over time.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

class Simulation;
class NavigationRun;
class LocalizationChain;

// The most particles a step of steps.jsonl carries (drawn evenly from the set).
inline constexpr std::size_t kStepParticles = 200;
// The terrain in world.json is subsampled to at most this many samples per side.
inline constexpr int kWorldTerrainMaxSide = 512;

// world.json of a run (deterministic; heights to the millimetre).
std::string world_json(const Simulation& sim, const NavigationRun* navigation = nullptr);

// world.json of a run over a robot log: no terrain, no obstacles, the default robot's body for
// scale, the start, and `map`'s grid as nav_map: its cells from the start when the map is `known`
// (localization), all unknown at first when the run builds it (SLAM).
std::string map_world_json(const OccupancyGrid& map, bool known, const Pose2& start);
// The same without a map (a run that built none): no nav_map.
std::string map_world_json(const OccupancyGrid* map, bool known, const Pose2& start);

// The run record of a run over a robot log (SLAM, localization, 3D SLAM): steps.jsonl, world.json, then
// run.json of `kind` with the log's file name and the method, on the log's clock (start_s, the
// first step's stamp; duration_s to the last's).
void write_log_run_record(const std::string& dir, const std::string& kind, const std::string& log, const std::string& method,
                          std::int64_t first_us, std::int64_t last_us, const std::string& steps_jsonl,
                          const std::string& world_json);

// What run.json says of a simulated run besides its schema, kind and files: the scenario's name
// and file (without folders), seed, step and duration; `live`: the scenario's duration and
// "live": true, for the manifest a live server hands out before the run has written anything.
std::string run_about_json(const Simulation& sim, bool live);
// That live manifest: its only file is world.json (served from memory); the steps come as events.
std::string live_run_manifest_json(const Simulation& sim, const std::string& kind);

// A steps.jsonl line with the true pose only ({"t_s", "pose"}: what a live scripted run streams).
std::string pose_step_json_line(double t_s, const Pose3& pose);

// The steps.jsonl of a scripted run with a LiDAR (docs/run-records.md): per scan the true pose,
// the returns (at most kStepHits, every k-th) and, with a localization chain, its estimate
// and at most `max_particles` of its belief. A recorder of the first LiDAR's scans: the
// chain's estimators see each scan before it does. Keep it alive while the simulation runs.
// The most returns a step carries in runs that keep no obstacle cells (scripted runs, logs).
inline constexpr std::size_t kStepHits = 180;
class ScanStepRecorder {
 public:
  ScanStepRecorder(Simulation& sim, const LocalizationChain* chain, std::size_t max_particles = kStepParticles);
  ScanStepRecorder(const ScanStepRecorder&) = delete;
  ScanStepRecorder& operator=(const ScanStepRecorder&) = delete;
  std::string steps_jsonl() const;
  std::size_t steps() const { return lines_.size(); }
  // Called with each line as it is recorded (a live viewer's feed).
  std::function<void(const std::string&)> on_line;

 private:
  std::vector<std::string> lines_;
};

// Writes world.json, then run.json listing every regular file in `dir` (call last). Throws Error
// naming the file when one cannot be written.
void write_run_record(const Simulation& sim, const NavigationRun* navigation, const std::string& dir);

}  // namespace starnav
