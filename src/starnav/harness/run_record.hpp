#pragma once
// The run record a viewer reads (docs/run-records.md): run.json names the run and what its folder
// holds; world.json is the simulated world (terrain, obstacles with their lifetimes and motions,
// the robot's body, the start, the goals and, for navigation, the navigator's grid and its prior
// occupancy). steps.jsonl (navigation_run.hpp) and trajectory.csv carry the run over time.
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"

namespace starnav {

class Simulation;
class NavigationRun;

// The terrain in world.json is subsampled to at most this many samples per side.
inline constexpr int kWorldTerrainMaxSide = 512;

// world.json of a run (deterministic; heights to the millimetre).
std::string world_json(const Simulation& sim, const NavigationRun* navigation = nullptr);

// world.json of a run over a robot log (SLAM): no terrain, no obstacles, the default robot's
// body for scale, the start, and `map`'s grid as nav_map, all unknown at first.
std::string map_world_json(const GridGeometry& map, const Pose2& start);

// What run.json says of a simulated run besides its schema, kind and files: the scenario's name
// and file (without folders), seed, step and duration; `live`: the scenario's duration and
// "live": true, for the manifest a live server hands out before the run has written anything.
std::string run_about_json(const Simulation& sim, bool live);
// That live manifest: its only file is world.json (served from memory); the steps come as events.
std::string live_run_manifest_json(const Simulation& sim, const std::string& kind);

// A steps.jsonl line with the true pose only ({"t_s", "pose"}: what a live scripted run streams).
std::string pose_step_json_line(double t_s, const Pose3& pose);

// Writes world.json, then run.json listing every regular file in `dir` (call last). Throws Error
// naming the file when one cannot be written.
void write_run_record(const Simulation& sim, const NavigationRun* navigation, const std::string& dir);

}  // namespace starnav
