#include "starnav/plan/dstar_lite.hpp"

#include <algorithm>
#include <chrono>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/plan/grid_plan_support.hpp"
#include "starnav/plan/grid_planners.hpp"

namespace starnav {

namespace {
constexpr std::int64_t kInf = infinite_cost<std::int64_t>();
// a + b, infinite when either is (kInf leaves room for one addition of finite costs).
inline std::int64_t add_cost(std::int64_t a, std::int64_t b) { return (a >= kInf || b >= kInf) ? kInf : a + b; }
}  // namespace

DStarLite::DStarLite(const OccupancyGrid& grid, const GridPlannerOptions& options)
    : connectivity_(options.connectivity),
      thresholds_(options.thresholds),
      unknown_is_free_(options.unknown_is_free),
      record_trace_(options.record_trace),
      geometry_(grid.geometry()) {
  validate_grid_planner_options(options);
  if (options.weight != 1.0) throw Error("only wastar takes a weight", {}, 0, "weight");
  if (!options.heuristic.empty())
    throw Error("dstar_lite uses its own heuristic (octile, manhattan on 4-connected grids), got '" +
                    options.heuristic + "'",
                {}, 0, "heuristic");
  map_ = GridSearchMap(grid, thresholds_, unknown_is_free_);
  nodes_.assign(map_.state_count(), Node{kInf, kInf, kNotQueued, 0});
  queue_.set_slot_map(SlotMap{&nodes_});
  octile_ = OctileHeuristic<Cost>(map_, UniformGridCost::kCardinal, UniformGridCost::kDiagonal);
  manhattan_ = ManhattanHeuristic<Cost>(map_, UniformGridCost::kCardinal, UniformGridCost::kDiagonal);
}

DStarLite::Node& DStarLite::node(std::uint32_t id) {
  Node& n = nodes_[id];
  if (n.generation != generation_) n = Node{kInf, kInf, kNotQueued, generation_};
  return n;
}

DStarLite::Cost DStarLite::heuristic_from_start(std::uint32_t id) const {
  return connectivity_ == 8 ? octile_(id) : manhattan_(id);
}

DStarLite::Key DStarLite::key(std::uint32_t id) {
  const Node& n = node(id);
  const Cost m = std::min(n.g, n.rhs);
  if (m >= kInf) return {kInf, kInf};
  return {m + heuristic_from_start(id) + km_, m};
}

template <class Visit>
void DStarLite::for_each_neighbour(std::uint32_t u, Visit&& visit) const {
  if (!map_.passable(u)) return;  // every edge of a blocked cell is infinite
  if (connectivity_ == 8) GridGraph<8>(map_).for_each_successor(u, visit);
  else GridGraph<4>(map_).for_each_successor(u, visit);
}

DStarLite::Cost DStarLite::best_rhs(std::uint32_t u) {
  if (u == goal_state_) return 0;
  Cost best = kInf;
  for_each_neighbour(u, [&](std::uint32_t v, Cost c) { best = std::min(best, add_cost(c, node(v).g)); });
  return best;
}

void DStarLite::update_vertex(std::uint32_t u) {
  Node& n = node(u);
  if (n.g != n.rhs) {
    const Key k = key(u);
    if (n.slot != kNotQueued) {
      queue_.update(n.slot, Entry{k.k1, k.k2, u});
    } else {
      queue_.push(Entry{k.k1, k.k2, u});
      ++generated_;
    }
  } else if (n.slot != kNotQueued) {
    const std::uint32_t slot = n.slot;
    n.slot = kNotQueued;
    queue_.remove(slot);
  }
}

SearchOutcome DStarLite::compute_shortest_path(const SearchLimits& limits, std::uint64_t& expanded,
                                               std::uint64_t& generated) {
  generated_ = 0;
  const auto started = std::chrono::steady_clock::now();
  std::uint64_t iterations = 0;
  SearchOutcome outcome = SearchOutcome::Found;
  while (!queue_.empty()) {
    const Entry top = queue_.top();
    const Key start_key = key(start_state_);
    const Node& s = node(start_state_);
    if (!key_less(Key{top.k1, top.k2}, start_key) && !(s.rhs > s.g)) break;
    if ((iterations++ % kLimitCheckInterval) == 0) {
      if (limits.cancel && limits.cancel->load(std::memory_order_relaxed)) {
        outcome = SearchOutcome::Cancelled;
        break;
      }
      if (limits.time_budget_s > 0.0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() > limits.time_budget_s) {
        outcome = SearchOutcome::TimeLimit;
        break;
      }
    }
    const std::uint32_t u = top.id;
    const Key k_new = key(u);
    Node& n = node(u);
    if (key_less(Key{top.k1, top.k2}, k_new)) {  // the key was computed for an earlier start
      queue_.update(n.slot, Entry{k_new.k1, k_new.k2, u});
      continue;
    }
    if (limits.max_expansions != 0 && expanded >= limits.max_expansions) {
      outcome = SearchOutcome::ExpansionLimit;
      break;
    }
    ++expanded;
    if (record_trace_) trace_.push_back(map_.cell(u));
    if (n.g > n.rhs) {  // over-consistent: settle g and pass it on
      n.g = n.rhs;
      const std::uint32_t slot = n.slot;
      n.slot = kNotQueued;
      queue_.remove(slot);
      const Cost gu = n.g;
      for_each_neighbour(u, [&](std::uint32_t v, Cost c) {
        if (v == goal_state_) return;
        Node& nv = node(v);
        const Cost candidate = add_cost(c, gu);
        if (candidate < nv.rhs) {
          nv.rhs = candidate;
          update_vertex(v);
        }
      });
    } else {  // under-consistent: forget g, repair those that relied on it
      const Cost g_old = n.g;
      n.g = kInf;
      for_each_neighbour(u, [&](std::uint32_t v, Cost c) {
        if (v == goal_state_) return;
        Node& nv = node(v);
        if (nv.rhs == add_cost(c, g_old)) {
          nv.rhs = best_rhs(v);
          update_vertex(v);
        }
      });
      if (u != goal_state_) node(u).rhs = best_rhs(u);
      update_vertex(u);
    }
  }
  generated += generated_;
  return outcome;
}

PlanResult DStarLite::plan(Cell start, Cell goal, const SearchLimits& limits) {
  trace_.clear();
  initialised_ = false;
  if (!map_.contains(start.x, start.y) || !map_.contains(goal.x, goal.y)) {
    PlanResult r;
    r.status = map_.contains(start.x, start.y) ? PlanStatus::GoalOutsideMap : PlanStatus::StartOutsideMap;
    return r;
  }
  if (++generation_ == 0) {  // stamps wrapped: clear them once
    for (Node& n : nodes_) n.generation = 0;
    generation_ = 1;
  }
  queue_.clear();
  km_ = 0;
  start_ = start;
  goal_ = goal;
  start_state_ = map_.state(start);
  goal_state_ = map_.state(goal);
  heuristic_origin_ = start_state_;
  octile_.set_goal(start_state_);
  manhattan_.set_goal(start_state_);
  node(goal_state_).rhs = 0;
  const Key k = key(goal_state_);
  queue_.push(Entry{k.k1, k.k2, goal_state_});
  initialised_ = true;
  return replan(limits);
}

void DStarLite::move_start(Cell start) {
  start_ = start;
  if (!initialised_ || !map_.contains(start.x, start.y)) return;
  start_state_ = map_.state(start);
  // Keys already queued were computed from the old start; raising km by the heuristic between
  // the two starts keeps them lower bounds of the new keys (the triangle inequality).
  km_ += heuristic_from_start(start_state_);
  heuristic_origin_ = start_state_;
  octile_.set_goal(start_state_);
  manhattan_.set_goal(start_state_);
}

std::size_t DStarLite::update_cells(std::span<const CellChange> changes) {
  for (const CellChange& c : changes) {
    if (!map_.contains(c.cell.x, c.cell.y))
      throw Error("(" + std::to_string(c.cell.x) + ", " + std::to_string(c.cell.y) + ") outside the map", {}, 0,
                  "cell");
    if (c.occupancy < -1 || c.occupancy > 100)
      throw Error("occupancy must be -1..100, got " + std::to_string(c.occupancy), {}, 0, "cell");
  }
  std::vector<Cell> changed;
  for (const CellChange& c : changes) {
    const CellState s = thresholds_.classify(c.occupancy);
    const bool passable = s == CellState::Free || (s == CellState::Unknown && unknown_is_free_);
    if (passable != map_.passable(c.cell.x, c.cell.y)) {
      map_.set_passable(c.cell.x, c.cell.y, passable);
      changed.push_back(c.cell);
    }
  }
  if (!initialised_) return changed.size();
  // A cell's change alters the edges of the cell itself and of its 8 neighbours (edges into it,
  // and diagonal edges that pass its corner): restore rhs = min over successors for all of them.
  for (const Cell& c : changed)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!map_.contains(c.x + dx, c.y + dy)) continue;
        const std::uint32_t v = map_.state(c.x + dx, c.y + dy);
        if (v == goal_state_) continue;
        node(v).rhs = best_rhs(v);
        update_vertex(v);
      }
  return changed.size();
}

PlanResult DStarLite::replan(const SearchLimits& limits) {
  if (!initialised_) throw Error("replan() before a successful plan()", {}, 0, "dstar_lite");
  trace_.clear();
  PlanResult result;
  if (const auto why = check_endpoints(map_, start_, goal_)) {
    result.status = *why;
    return result;
  }
  const auto started = std::chrono::steady_clock::now();
  const SearchOutcome outcome = compute_shortest_path(limits, result.expanded, result.generated);
  if (outcome != SearchOutcome::Found) {
    result.time_ms = elapsed_ms(started);
    result.status = plan_status_of(outcome);
    return result;
  }
  if (node(start_state_).rhs >= kInf) {
    result.time_ms = elapsed_ms(started);
    result.status = PlanStatus::NoPath;
    return result;
  }
  // Follow the cheapest c(s, s') + g(s') from the start (the paper's way to read the path);
  // ties go to the lower cell index.
  std::vector<Cell> cells{start_};
  std::uint32_t s = start_state_;
  for (std::size_t steps = 0; s != goal_state_; ++steps) {
    std::uint32_t best = kNoState;
    Cost best_cost = kInf;
    for_each_neighbour(s, [&](std::uint32_t v, Cost c) {
      const Cost through = add_cost(c, node(v).g);
      if (through < best_cost || (through == best_cost && through < kInf && v < best)) {
        best_cost = through;
        best = v;
      }
    });
    if (best == kNoState || steps > map_.state_count())
      throw Error("internal error: D* Lite path extraction failed", {}, 0, "dstar_lite");
    s = best;
    cells.push_back(map_.cell(s));
  }
  result.time_ms = elapsed_ms(started);
  set_found_path(result, geometry_, std::move(cells));
  return result;
}

}  // namespace starnav
