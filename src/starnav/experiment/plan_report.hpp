#pragma once
// How `starnav plan` reports a query on an occupancy map, as library calls: the JSON object, the
// text summary, the path as CSV and the picture (map, inflation, expanded cells, the path before
// and after smoothing, start and goal). Points are in the map's units: cells on index grids
// (MovingAI), metres on metric maps.
#include <string>

#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/plan_pipeline.hpp"

namespace starnav {

struct PlanReportContext {
  const OccupancyGrid* grid = nullptr;
  Cell start{}, goal{};
  bool index_grid = false;  // MovingAI or y_down: report cells
  bool expanded = false;    // the planner recorded its expanded cells (record_trace)
};

std::string plan_json(const PlanOutcome& outcome, const PlanReportContext& c);  // one line
std::string plan_text(const PlanOutcome& outcome, const PlanReportContext& c);
// The reported path: the smoothed points, or the cells (index grids), or metres and cells.
std::string plan_path_csv(const PlanOutcome& outcome, const PlanReportContext& c);
// SVG or PNG by extension; throws Error naming the file when it cannot be written.
void write_plan_picture(const PlanOutcome& outcome, const PlanReportContext& c, const GridPlannerOptions& options,
                        const std::string& path);

// A query of a planner between poses (capability needs_headings, e.g. hybrid_astar), in metres:
// planner, found, reason (when not), cost, length, units, expanded, generated, cusps (changes
// between forward and reverse), reverse_length (metres driven backwards), path ([x, y, yaw] per
// pose, yaw in radians), reversing (1 where the motion leaving the pose, for the last one
// arriving at it, is in reverse), path_cells, time_ms.
std::string pose_plan_json(const std::string& planner, const PlanResult& r);  // one line
std::string pose_plan_text(const std::string& planner, const PlanResult& r);
// x_m,y_m,yaw_rad,reverse: one line per pose.
std::string pose_plan_csv(const PlanResult& r);

}  // namespace starnav
