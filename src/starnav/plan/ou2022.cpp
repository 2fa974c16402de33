#include "starnav/plan/ou2022.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/plan/grid_plan_support.hpp"
#include "starnav/plan/grid_planners.hpp"
#include "starnav/plan/path_smoothing.hpp"

namespace starnav {

namespace {

using Clock = std::chrono::steady_clock;

// Padded states of the (cell, direction) graph must stay below kNoState.
void check_directed_size(const GridSearchMap& map) {
  if (static_cast<double>(map.state_count()) * 8.0 + 1.0 >= 4294967294.0)
    throw Error("the map is too large for (cell, direction) states (at most about 536 million cells)", {}, 0,
                "turn_exact");
}

}  // namespace

// ---- Options --------------------------------------------------------------------------------------

ImprovedAStarPlanner::Settings ImprovedAStarPlanner::resolve(const GridPlannerOptions& options, bool paper_defaults) {
  validate_grid_planner_options(options);
  if (options.weight != 1.0) throw Error("only wastar takes a weight", {}, 0, "weight");
  const Ou2022Options& o = options.ou2022;
  validate_inflation(o.inflation);
  Settings s;
  s.connectivity = options.connectivity;
  if (options.heuristic.empty() && paper_defaults) s.heuristic = GridHeuristicKind::Manhattan;
  else s.heuristic = parse_grid_heuristic(options.heuristic, options.connectivity);
  s.turn_cost = o.turn_cost.value_or(paper_defaults ? 1.0 : 0.0);
  if (!std::isfinite(s.turn_cost) || s.turn_cost < 0.0)
    throw Error("must be a finite number >= 0", {}, 0, "turn_cost");
  s.turn_exact = o.turn_exact;
  s.adaptive_weight = o.adaptive_weight.value_or(paper_defaults);
  s.smoothing = o.smoothing.value_or(paper_defaults ? PathSmoothing::LineOfSight : PathSmoothing::None);
  s.start_heading_rad = o.start_heading_rad;
  if (s.start_heading_rad && !std::isfinite(*s.start_heading_rad))
    throw Error("must be a finite angle", {}, 0, "start_heading");
  s.inflation = o.inflation;
  return s;
}

ImprovedAStarPlanner::ImprovedAStarPlanner(const OccupancyGrid& grid, const GridPlannerOptions& options,
                                           bool paper_defaults)
    : paper_defaults_(paper_defaults),
      record_trace_(options.record_trace),
      settings_(resolve(options, paper_defaults)),
      geometry_(grid.geometry()) {
  const auto t0 = Clock::now();
  inflated_ = inflate_obstacles(grid, options.thresholds, options.unknown_is_free, settings_.inflation);
  map_ = GridSearchMap(grid.width(), grid.height(), inflated_.blocked);
  if (settings_.inflation.graded()) {
    cardinal_cost_.assign(map_.state_count(), UniformGridCost::kCardinal);
    diagonal_cost_.assign(map_.state_count(), UniformGridCost::kDiagonal);
    for (int y = 0; y < grid.height(); ++y)
      for (int x = 0; x < grid.width(); ++x) {
        const double m = inflated_.multiplier[static_cast<std::size_t>(y) * grid.width() + x];
        const std::uint32_t s = map_.state(x, y);
        cardinal_cost_[s] = std::llround(m * UniformGridCost::kUnitsPerCell);
        diagonal_cost_[s] = std::llround(m * kSqrt2 * UniformGridCost::kUnitsPerCell);
      }
  }
  turns_ = TurnCostTable<std::int64_t>::make(settings_.turn_cost, settings_.start_heading_rad,
                                             UniformGridCost::kUnitsPerCell);
  if (settings_.turn_exact) {
    check_directed_size(map_);
    directed_search_ = std::make_unique<BestFirstSearch<std::int64_t>>(8 * map_.state_count() + 1);
  } else {
    cell_search_.resize(map_.state_count());
  }
  preprocess_ms_ = elapsed_ms(t0);
}

bool ImprovedAStarPlanner::admissible() const {
  if (settings_.adaptive_weight) return false;
  if (settings_.turn_cost > 0.0 && !settings_.turn_exact) return false;
  return grid_heuristic_admissible(settings_.heuristic, settings_.connectivity);
}

double ImprovedAStarPlanner::path_cost(std::span<const Cell> cells) const {
  double cost = 0.0;
  int previous = kNoDirection;
  for (std::size_t i = 1; i < cells.size(); ++i) {
    const int dx = cells[i].x - cells[i - 1].x, dy = cells[i].y - cells[i - 1].y;
    const int dir = move_direction(dx, dy);
    if (dir < 0) throw Error("path_cost needs a path of adjacent cells");
    const double multiplier =
        inflated_.multiplier.empty() ? 1.0 : inflated_.multiplier[geometry_.index(cells[i].x, cells[i].y)];
    cost += (dx != 0 && dy != 0 ? kSqrt2 : 1.0) * multiplier;
    if (settings_.turn_cost > 0.0) {
      if (previous != kNoDirection) cost += turn_cost_cells(settings_.turn_cost, previous, dir);
      else if (settings_.start_heading_rad)
        cost += settings_.turn_cost * heading_to_direction_rad(*settings_.start_heading_rad, dir) /
                (std::numbers::pi / 4.0);
    }
    previous = dir;
  }
  return cost * geometry_.resolution;
}

// ---- Queries --------------------------------------------------------------------------------------

struct ImprovedAStarPlanner::Query {
  Cell start, goal;
  std::uint32_t start_state = 0, goal_state = 0;  // padded cell states
  const SearchLimits* limits = nullptr;
  SearchOutcome outcome = SearchOutcome::Exhausted;
  SearchStats stats;
  std::vector<Cell> cells;  // the grid path when found
};

template <class Graph, class Heuristic>
void ImprovedAStarPlanner::run_search(Query& q, const Graph& graph, Heuristic heuristic) {
  trace_states_.clear();
  auto finish = [&](BestFirstSearch<std::int64_t>& search, auto&& cell_of_state) {
    q.stats = search.stats();
    if (q.outcome == SearchOutcome::Found) {
      search.path_to(search.goal_reached(), path_states_);
      q.cells.clear();
      q.cells.reserve(path_states_.size());
      for (const std::uint32_t s : path_states_) q.cells.push_back(map_.cell(cell_of_state(s)));
    }
    if (record_trace_) {
      trace_.reserve(trace_states_.size());
      for (const std::uint32_t s : trace_states_) trace_.push_back(map_.cell(cell_of_state(s)));
    }
  };
  if constexpr (requires { graph.start_state(); }) {
    // (cell, direction) states: the heuristic and the goal test read the cell.
    CellStateHeuristic<Heuristic, Graph> h(heuristic, graph);
    h.set_goal(q.goal_state);
    const std::uint32_t goal = q.goal_state;
    auto is_goal = [goal, &graph](std::uint32_t s) { return graph.cell_of(s) == goal; };
    BestFirstSearch<std::int64_t>& search = *directed_search_;
    q.outcome = record_trace_ ? search.run(graph, h, graph.start_state(), is_goal, *q.limits,
                                           TraceListener{&trace_states_})
                              : search.run(graph, h, graph.start_state(), is_goal, *q.limits);
    finish(search, [&graph](std::uint32_t s) { return graph.cell_of(s); });
  } else {
    heuristic.set_goal(q.goal_state);
    q.outcome = record_trace_ ? cell_search_.run(graph, heuristic, q.start_state, SingleGoal{q.goal_state},
                                                 *q.limits, TraceListener{&trace_states_})
                              : cell_search_.run(graph, heuristic, q.start_state, SingleGoal{q.goal_state}, *q.limits);
    finish(cell_search_, [](std::uint32_t s) { return s; });
  }
}

template <class Graph, class Heuristic>
void ImprovedAStarPlanner::run_weight(Query& q, const Graph& graph, Heuristic heuristic) {
  if constexpr (Heuristic::kKind != GridHeuristicKind::Zero) {
    if (settings_.adaptive_weight) {
      run_search(q, graph, AdaptiveWeightHeuristic<Heuristic>(heuristic, map_, q.start_state));
      return;
    }
  }
  run_search(q, graph, heuristic);
}

template <class Graph>
void ImprovedAStarPlanner::run_heuristic(Query& q, const Graph& graph) {
  using C = std::int64_t;
  const C card = UniformGridCost::kCardinal, diag = UniformGridCost::kDiagonal;
  switch (settings_.heuristic) {
    case GridHeuristicKind::Zero: return run_weight(q, graph, ZeroHeuristic<C>{});
    case GridHeuristicKind::Octile: return run_weight(q, graph, OctileHeuristic<C>(map_, card, diag));
    case GridHeuristicKind::Manhattan: return run_weight(q, graph, ManhattanHeuristic<C>(map_, card, diag));
    case GridHeuristicKind::Euclidean: return run_weight(q, graph, EuclideanHeuristic<C>(map_, card, diag));
  }
}

template <int Connectivity, class CostModel>
void ImprovedAStarPlanner::run_cost(Query& q, CostModel cost) {
  if (settings_.turn_exact) {
    DirectedTurnGridGraph<Connectivity, CostModel> graph(map_, cost, turns_, q.start_state);
    run_heuristic(q, graph);
  } else if (settings_.turn_cost > 0.0) {
    TurnCostGridGraph<Connectivity, CostModel> graph(map_, cost, turns_);
    run_heuristic(q, graph);
  } else {
    GridGraph<Connectivity, CostModel> graph(map_, cost);
    run_heuristic(q, graph);
  }
}

template <int Connectivity>
void ImprovedAStarPlanner::run_connectivity(Query& q) {
  if (settings_.inflation.graded()) run_cost<Connectivity>(q, FixedPointCellCost{cardinal_cost_.data(), diagonal_cost_.data()});
  else run_cost<Connectivity>(q, UniformGridCost{});
}

PlanResult ImprovedAStarPlanner::plan(Cell start, Cell goal, const SearchLimits& limits) {
  trace_.clear();
  unsmoothed_.clear();
  PlanResult result;
  if (const auto why = check_endpoints(map_, start, goal)) {
    result.status = *why;
    return result;
  }
  const auto t0 = Clock::now();
  Query q;
  q.start = start;
  q.goal = goal;
  q.start_state = map_.state(start);
  q.goal_state = map_.state(goal);
  q.limits = &limits;
  if (start == goal) {
    q.outcome = SearchOutcome::Found;
    q.cells = {start};
  } else if (settings_.connectivity == 4) {
    run_connectivity<4>(q);
  } else {
    run_connectivity<8>(q);
  }
  result.expanded = q.stats.expanded;
  result.generated = q.stats.generated;
  if (q.outcome != SearchOutcome::Found) {
    result.status = plan_status_of(q.outcome);
    result.time_ms = elapsed_ms(t0);
    return result;
  }
  const double cost = path_cost(q.cells);
  if (settings_.smoothing == PathSmoothing::LineOfSight) {
    std::vector<Cell> smoothed = remove_redundant_nodes(map_, q.cells);
    unsmoothed_ = std::move(q.cells);
    set_found_path(result, geometry_, std::move(smoothed));
  } else {
    set_found_path(result, geometry_, std::move(q.cells));
  }
  result.cost = cost;
  result.time_ms = elapsed_ms(t0);
  return result;
}

// ---- Inflation and smoothing around other planners -------------------------------------------------

namespace {

class InflatedSmoothedPlanner final : public GridPlanner {
 public:
  InflatedSmoothedPlanner(std::unique_ptr<GridPlanner> inner, const GridGeometry& geometry, GridSearchMap map,
                          PathSmoothing smoothing, double preprocess_ms)
      : inner_(std::move(inner)),
        geometry_(geometry),
        map_(std::move(map)),
        smoothing_(smoothing),
        preprocess_ms_(preprocess_ms) {}

  std::string_view name() const override { return inner_->name(); }
  bool admissible() const override { return inner_->admissible(); }
  double preprocess_ms() const override { return preprocess_ms_ + inner_->preprocess_ms(); }
  const std::vector<Cell>& trace() const override { return inner_->trace(); }
  const std::vector<Cell>& unsmoothed_path() const override { return unsmoothed_; }

  PlanResult plan(Cell start, Cell goal, const SearchLimits& limits) override {
    unsmoothed_.clear();
    PlanResult r = inner_->plan(start, goal, limits);
    if (!r.found() || smoothing_ == PathSmoothing::None) return r;
    const auto t0 = Clock::now();
    std::vector<Cell> smoothed = remove_redundant_nodes(map_, r.path_cells);
    unsmoothed_ = std::move(r.path_cells);
    const double cost = r.cost;
    set_found_path(r, geometry_, std::move(smoothed));
    r.cost = cost;  // the inner planner's objective, on its grid path
    r.time_ms += elapsed_ms(t0);
    return r;
  }

 private:
  std::unique_ptr<GridPlanner> inner_;
  GridGeometry geometry_;
  GridSearchMap map_;
  PathSmoothing smoothing_;
  double preprocess_ms_;
  std::vector<Cell> unsmoothed_;
};

}  // namespace

std::unique_ptr<GridPlanner> make_inflated_smoothed_planner(std::string_view name, const OccupancyGrid& grid,
                                                            const GridPlannerOptions& options,
                                                            GridPlannerFactory make_inner) {
  const Ou2022Options& o = options.ou2022;
  const std::string who(name);
  if (o.inflation.graded())
    throw Error(who + " cannot use a graded inflation cost band (JPS-style pruning and the other planners assume "
                      "uniform move costs); use --planner astar or ou2022",
                {}, 0, "inflate_cost_radius");
  if (o.turn_cost && *o.turn_cost != 0.0)
    throw Error(who + " cannot use turn costs (they make move costs depend on the direction); use --planner astar "
                      "or ou2022",
                {}, 0, "turn_cost");
  if (o.turn_exact) throw Error(who + " has no (cell, direction) variant; use --planner astar or ou2022", {}, 0, "turn_exact");
  if (o.adaptive_weight.value_or(false))
    throw Error(who + " cannot use the adaptive heuristic weight; use --planner astar or ou2022", {}, 0,
                "adaptive_weight");
  const auto t0 = Clock::now();
  const InflatedMap inflated = inflate_obstacles(grid, options.thresholds, options.unknown_is_free, o.inflation);
  GridSearchMap map(grid.width(), grid.height(), inflated.blocked);
  GridPlannerOptions inner_options = options;
  inner_options.ou2022 = {};
  const double preprocess = elapsed_ms(t0);
  std::unique_ptr<GridPlanner> inner =
      o.inflation.hard() ? make_inner(name, inflated_grid(grid, inflated), inner_options)
                         : make_inner(name, grid, inner_options);
  return std::make_unique<InflatedSmoothedPlanner>(std::move(inner), grid.geometry(), std::move(map),
                                                   o.smoothing.value_or(PathSmoothing::None), preprocess);
}

}  // namespace starnav
