#pragma once
// The run record of a `starnav slam3d` run (docs/run-records.md), so that `starnav view` shows it:
// the base's optimised pose per frame, each key frame's cloud (a subsample) where it was taken,
// the loop closures, the 2D grid the octree projects to (known from the start: the map is made
// from the final poses, not frame by frame) and the planned path, if any, at the run's end.
#include <optional>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/harness/slam3d_run.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// steps.jsonl: one line per frame, in time order.
std::string slam3d_steps_jsonl(const Slam3dRunResult& r, const std::vector<Vec2>& path);

// Writes steps.jsonl, world.json and run.json (kind "slam3d", call last: it lists the folder) for
// the run read from `input`; `grid` is the projected map (nullptr: none was built).
void write_slam3d_run_record(const std::string& dir, const std::string& input, const Slam3dRunResult& r, const OccupancyGrid* grid,
                             const std::vector<Vec2>& path);

// Every file of `starnav slam3d --out DIR` (the CLI and Python's Slam3dRun.write call this one
// function, so their files are the same bytes): trajectory.csv, keyframes.csv, summary.json; with
// the map, the octree (map.bt), its 2D grid (map.yaml + map.pgm), the path to `plan_to` (path.csv)
// and the pictures (map.svg, map.png); the run record last. Errors name the file and `field`.
struct Slam3dOutputConfig {
  bool map = true;
  Slam3dMapConfig map_config;
  std::optional<Vec2> plan_to;  // map frame (m): the improved A* from the first key frame
  double inflation_m = 0.35;
  std::string field = "--out";  // what write errors name
};
struct Slam3dOutputs {
  std::optional<PlanOutcome> plan;  // when plan_to was given
  std::vector<Vec2> path;           // its path (empty: none found)
};
Slam3dOutputs write_slam3d_outputs(const Slam3dRunResult& r, const std::string& input, const std::string& dir,
                                   const Slam3dOutputConfig& config);

}  // namespace starnav
