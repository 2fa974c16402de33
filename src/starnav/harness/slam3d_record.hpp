#pragma once
// The run record of a `starnav slam3d` run (docs/run-records.md), so that `starnav view` shows it:
// the base's optimised pose per frame, each key frame's cloud (a subsample) where it was taken,
// the loop closures, the 2D grid the octree projects to (known from the start: the map is made
// from the final poses, not frame by frame) and the planned path, if any, at the run's end.
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

}  // namespace starnav
