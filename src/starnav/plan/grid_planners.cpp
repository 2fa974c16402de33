#include "starnav/plan/grid_planners.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/plan/grid_plan_support.hpp"
#include "starnav/plan/line_of_sight.hpp"

namespace starnav {

namespace {

// One single-goal query on the search core, shared by the planners of this file: run, count,
// convert the trace and the path from states to cells.
template <class Search, class Graph, class Heuristic>
PlanResult run_grid_query(Search& search, const Graph& graph, Heuristic& heuristic, const GridSearchMap& map,
                          const GridGeometry& geometry, Cell start, Cell goal, const SearchLimits& limits,
                          bool record_trace, std::vector<std::uint32_t>& path_states,
                          std::vector<std::uint32_t>& trace_states, std::vector<Cell>& trace) {
  PlanResult result;
  const std::uint32_t goal_state = map.state(goal);
  heuristic.set_goal(goal_state);
  const auto started = std::chrono::steady_clock::now();
  SearchOutcome outcome;
  if (record_trace) {
    trace_states.clear();
    outcome = search.run(graph, heuristic, map.state(start), SingleGoal{goal_state}, limits,
                         TraceListener{&trace_states});
  } else {
    outcome = search.run(graph, heuristic, map.state(start), SingleGoal{goal_state}, limits);
  }
  result.time_ms = elapsed_ms(started);
  result.expanded = search.stats().expanded;
  result.generated = search.stats().generated;
  if (record_trace) {
    trace.clear();
    trace.reserve(trace_states.size());
    for (const std::uint32_t s : trace_states) trace.push_back(map.cell(s));
  }
  if (outcome == SearchOutcome::Found) {
    search.path_to(goal_state, path_states);
    std::vector<Cell> cells;
    cells.reserve(path_states.size());
    for (const std::uint32_t s : path_states) cells.push_back(map.cell(s));
    set_found_path(result, geometry, std::move(cells));
  } else {
    result.status = plan_status_of(outcome);
  }
  return result;
}

}  // namespace


void validate_grid_planner_options(const GridPlannerOptions& options) {
  if (options.connectivity != 4 && options.connectivity != 8)
    throw Error("must be 4 or 8, got " + std::to_string(options.connectivity), {}, 0, "connectivity");
  if (!std::isfinite(options.weight) || options.weight < 1.0)
    throw Error("must be a finite number >= 1", {}, 0, "weight");
}

GridHeuristicKind parse_grid_heuristic(const std::string& name, int connectivity) {
  if (name.empty()) return connectivity == 4 ? GridHeuristicKind::Manhattan : GridHeuristicKind::Octile;
  if (name == "zero") return GridHeuristicKind::Zero;
  if (name == "octile") return GridHeuristicKind::Octile;
  if (name == "manhattan") return GridHeuristicKind::Manhattan;
  if (name == "euclidean") return GridHeuristicKind::Euclidean;
  throw Error("unknown heuristic '" + name + "' (zero, octile, manhattan, euclidean)", {}, 0, "heuristic");
}

const char* grid_heuristic_name(GridHeuristicKind kind) {
  switch (kind) {
    case GridHeuristicKind::Zero: return "zero";
    case GridHeuristicKind::Octile: return "octile";
    case GridHeuristicKind::Manhattan: return "manhattan";
    case GridHeuristicKind::Euclidean: return "euclidean";
  }
  return "?";
}

bool grid_heuristic_admissible(GridHeuristicKind kind, int connectivity) {
  // Manhattan overestimates a diagonal move (2 > sqrt 2); the others never overestimate.
  return !(kind == GridHeuristicKind::Manhattan && connectivity == 8);
}

// ---- Dijkstra / A* / weighted A* ------------------------------------------------------------------

BestFirstGridPlanner::BestFirstGridPlanner(Kind kind, const OccupancyGrid& grid, const GridPlannerOptions& options)
    : kind_(kind),
      connectivity_(options.connectivity),
      heuristic_(GridHeuristicKind::Zero),
      weight_(1.0),
      record_trace_(options.record_trace),
      geometry_(grid.geometry()) {
  validate_grid_planner_options(options);
  switch (kind) {
    case Kind::Dijkstra:
      if (!options.heuristic.empty() && options.heuristic != "zero")
        throw Error("dijkstra uses no heuristic, got '" + options.heuristic + "'", {}, 0, "heuristic");
      if (options.weight != 1.0) throw Error("only wastar takes a weight", {}, 0, "weight");
      break;
    case Kind::AStar:
      if (options.weight != 1.0) throw Error("only wastar takes a weight", {}, 0, "weight");
      heuristic_ = parse_grid_heuristic(options.heuristic, connectivity_);
      break;
    case Kind::WeightedAStar:
      heuristic_ = parse_grid_heuristic(options.heuristic, connectivity_);
      weight_ = options.weight;
      break;
  }
  map_ = GridSearchMap(grid, options.thresholds, options.unknown_is_free);
  search_.resize(map_.state_count());
}

std::string_view BestFirstGridPlanner::name() const {
  switch (kind_) {
    case Kind::Dijkstra: return "dijkstra";
    case Kind::AStar: return "astar";
    case Kind::WeightedAStar: return "wastar";
  }
  return "?";
}

bool BestFirstGridPlanner::admissible() const {
  return weight_ == 1.0 && grid_heuristic_admissible(heuristic_, connectivity_);
}

template <int Connectivity, class Heuristic>
PlanResult BestFirstGridPlanner::run(Cell start, Cell goal, const SearchLimits& limits, Heuristic heuristic) {
  GridGraph<Connectivity> graph(map_);
  return run_grid_query(search_, graph, heuristic, map_, geometry_, start, goal, limits, record_trace_, path_states_,
                        trace_states_, trace_);
}

template <int Connectivity>
PlanResult BestFirstGridPlanner::dispatch_heuristic(Cell start, Cell goal, const SearchLimits& limits) {
  using C = std::int64_t;
  const C card = UniformGridCost::kCardinal, diag = UniformGridCost::kDiagonal;
  const bool weighted = weight_ != 1.0;
  switch (heuristic_) {
    case GridHeuristicKind::Zero: return run<Connectivity>(start, goal, limits, ZeroHeuristic<C>{});
    case GridHeuristicKind::Octile:
      if (weighted)
        return run<Connectivity>(start, goal, limits, WeightedHeuristic(OctileHeuristic<C>(map_, card, diag), weight_));
      return run<Connectivity>(start, goal, limits, OctileHeuristic<C>(map_, card, diag));
    case GridHeuristicKind::Manhattan:
      if (weighted)
        return run<Connectivity>(start, goal, limits,
                                 WeightedHeuristic(ManhattanHeuristic<C>(map_, card, diag), weight_));
      return run<Connectivity>(start, goal, limits, ManhattanHeuristic<C>(map_, card, diag));
    case GridHeuristicKind::Euclidean:
      if (weighted)
        return run<Connectivity>(start, goal, limits,
                                 WeightedHeuristic(EuclideanHeuristic<C>(map_, card, diag), weight_));
      return run<Connectivity>(start, goal, limits, EuclideanHeuristic<C>(map_, card, diag));
  }
  return {};
}

PlanResult BestFirstGridPlanner::plan(Cell start, Cell goal, const SearchLimits& limits) {
  trace_.clear();
  if (const auto why = check_endpoints(map_, start, goal)) {
    PlanResult r;
    r.status = *why;
    return r;
  }
  return connectivity_ == 4 ? dispatch_heuristic<4>(start, goal, limits) : dispatch_heuristic<8>(start, goal, limits);
}

// ---- Theta* ---------------------------------------------------------------------------------------

ThetaStarPlanner::ThetaStarPlanner(const OccupancyGrid& grid, const GridPlannerOptions& options)
    : connectivity_(options.connectivity), record_trace_(options.record_trace), geometry_(grid.geometry()) {
  validate_grid_planner_options(options);
  if (options.weight != 1.0) throw Error("only wastar takes a weight", {}, 0, "weight");
  if (!options.heuristic.empty() && options.heuristic != "euclidean")
    throw Error("thetastar uses the euclidean heuristic, got '" + options.heuristic + "'", {}, 0, "heuristic");
  map_ = GridSearchMap(grid, options.thresholds, options.unknown_is_free);
  search_.resize(map_.state_count());
}

template <int Connectivity>
PlanResult ThetaStarPlanner::run(Cell start, Cell goal, const SearchLimits& limits) {
  AnyAngleGridGraph<Connectivity> graph(map_);
  EuclideanHeuristic<double> heuristic(map_, 1.0, kSqrt2);
  return run_grid_query(search_, graph, heuristic, map_, geometry_, start, goal, limits, record_trace_, path_states_,
                        trace_states_, trace_);
}

PlanResult ThetaStarPlanner::plan(Cell start, Cell goal, const SearchLimits& limits) {
  trace_.clear();
  if (const auto why = check_endpoints(map_, start, goal)) {
    PlanResult r;
    r.status = *why;
    return r;
  }
  return connectivity_ == 4 ? run<4>(start, goal, limits) : run<8>(start, goal, limits);
}

}  // namespace starnav
