#pragma once
// Search-core policies for the improved A* of Ou et al. 2022 (docs/papers/ou2022.md).
// They plug into BestFirstSearch (search_core.hpp) like GridGraph and
// the grid heuristics of grid_graph.hpp:
//
//   FixedPointCellCost       cost model: moves cost length x a per-cell multiplier (the graded
//                            inflation band), in UniformGridCost's fixed point (2^32 per cell).
//   TurnCostGridGraph        the paper's steering cost on cell states: the turn into a move out
//                            of u is measured against the move into u from its parent (read from
//                            the search through visit.parent_of). Not optimal for the turn-
//                            inclusive cost: a state's cost depends on how it was reached.
//   DirectedTurnGridGraph    the exact variant: states are (cell, incoming direction), 8 per cell,
//                            plus one start state without a direction; optimal for the turn-
//                            inclusive cost with an admissible heuristic.
//   AdaptiveWeightHeuristic  f = g + (1 + d/D) h (paper Eq. 27), inadmissible.
//   CellStateHeuristic       a cell heuristic read through DirectedTurnGridGraph's states.
//
// Move directions follow the paper's Table 1 in cell coordinates (dx, dy): index k has angle
// 45 k degrees: (1,0) 0, (1,1) 1, (0,1) 2, (-1,1) 3, (-1,0) 4, (-1,-1) 5, (0,-1) 6, (1,-1) 7. (The
// paper prints 275 and 360 for the last two angles: typos for 270 and 315.) The steering angle
// between two directions is the smaller angle between them, 0, 45, 90, 135 or 180 degrees, and
// turn_w = k_turn * (angle / 45 deg) * resolution (the paper's k = 10 on steps 10 and 14 is
// k_turn = 1: one 45-degree turn costs one straight step). Internally costs are in cells, the
// resolution is applied to the reported cost.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <type_traits>

#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/search_memory.hpp"

namespace starnav {

// ---- Directions and steering angles ------------------------------------------------------------

inline constexpr int kNoDirection = 8;  // the start: no incoming move (row 8 of a turn table)

// Table 1 index of a move (dx, dy) in {-1, 0, 1}^2 \ {(0, 0)}; -1 for anything else.
constexpr int move_direction(int dx, int dy) {
  constexpr int table[3][3] = {{5, 4, 3}, {6, -1, 2}, {7, 0, 1}};  // [dx + 1][dy + 1]
  if (dx < -1 || dx > 1 || dy < -1 || dy > 1) return -1;
  return table[dx + 1][dy + 1];
}
constexpr int direction_dx(int dir) { return std::array<int, 8>{1, 1, 0, -1, -1, -1, 0, 1}[static_cast<std::size_t>(dir)]; }
constexpr int direction_dy(int dir) { return std::array<int, 8>{0, 1, 1, 1, 0, -1, -1, -1}[static_cast<std::size_t>(dir)]; }
constexpr int direction_angle_deg(int dir) { return 45 * dir; }

// The smaller angle between two move directions: 0, 45, 90, 135 or 180 degrees.
constexpr int steering_angle_deg(int from_dir, int to_dir) {
  const int d = from_dir > to_dir ? from_dir - to_dir : to_dir - from_dir;
  return 45 * (d <= 4 ? d : 8 - d);
}

// turn_w in cells for the steering angle between two directions (multiply by the resolution for
// metres): k_turn * angle / 45 deg.
constexpr double turn_cost_cells(double k_turn, int from_dir, int to_dir) {
  return k_turn * steering_angle_deg(from_dir, to_dir) / 45.0;
}

// The smaller angle (radians, [0, pi]) between a heading and a move direction.
inline double heading_to_direction_rad(double heading_rad, int dir) {
  const double a = std::remainder(direction_angle_deg(dir) * (std::numbers::pi / 180.0) - heading_rad, 2.0 * std::numbers::pi);
  return std::abs(a);
}

// turn_w of every (incoming direction, outgoing direction) pair in a cost type, row kNoDirection
// for the start (zero, or the turn from the robot's initial heading when it is given).
template <class Cost>
struct TurnCostTable {
  std::array<std::array<Cost, 8>, 9> cost{};

  // `units_per_cell`: cost units of one cell (UniformGridCost::kUnitsPerCell for fixed point).
  static TurnCostTable make(double k_turn, std::optional<double> start_heading_rad, double units_per_cell) {
    TurnCostTable t;
    auto to_cost = [&](double cells) {
      if constexpr (std::is_integral_v<Cost>) return static_cast<Cost>(std::llround(cells * units_per_cell));
      else return static_cast<Cost>(cells * units_per_cell);
    };
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) t.cost[a][b] = to_cost(turn_cost_cells(k_turn, a, b));
    for (int b = 0; b < 8; ++b)
      t.cost[kNoDirection][b] =
          start_heading_rad ? to_cost(k_turn * heading_to_direction_rad(*start_heading_rad, b) / (std::numbers::pi / 4))
                            : Cost{};
    return t;
  }
};

// ---- Moves -------------------------------------------------------------------------------------

// Calls f(v, direction, diagonal) for every move out of padded state u of a 4- or 8-connected grid
// without corner cutting: exactly GridGraph's moves, with their Table 1 directions (padded state
// + 1 is x + 1, + stride is y + 1).
template <int Connectivity, class F>
inline void for_each_grid_move(const GridSearchMap& map, std::uint32_t u, F&& f) {
  const std::uint8_t* p = map.data() + u;
  const std::uint32_t s = map.stride();
  const std::ptrdiff_t ns = -static_cast<std::ptrdiff_t>(s);
  const std::uint8_t up = p[ns], down = p[s], left = p[-1], right = p[1];  // "up" = y - 1
  if (right) f(u + 1, 0, false);
  if (left) f(u - 1, 4, false);
  if (down) f(u + s, 2, false);
  if (up) f(u - s, 6, false);
  if constexpr (Connectivity == 8) {
    if (up & right & p[ns + 1]) f(u - s + 1, 7, true);
    if (up & left & p[ns - 1]) f(u - s - 1, 5, true);
    if (down & right & p[s + 1]) f(u + s + 1, 1, true);
    if (down & left & p[s - 1]) f(u + s - 1, 3, true);
  }
}

// Direction of the move from padded state `from` to its neighbour `to`.
inline int direction_between(const GridSearchMap& map, std::uint32_t from, std::uint32_t to) {
  std::uint32_t fx, fy, tx, ty;
  map.padded_xy(from, fx, fy);
  map.padded_xy(to, tx, ty);
  return move_direction(static_cast<int>(tx) - static_cast<int>(fx), static_cast<int>(ty) - static_cast<int>(fy));
}

// ---- Cost model: graded inflation band ---------------------------------------------------------

// Moves cost their length times the multiplier of the cell entered, in UniformGridCost's fixed
// point: cardinal[s] = round(m * 2^32), diagonal[s] = round(m * sqrt(2) * 2^32), one entry per
// padded state. Multipliers are >= 1, so the cheapest moves are UniformGridCost's.
struct FixedPointCellCost {
  using cost_type = std::int64_t;
  const std::int64_t* cardinal_cost = nullptr;
  const std::int64_t* diagonal_cost = nullptr;
  std::int64_t cardinal(std::uint32_t to) const { return cardinal_cost[to]; }
  std::int64_t diagonal(std::uint32_t to) const { return diagonal_cost[to]; }
  std::int64_t min_cardinal() const { return UniformGridCost::kCardinal; }
  std::int64_t min_diagonal() const { return UniformGridCost::kDiagonal; }
  static double to_cells(std::int64_t c) { return UniformGridCost::to_cells(c); }
};

// ---- Graphs ------------------------------------------------------------------------------------

// The paper's steering cost on cell states: g(v) = g(u) + step(u, v) + turn_w(in(u), dir(u, v)),
// where in(u) is the direction of the move from u's parent into u (none at the start).
template <int Connectivity, class CostModel = UniformGridCost>
class TurnCostGridGraph {
 public:
  using cost_type = typename CostModel::cost_type;
  TurnCostGridGraph(const GridSearchMap& map, CostModel cost, const TurnCostTable<cost_type>& turns)
      : map_(&map), cost_(cost), turns_(&turns) {}
  std::size_t state_count() const { return map_->state_count(); }

  template <class Visit>
  void for_each_successor(std::uint32_t u, Visit& visit) const {
    const std::uint32_t parent = visit.parent_of(u);
    const int in = parent == kNoState ? kNoDirection : direction_between(*map_, parent, u);
    const auto& row = turns_->cost[static_cast<std::size_t>(in)];
    for_each_grid_move<Connectivity>(*map_, u, [&](std::uint32_t v, int dir, bool diagonal) {
      visit(v, (diagonal ? cost_.diagonal(v) : cost_.cardinal(v)) + row[static_cast<std::size_t>(dir)]);
    });
  }

 private:
  const GridSearchMap* map_;
  CostModel cost_;
  const TurnCostTable<cost_type>* turns_;
};

// The exact variant: state 8 * c + d is cell c (padded state) entered by a move of direction d;
// state 8 * (number of padded states) is the start, which has no incoming direction. Edge
// (c, d) -> (v, d') costs step(c, v) + turn_w(d, d').
template <int Connectivity, class CostModel = UniformGridCost>
class DirectedTurnGridGraph {
 public:
  using cost_type = typename CostModel::cost_type;
  static std::size_t states_for(const GridSearchMap& map) { return 8 * map.state_count() + 1; }

  DirectedTurnGridGraph(const GridSearchMap& map, CostModel cost, const TurnCostTable<cost_type>& turns,
                        std::uint32_t start_cell)
      : map_(&map),
        cost_(cost),
        turns_(&turns),
        start_state_(static_cast<std::uint32_t>(8 * map.state_count())),
        start_cell_(start_cell) {}
  std::size_t state_count() const { return states_for(*map_); }
  std::uint32_t start_state() const { return start_state_; }
  std::uint32_t cell_of(std::uint32_t state) const { return state == start_state_ ? start_cell_ : state >> 3; }

  template <class Visit>
  void for_each_successor(std::uint32_t u, Visit& visit) const {
    const bool start = u == start_state_;
    const std::uint32_t c = start ? start_cell_ : u >> 3;
    const auto& row = turns_->cost[start ? kNoDirection : (u & 7u)];
    for_each_grid_move<Connectivity>(*map_, c, [&](std::uint32_t v, int dir, bool diagonal) {
      visit(v * 8 + static_cast<std::uint32_t>(dir),
            (diagonal ? cost_.diagonal(v) : cost_.cardinal(v)) + row[static_cast<std::size_t>(dir)]);
    });
  }

 private:
  const GridSearchMap* map_;
  CostModel cost_;
  const TurnCostTable<cost_type>* turns_;
  std::uint32_t start_state_;
  std::uint32_t start_cell_;
};

// ---- Heuristics --------------------------------------------------------------------------------

// (1 + d/D) * inner, d = Euclidean distance (cells) from the state to the goal, D from the start
// to the goal (paper Eq. 27). The weight falls from 2 at the start to 1 at the goal; with D = 0
// (start = goal, which planners answer without a search) the weight is 1. Inadmissible.
template <class Inner>
class AdaptiveWeightHeuristic {
 public:
  static constexpr GridHeuristicKind kKind = Inner::kKind;
  AdaptiveWeightHeuristic() = default;
  AdaptiveWeightHeuristic(Inner inner, const GridSearchMap& map, std::uint32_t start)
      : inner_(inner), map_(&map), start_(start) {}
  void set_goal(std::uint32_t goal) {
    inner_.set_goal(goal);
    map_->padded_xy(goal, gx_, gy_);
    std::uint32_t sx, sy;
    map_->padded_xy(start_, sx, sy);
    const double dx = static_cast<double>(sx) - gx_, dy = static_cast<double>(sy) - gy_;
    const double dist = std::sqrt(dx * dx + dy * dy);
    inv_start_distance_ = dist > 0.0 ? 1.0 / dist : 0.0;
  }
  // The weight 1 + d/D at a state.
  double weight(std::uint32_t id) const {
    std::uint32_t x, y;
    map_->padded_xy(id, x, y);
    const double dx = static_cast<double>(x) - gx_, dy = static_cast<double>(y) - gy_;
    return 1.0 + std::sqrt(dx * dx + dy * dy) * inv_start_distance_;
  }
  auto operator()(std::uint32_t id) const {
    using Cost = decltype(inner_(id));
    return static_cast<Cost>(weight(id) * static_cast<double>(inner_(id)));
  }

 private:
  Inner inner_;
  const GridSearchMap* map_ = nullptr;
  std::uint32_t start_ = 0;
  std::uint32_t gx_ = 0, gy_ = 0;
  double inv_start_distance_ = 0.0;
};

// A heuristic over padded cell states read through DirectedTurnGridGraph's (cell, direction)
// states; set_goal takes the goal cell.
template <class Inner, class Graph>
class CellStateHeuristic {
 public:
  static constexpr GridHeuristicKind kKind = Inner::kKind;
  CellStateHeuristic(Inner inner, const Graph& graph) : inner_(inner), graph_(&graph) {}
  void set_goal(std::uint32_t goal_cell) { inner_.set_goal(goal_cell); }
  auto operator()(std::uint32_t state) const { return inner_(graph_->cell_of(state)); }

 private:
  Inner inner_;
  const Graph* graph_;
};

}  // namespace starnav
