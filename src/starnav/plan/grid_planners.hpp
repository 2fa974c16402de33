#pragma once
// The best-first grid planners built on the search core: Dijkstra, A*, weighted A* (one class,
// different heuristics) and Theta*. Construct them through make_grid_planner (grid_planner.hpp)
// or directly.
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/search_core.hpp"

namespace starnav {

// Heuristic named in options ("" = default for the connectivity: octile on 8, manhattan on 4).
// Throws Error (field "heuristic") for an unknown name.
GridHeuristicKind parse_grid_heuristic(const std::string& name, int connectivity);
const char* grid_heuristic_name(GridHeuristicKind kind);
// Whether the heuristic never overestimates on grids of this connectivity.
bool grid_heuristic_admissible(GridHeuristicKind kind, int connectivity);

// Dijkstra (zero heuristic), A* and weighted A* (f = g + w * h, w >= 1) on 4- or 8-connected
// grids. Options are checked on construction (Error naming the field).
class BestFirstGridPlanner final : public GridPlanner {
 public:
  enum class Kind { Dijkstra, AStar, WeightedAStar };
  BestFirstGridPlanner(Kind kind, const OccupancyGrid& grid, const GridPlannerOptions& options = {});

  std::string_view name() const override;
  bool admissible() const override;
  bool takes_weight() const override { return kind_ == Kind::WeightedAStar; }
  PlanResult plan(Cell start, Cell goal, const SearchLimits& limits = {}) override;
  const std::vector<Cell>& trace() const override { return trace_; }

  GridHeuristicKind heuristic() const { return heuristic_; }
  double weight() const { return weight_; }
  const GridSearchMap& search_map() const { return map_; }
  // Open-list storage reached so far (grows during warm-up, then stays).
  std::size_t open_capacity() const { return search_.open_capacity(); }

 private:
  template <int Connectivity, class Heuristic>
  PlanResult run(Cell start, Cell goal, const SearchLimits& limits, Heuristic heuristic);
  template <int Connectivity>
  PlanResult dispatch_heuristic(Cell start, Cell goal, const SearchLimits& limits);

  Kind kind_;
  int connectivity_;
  GridHeuristicKind heuristic_;
  double weight_;
  bool record_trace_;
  GridGeometry geometry_;
  GridSearchMap map_;
  BestFirstSearch<std::int64_t> search_;
  std::vector<std::uint32_t> path_states_;
  std::vector<std::uint32_t> trace_states_;
  std::vector<Cell> trace_;
};

// Theta* (Nash, Daniel, Koenig & Felner 2007): any-angle paths through cell centres, with line of
// sight under the no-corner-cutting rule (line_of_sight.hpp). Euclidean heuristic; the path
// length is at most that of the 8-connected grid path in practice but Theta* is not optimal
// among any-angle paths (admissible() is false).
class ThetaStarPlanner final : public GridPlanner {
 public:
  ThetaStarPlanner(const OccupancyGrid& grid, const GridPlannerOptions& options = {});

  std::string_view name() const override { return "thetastar"; }
  bool admissible() const override { return false; }
  PlanResult plan(Cell start, Cell goal, const SearchLimits& limits = {}) override;
  const std::vector<Cell>& trace() const override { return trace_; }

 private:
  template <int Connectivity>
  PlanResult run(Cell start, Cell goal, const SearchLimits& limits);

  int connectivity_;
  bool record_trace_;
  GridGeometry geometry_;
  GridSearchMap map_;
  BestFirstSearch<double> search_;
  std::vector<std::uint32_t> path_states_;
  std::vector<std::uint32_t> trace_states_;
  std::vector<Cell> trace_;
};

// Checks what every grid planner checks: connectivity 4 or 8, weight >= 1 and finite.
void validate_grid_planner_options(const GridPlannerOptions& options);

}  // namespace starnav
