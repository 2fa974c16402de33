#pragma once
// The improved A* of Ou et al. 2022 (docs/papers/ou2022.md): A* on the search
// core (search_core.hpp) with the policies of ou2022_policies.hpp, on a map inflated through the
// distance transform (inflation.hpp), followed by line-of-sight removal of redundant nodes
// (path_smoothing.hpp). Every feature is switchable on its own (ou2022_options.hpp).
//
// What a query reports (PlanResult):
//   path_cells / path_world  the final path: the smoothed vertices when smoothing is on (an
//                            any-angle polyline through cell centres), else the grid path;
//                            unsmoothed_path() keeps the grid path.
//   cost                     the search objective of the grid path in map units: the sum of move
//                            lengths times the multipliers of the cells entered, plus the turn
//                            costs (the paper's g; recomputed in double precision from the path).
//   length                   the geometric length of the final path.
//   expanded / generated     search states: cells, or (cell, direction) states with turn_exact.
//   time_ms                  the search, the path reconstruction and the smoothing; the per-map
//                            inflation is preprocess_ms().
// A start equal to the goal is the one-cell path with no search (expanded 0).
//
// With turn costs and cell states (the paper) the search is not optimal for the turn-inclusive
// cost: the cost of a cell depends on the direction it was entered from, which cell states
// forget. turn_exact searches (cell, incoming direction) states instead (8 per cell, 8x memory).
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/ou2022_policies.hpp"
#include "starnav/plan/search_core.hpp"

namespace starnav {

class ImprovedAStarPlanner final : public GridPlanner {
 public:
  // Options with every unset field resolved.
  struct Settings {
    int connectivity = 8;
    GridHeuristicKind heuristic = GridHeuristicKind::Octile;
    double turn_cost = 0.0;  // k_turn, 0 = no steering cost
    bool turn_exact = false;
    bool adaptive_weight = false;
    PathSmoothing smoothing = PathSmoothing::None;
    std::optional<double> start_heading_rad;
    InflationOptions inflation;
  };
  // paper_defaults = true: the `ou2022` planner (unset options take the paper's values: k_turn 1,
  // adaptive weight, line-of-sight smoothing, Manhattan); false: `astar` with the features asked
  // for. Throws Error naming the field for bad options.
  static Settings resolve(const GridPlannerOptions& options, bool paper_defaults);

  ImprovedAStarPlanner(const OccupancyGrid& grid, const GridPlannerOptions& options, bool paper_defaults);

  std::string_view name() const override { return paper_defaults_ ? "ou2022" : "astar"; }
  // False with the adaptive weight, with turn costs on cell states (not optimal for the
  // turn-inclusive cost) and with Manhattan on 8-connected grids.
  bool admissible() const override;
  PlanResult plan(Cell start, Cell goal, const SearchLimits& limits = {}) override;
  double preprocess_ms() const override { return preprocess_ms_; }
  const std::vector<Cell>& trace() const override { return trace_; }
  const std::vector<Cell>& unsmoothed_path() const override { return unsmoothed_; }

  const Settings& settings() const { return settings_; }
  // The map the search runs on (after hard inflation).
  const GridSearchMap& search_map() const { return map_; }
  const InflatedMap& inflated() const { return inflated_; }
  // The search objective of a path of adjacent cells, in map units (see the header comment).
  double path_cost(std::span<const Cell> cells) const;

 private:
  struct Query;
  template <int Connectivity>
  void run_connectivity(Query& q);
  template <int Connectivity, class CostModel>
  void run_cost(Query& q, CostModel cost);
  template <class Graph>
  void run_heuristic(Query& q, const Graph& graph);
  template <class Graph, class Heuristic>
  void run_weight(Query& q, const Graph& graph, Heuristic heuristic);
  template <class Graph, class Heuristic>
  void run_search(Query& q, const Graph& graph, Heuristic heuristic);

  bool paper_defaults_;
  bool record_trace_;
  Settings settings_;
  GridGeometry geometry_;
  InflatedMap inflated_;
  GridSearchMap map_;
  std::vector<std::int64_t> cardinal_cost_, diagonal_cost_;  // graded band, per padded state
  TurnCostTable<std::int64_t> turns_;
  BestFirstSearch<std::int64_t> cell_search_;
  std::unique_ptr<BestFirstSearch<std::int64_t>> directed_search_;  // turn_exact only
  double preprocess_ms_ = 0.0;
  std::vector<std::uint32_t> path_states_, trace_states_;
  std::vector<Cell> unsmoothed_, trace_;
};

// Hard inflation and line-of-sight smoothing around any other planner (JPS, JPS+, Dijkstra, ...):
// `make_inner` builds it, with options.ou2022 cleared, on the grid whose inflated cells are
// marked occupied. Search features (graded band, turn costs, adaptive weight) are refused with an
// Error naming the field: JPS prunes symmetric paths assuming uniform move costs.
using GridPlannerFactory =
    std::unique_ptr<GridPlanner> (*)(std::string_view name, const OccupancyGrid& grid, const GridPlannerOptions& options);
std::unique_ptr<GridPlanner> make_inflated_smoothed_planner(std::string_view name, const OccupancyGrid& grid,
                                                            const GridPlannerOptions& options,
                                                            GridPlannerFactory make_inner);

}  // namespace starnav
