#pragma once
// The run record a viewer reads (docs/run-records.md): run.json names the run and what its folder
// holds; world.json is the simulated world (terrain, obstacles with their lifetimes and motions,
// the robot's body, the start, the goals and, for navigation, the navigator's grid and its prior
// occupancy). steps.jsonl (navigation_run.hpp) and trajectory.csv carry the run over time.
#include <string>
#include <vector>

namespace starnav {

class Simulation;
class NavigationRun;

// The terrain in world.json is subsampled to at most this many samples per side.
inline constexpr int kWorldTerrainMaxSide = 512;

// world.json of a run (deterministic; heights to the millimetre).
std::string world_json(const Simulation& sim, const NavigationRun* navigation = nullptr);

// run.json: schema and version, kind ("simulation" or "navigation"), the scenario's name, file,
// seed, step and duration, and the files of the folder (plain names, sorted; run.json itself excluded).
// `live`: the manifest a live server hands out before the run has written anything (its steps
// come as events; "live": true and the scenario's duration).
std::string run_manifest_json(const Simulation& sim, const std::string& kind, const std::vector<std::string>& files,
                              bool live = false);

// Writes world.json, then run.json listing every regular file in `dir` (call last). Throws Error
// naming the file when one cannot be written.
void write_run_record(const Simulation& sim, const NavigationRun* navigation, const std::string& dir);

}  // namespace starnav
