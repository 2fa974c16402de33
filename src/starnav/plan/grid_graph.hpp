#pragma once
// Occupancy grids as search graphs: a passable bitmap with a 1-cell blocked border (so successor
// generation needs no bounds checks), cost models and heuristics for the search core.
//
// States are padded indices: state(x, y) = (y + 1) * (width + 2) + (x + 1). The padded index
// grows with the plain row-major index y * width + x, so "lower cell index" tie-breaking
// (conventions.md) is the same on either.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <type_traits>
#include <vector>

#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// Division by a run-time constant through multiply and shift (exact for n < 2^31, d < 2^31):
// with k = 31 + ceil(log2 d) and M = ceil(2^k / d), floor(n * M / 2^k) = floor(n / d) because
// the error n * (M * d - 2^k) < 2^31 * d <= 2^k.
class FastDivider {
 public:
  FastDivider() = default;
  explicit FastDivider(std::uint32_t d) : divisor_(d) {
    unsigned l = 0;
    while ((std::uint64_t{1} << l) < d) ++l;
    shift_ = 31 + l;
    magic_ = ((std::uint64_t{1} << shift_) + d - 1) / d;
  }
  std::uint32_t divide(std::uint32_t n) const { return static_cast<std::uint32_t>((n * magic_) >> shift_); }
  std::uint32_t divisor() const { return divisor_; }

 private:
  std::uint64_t magic_ = 0;
  unsigned shift_ = 0;
  std::uint32_t divisor_ = 1;
};

// Which cells a planner may enter, with a blocked border of one cell around the map.
class GridSearchMap {
 public:
  GridSearchMap() = default;
  // Free cells (by the thresholds; unknown cells when unknown_is_free) are passable.
  GridSearchMap(const OccupancyGrid& grid, const OccupancyThresholds& thresholds, bool unknown_is_free);
  // blocked: width * height bytes, row-major, non-zero = blocked.
  GridSearchMap(int width, int height, const std::vector<std::uint8_t>& blocked);

  int width() const { return width_; }
  int height() const { return height_; }
  std::uint32_t stride() const { return stride_; }
  std::size_t state_count() const { return passable_.size(); }

  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  std::uint32_t state(int x, int y) const {
    return static_cast<std::uint32_t>(y + 1) * stride_ + static_cast<std::uint32_t>(x + 1);
  }
  std::uint32_t state(const Cell& c) const { return state(c.x, c.y); }
  // Padded coordinates (x + 1, y + 1) of a state.
  void padded_xy(std::uint32_t id, std::uint32_t& px, std::uint32_t& py) const {
    py = row_divider_.divide(id);
    px = id - py * stride_;
  }
  Cell cell(std::uint32_t id) const {
    std::uint32_t px, py;
    padded_xy(id, px, py);
    return {static_cast<int>(px) - 1, static_cast<int>(py) - 1};
  }
  // Unchecked (border cells read as blocked).
  bool passable(std::uint32_t id) const { return passable_[id] != 0; }
  // Checked: false outside the map.
  bool passable(int x, int y) const { return contains(x, y) && passable_[state(x, y)] != 0; }
  void set_passable(int x, int y, bool passable) { passable_[state(x, y)] = passable ? 1 : 0; }
  const std::uint8_t* data() const { return passable_.data(); }

 private:
  void allocate(int width, int height);

  int width_ = 0;
  int height_ = 0;
  std::uint32_t stride_ = 0;
  FastDivider row_divider_;
  std::vector<std::uint8_t> passable_;
};

inline constexpr double kSqrt2 = std::numbers::sqrt2;

// ---- Cost models -------------------------------------------------------------------------------
// A cost model gives the cost of entering state `to` by a cardinal or a diagonal move, in its
// cost_type, and converts costs back to cells.

// Cost 1 and sqrt(2) per move, in fixed point (2^32 units per cell). Integer costs make ties on f
// exact (two paths with the same numbers of straight and diagonal moves tie exactly, which
// floating point does not guarantee), and with 2^32 units the rounding of sqrt(2) is 5e-11 per
// move. Reported costs are recomputed from the path in double precision.
struct UniformGridCost {
  using cost_type = std::int64_t;
  static constexpr double kUnitsPerCell = 4294967296.0;  // 2^32
  static constexpr std::int64_t kCardinal = std::int64_t{1} << 32;
  static constexpr std::int64_t kDiagonal = 6074001000;  // round(sqrt(2) * 2^32)
  std::int64_t cardinal(std::uint32_t /*to*/) const { return kCardinal; }
  std::int64_t diagonal(std::uint32_t /*to*/) const { return kDiagonal; }
  // Cheapest cardinal and diagonal moves, for heuristics.
  std::int64_t min_cardinal() const { return kCardinal; }
  std::int64_t min_diagonal() const { return kDiagonal; }
  static double to_cells(std::int64_t c) { return static_cast<double>(c) / kUnitsPerCell; }
};

// Cost 1 and sqrt(2) per move in double precision: for searches whose other edges are not grid
// moves (any-angle search adds straight segments of any length).
struct UniformGridCostDouble {
  using cost_type = double;
  double cardinal(std::uint32_t /*to*/) const { return 1.0; }
  double diagonal(std::uint32_t /*to*/) const { return kSqrt2; }
  double min_cardinal() const { return 1.0; }
  double min_diagonal() const { return kSqrt2; }
  static double to_cells(double c) { return c; }
};

// Moves cost their length times the multiplier of the cell entered (>= some positive minimum).
// multipliers: one per padded state (use GridSearchMap::state to index), read while searching.
struct CellCostMultipliers {
  using cost_type = double;
  const double* multipliers = nullptr;
  double min_multiplier = 1.0;
  double cardinal(std::uint32_t to) const { return multipliers[to]; }
  double diagonal(std::uint32_t to) const { return kSqrt2 * multipliers[to]; }
  double min_cardinal() const { return min_multiplier; }
  double min_diagonal() const { return kSqrt2 * min_multiplier; }
  static double to_cells(double c) { return c; }
};

// ---- Graphs ------------------------------------------------------------------------------------

// 4- or 8-connected grid, no corner cutting: a diagonal move needs both orthogonally adjacent
// cells passable (conventions.md).
template <int Connectivity, class CostModel = UniformGridCost>
class GridGraph {
  static_assert(Connectivity == 4 || Connectivity == 8);

 public:
  using cost_type = typename CostModel::cost_type;
  static constexpr int kConnectivity = Connectivity;

  GridGraph() = default;
  GridGraph(const GridSearchMap& map, CostModel cost = {}) : map_(&map), cost_(cost) {}

  const GridSearchMap& map() const { return *map_; }
  const CostModel& cost_model() const { return cost_; }
  std::size_t state_count() const { return map_->state_count(); }

  // Calls visit(successor, edge_cost) for every move out of u.
  template <class Visit>
  void for_each_successor(std::uint32_t u, Visit&& visit) const {
    const std::uint8_t* p = map_->data() + u;
    const std::uint32_t s = map_->stride();
    const std::uint8_t up = p[-static_cast<std::ptrdiff_t>(s)], down = p[s], left = p[-1], right = p[1];
    if (right) visit(u + 1, cost_.cardinal(u + 1));
    if (left) visit(u - 1, cost_.cardinal(u - 1));
    if (down) visit(u + s, cost_.cardinal(u + s));
    if (up) visit(u - s, cost_.cardinal(u - s));
    if constexpr (Connectivity == 8) {
      if (up & right & p[1 - static_cast<std::ptrdiff_t>(s)]) visit(u - s + 1, cost_.diagonal(u - s + 1));
      if (up & left & p[-1 - static_cast<std::ptrdiff_t>(s)]) visit(u - s - 1, cost_.diagonal(u - s - 1));
      if (down & right & p[s + 1]) visit(u + s + 1, cost_.diagonal(u + s + 1));
      if (down & left & p[s - 1]) visit(u + s - 1, cost_.diagonal(u + s - 1));
    }
  }

 private:
  const GridSearchMap* map_ = nullptr;
  CostModel cost_{};
};

// ---- Heuristics --------------------------------------------------------------------------------
// A heuristic is told the goal state, then estimates the cost from a state to it. Every grid
// heuristic works in the cost units of the model it was built for (cheapest cardinal and
// diagonal move costs).

enum class GridHeuristicKind { Zero, Octile, Manhattan, Euclidean };

template <class Cost>
class GridHeuristic {
 public:
  GridHeuristic() = default;
  GridHeuristic(const GridSearchMap& map, Cost cardinal, Cost diagonal)
      : map_(&map), cardinal_(cardinal), diagonal_(diagonal) {}
  void set_goal(std::uint32_t goal) { map_->padded_xy(goal, gx_, gy_); }

 protected:
  void deltas(std::uint32_t id, std::uint32_t& dx, std::uint32_t& dy) const {
    std::uint32_t x, y;
    map_->padded_xy(id, x, y);
    dx = x > gx_ ? x - gx_ : gx_ - x;
    dy = y > gy_ ? y - gy_ : gy_ - y;
  }
  const GridSearchMap* map_ = nullptr;
  Cost cardinal_{};
  Cost diagonal_{};
  std::uint32_t gx_ = 0, gy_ = 0;
};

template <class Cost>
struct ZeroHeuristic {
  static constexpr GridHeuristicKind kKind = GridHeuristicKind::Zero;
  void set_goal(std::uint32_t) {}
  Cost operator()(std::uint32_t) const { return Cost{}; }
};

// Exact distance on an empty 8-connected grid: admissible and consistent there.
template <class Cost>
class OctileHeuristic : public GridHeuristic<Cost> {
 public:
  static constexpr GridHeuristicKind kKind = GridHeuristicKind::Octile;
  using GridHeuristic<Cost>::GridHeuristic;
  Cost operator()(std::uint32_t id) const {
    std::uint32_t dx, dy;
    this->deltas(id, dx, dy);
    const std::uint32_t lo = dx < dy ? dx : dy, hi = dx < dy ? dy : dx;
    return static_cast<Cost>(hi - lo) * this->cardinal_ + static_cast<Cost>(lo) * this->diagonal_;
  }
};

// Exact distance on an empty 4-connected grid; overestimates on 8-connected ones (inadmissible).
template <class Cost>
class ManhattanHeuristic : public GridHeuristic<Cost> {
 public:
  static constexpr GridHeuristicKind kKind = GridHeuristicKind::Manhattan;
  using GridHeuristic<Cost>::GridHeuristic;
  Cost operator()(std::uint32_t id) const {
    std::uint32_t dx, dy;
    this->deltas(id, dx, dy);
    return static_cast<Cost>(dx + dy) * this->cardinal_;
  }
};

// Straight-line distance: admissible for any connectivity and for any-angle search.
template <class Cost>
class EuclideanHeuristic : public GridHeuristic<Cost> {
 public:
  static constexpr GridHeuristicKind kKind = GridHeuristicKind::Euclidean;
  using GridHeuristic<Cost>::GridHeuristic;
  Cost operator()(std::uint32_t id) const {
    std::uint32_t dx, dy;
    this->deltas(id, dx, dy);
    const double d = std::sqrt(static_cast<double>(dx) * dx + static_cast<double>(dy) * dy);
    if constexpr (std::is_integral_v<Cost>) return static_cast<Cost>(std::floor(d * static_cast<double>(this->cardinal_)));
    else return static_cast<Cost>(d * this->cardinal_);
  }
};

// w * inner (w >= 1): weighted A*. Inadmissible when w > 1 (cost <= w * optimal).
template <class Inner>
class WeightedHeuristic {
 public:
  static constexpr GridHeuristicKind kKind = Inner::kKind;
  WeightedHeuristic() = default;
  WeightedHeuristic(Inner inner, double weight) : inner_(inner), weight_(weight) {}
  void set_goal(std::uint32_t goal) { inner_.set_goal(goal); }
  auto operator()(std::uint32_t id) const {
    using Cost = decltype(inner_(id));
    return static_cast<Cost>(weight_ * static_cast<double>(inner_(id)));
  }
  double weight() const { return weight_; }
  // A weight above 1 makes any heuristic inadmissible: costs are only within w of the optimum.
  bool keeps_admissibility() const { return weight_ <= 1.0; }

 private:
  Inner inner_;
  double weight_ = 1.0;
};

}  // namespace starnav
