#pragma once
// What every planner returns (conventions.md, "Moves and costs on grids"): found or why not,
// the path as cells and world points, its cost and length, node counts and the search time.
#include <atomic>
#include <cstdint>
#include <vector>

#include "starnav/core/grid_geometry.hpp"

namespace starnav {

enum class PlanStatus : std::uint8_t {
  Found,
  StartOutsideMap,
  GoalOutsideMap,
  StartBlocked,
  GoalBlocked,
  NoPath,
  ExpansionLimit,
  TimeLimit,
  Cancelled,
};

// snake_case reason for JSON output: "found", "start_outside_map", "goal_outside_map",
// "start_blocked", "goal_blocked", "no_path", "expansion_limit", "time_limit", "cancelled".
inline const char* plan_status_reason(PlanStatus s) {
  switch (s) {
    case PlanStatus::Found: return "found";
    case PlanStatus::StartOutsideMap: return "start_outside_map";
    case PlanStatus::GoalOutsideMap: return "goal_outside_map";
    case PlanStatus::StartBlocked: return "start_blocked";
    case PlanStatus::GoalBlocked: return "goal_blocked";
    case PlanStatus::NoPath: return "no_path";
    case PlanStatus::ExpansionLimit: return "expansion_limit";
    case PlanStatus::TimeLimit: return "time_limit";
    case PlanStatus::Cancelled: return "cancelled";
  }
  return "unknown";
}

// Optional limits every search honours; zero means "no limit".
struct SearchLimits {
  std::uint64_t max_expansions = 0;
  double time_budget_s = 0.0;
  const std::atomic<bool>* cancel = nullptr;
};

struct PlanResult {
  PlanStatus status = PlanStatus::NoPath;
  std::vector<Cell> path_cells;  // start .. goal inclusive
  std::vector<Vec2> path_world;  // world points of the path (cell centres, or any-angle vertices)
  // Planners between poses (capability "needs_headings"): the path's poses (map frame), and per
  // pose 1 when the motion leaving it (for the last pose, arriving at it) drives in reverse.
  // Empty for the grid planners.
  std::vector<Pose2> path_poses;
  std::vector<std::uint8_t> path_reversing;
  double cost = 0.0;             // the planner's objective
  double length = 0.0;           // geometric length in map units (metres; cells on index maps)
  std::uint64_t expanded = 0;    // popped from the open list and closed
  std::uint64_t generated = 0;   // pushed onto the open list
  double time_ms = 0.0;          // wall time of the search alone

  bool found() const { return status == PlanStatus::Found; }
};

}  // namespace starnav
