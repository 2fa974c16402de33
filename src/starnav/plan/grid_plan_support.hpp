#pragma once
// Helpers shared by the grid planners: the checks every query makes before searching (outside
// the map, blocked) and turning a list of cells into a PlanResult (world points, cost, length).
#include <chrono>
#include <optional>
#include <vector>

#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/plan_result.hpp"
#include "starnav/plan/search_core.hpp"

namespace starnav {

// Why a query cannot even start (start/goal outside the map or blocked), or nothing.
std::optional<PlanStatus> check_endpoints(const GridSearchMap& map, Cell start, Cell goal);

// Fills path_cells, path_world (cell centres), length and cost (both the sum of the straight
// segments between consecutive cells, times the resolution) and sets status Found.
void set_found_path(PlanResult& result, const GridGeometry& geometry, std::vector<Cell> cells);

// The result status of a search that did not find the goal (or did).
inline PlanStatus plan_status_of(SearchOutcome outcome) {
  switch (outcome) {
    case SearchOutcome::Found: return PlanStatus::Found;
    case SearchOutcome::Exhausted: return PlanStatus::NoPath;
    case SearchOutcome::ExpansionLimit: return PlanStatus::ExpansionLimit;
    case SearchOutcome::TimeLimit: return PlanStatus::TimeLimit;
    case SearchOutcome::Cancelled: return PlanStatus::Cancelled;
  }
  return PlanStatus::NoPath;
}

// Milliseconds since `since`.
inline double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace starnav
