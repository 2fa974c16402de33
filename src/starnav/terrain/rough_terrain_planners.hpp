#pragma once
// The three planners of Liu et al. 2024 on elevation maps (docs/papers/liu2024.md):
//
//   oa    OA*: A* with distance cost only; only the map's own obstacles are blocked (on an
//         elevation map: unobserved cells under UnobservedPolicy::Blocked).
//   aoea  AOEA*: A* with distance cost only on the Liu obstacle mask (slope, step or ruggedness
//         reaching its threshold) expanded by the robot radius (terrain_analysis.hpp).
//   ia    IA*: A* with the Liu move cost w1 * g + w2 * d (liu_cost.hpp) and passability per move;
//         heuristic the paper's H (Euclidean distance, not admissible: searched with reopening,
//         as the paper's Algorithm 1, unless options.reopen is off) or the admissible
//         w2 * Euclidean distance (consistent: optimal without reopening). Both run on the search
//         core (search_core.hpp), with its ReopenClosed policy for the paper's H.
//
// All three are GridPlanner (grid_planner.hpp): 8-connected, a diagonal move needs both straight
// moves beside it passable (for IA*: the straight moves from the parent to the two cells beside
// the diagonal). OA* and AOEA* are the project's A* (octile heuristic) on a blocked mask. IA*
// runs on TerrainMoveGraph: the cost of every move of every cell precomputed once per planner
// (8 floats per cell; +inf = impassable), so an expansion reads one 32-byte record.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/plan/grid_graph.hpp"
#include "starnav/plan/global_planner.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/search_core.hpp"
#include "starnav/terrain/liu_cost.hpp"
#include "starnav/terrain/terrain_analysis.hpp"

namespace starnav {

enum class RoughTerrainPlannerKind : std::uint8_t { OA, AOEA, IA };
const char* rough_terrain_planner_name(RoughTerrainPlannerKind k);  // "oa", "aoea", "ia"
// "oa", "aoea", "ia" (also "oastar", "aoeastar", "iastar"); Error naming `field` otherwise.
RoughTerrainPlannerKind parse_rough_terrain_planner(const std::string& name, const std::string& field = "planner");
std::vector<std::string> rough_terrain_planner_names();

struct RoughTerrainPlannerOptions {
  LiuCostParams cost;                                  // IA*: all of it; AOEA*: the thresholds
  LiuHeuristic heuristic = LiuHeuristic::Admissible;   // IA* only
  // IA* with the paper's H: reopen closed states reached again with a lower G, as the paper's
  // Algorithm 1 (default). Off: the search core without reopening, which is weighted A* with
  // w = 1 / w2 (cost <= optimal / w2) and expands each state once; on large maps reopening can
  // cost many re-expansions (docs/terrain.md has figures).
  bool reopen = true;
  UnobservedPolicy unobserved = UnobservedPolicy::Blocked;
  double robot_radius_m = 0.36;                        // AOEA* obstacle expansion
  bool record_trace = false;
  void validate() const;  // Error naming the field
};

// ---- IA* move costs ---------------------------------------------------------------------------

// Cost of move k out of (x, y) under IA* (double precision), +inf when impassable:
//  - leaving the map: impassable;
//  - both ends observed: liu_move_cost(a, h, S(child), d);
//  - an end unobserved: Blocked -> impassable; FreeFlat -> h = a = 0 and the child's S (0 when
//    unobserved); UnknownCost -> g = unobserved_g (impassable if the child is observed with
//    S >= s_y);
//  - a diagonal move additionally needs both straight moves beside it (from (x, y)) passable.
double ia_move_cost(const TerrainAnalysis& analysis, int x, int y, int k, const LiuCostParams& p);

// The IA* cost of a path of 8-neighbour cells (sum of ia_move_cost), +inf if a step is not a
// passable move.
double ia_path_cost(const TerrainAnalysis& analysis, const std::vector<Cell>& path, const LiuCostParams& p);

// ---- Search policies (search_core.hpp) ---------------------------------------------------------

// Precomputed move costs: costs[8 * i + k] for cell i = y * width + x and move k (kMoveDx/Dy),
// +inf for impassable moves. States are plain cell indices.
template <class Store = float>
class MoveCostTable {
 public:
  MoveCostTable() = default;
  // IA* costs of `analysis` under `p` (ia_move_cost, rounded to Store).
  MoveCostTable(const TerrainAnalysis& analysis, const LiuCostParams& p);

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t state_count() const { return costs_.size() / kMoveCount; }
  const Store* costs_of(std::uint32_t state) const { return costs_.data() + std::size_t{kMoveCount} * state; }
  const std::vector<Store>& costs() const { return costs_; }
  // State offset of move k.
  std::int64_t offset(int k) const { return offsets_[k]; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::int64_t offsets_[kMoveCount]{};
  std::vector<Store> costs_;
};

// The graph policy: successors of u are its moves with a finite cost.
template <class Store = float>
class TerrainMoveGraph {
 public:
  using cost_type = double;
  TerrainMoveGraph() = default;
  explicit TerrainMoveGraph(const MoveCostTable<Store>& table) : table_(&table) {
    for (int k = 0; k < kMoveCount; ++k) offsets_[k] = table.offset(k);
  }
  std::size_t state_count() const { return table_->state_count(); }

  template <class Visit>
  void for_each_successor(std::uint32_t u, Visit&& visit) const {
    const Store* c = table_->costs_of(u);
    constexpr Store kInf = std::numeric_limits<Store>::infinity();
    for (int k = 0; k < kMoveCount; ++k)
      if (c[k] != kInf) {
        const auto v = static_cast<std::uint32_t>(static_cast<std::int64_t>(u) + offsets_[k]);
        // The cost row of a successor is read when (if) it is expanded, usually soon after
        // the frontier reaches it: fetching it now hides most of that cache miss.
        __builtin_prefetch(table_->costs_of(v));
        visit(v, static_cast<double>(c[k]));
      }
  }

 private:
  const MoveCostTable<Store>* table_ = nullptr;
  std::int64_t offsets_[kMoveCount]{};
};

// scale * horizontal Euclidean distance (metres) from a state (plain cell index) to the goal:
// scale 1 is the paper's H, scale w2 the admissible one.
class TerrainEuclideanHeuristic {
 public:
  TerrainEuclideanHeuristic() = default;
  TerrainEuclideanHeuristic(int width, double resolution, double scale)
      : divider_(static_cast<std::uint32_t>(width)), width_(static_cast<std::uint32_t>(width)), factor_(resolution * scale) {}
  void set_goal(std::uint32_t goal) { split(goal, gx_, gy_); }
  double operator()(std::uint32_t id) const {
    std::uint32_t x, y;
    split(id, x, y);
    const double dx = static_cast<double>(x) - gx_, dy = static_cast<double>(y) - gy_;
    return factor_ * std::sqrt(dx * dx + dy * dy);
  }

 private:
  void split(std::uint32_t id, std::uint32_t& x, std::uint32_t& y) const {
    y = divider_.divide(id);
    x = id - y * width_;
  }
  void split(std::uint32_t id, double& x, double& y) const {
    std::uint32_t ux, uy;
    split(id, ux, uy);
    x = ux;
    y = uy;
  }
  FastDivider divider_{1};
  std::uint32_t width_ = 1;
  double factor_ = 1.0;
  double gx_ = 0.0, gy_ = 0.0;
};

// ---- The planners ------------------------------------------------------------------------------

class RoughTerrainPlanner final : public GridPlanner {
 public:
  // Analyses `map` itself (TerrainAnalysisOptions from `options`).
  RoughTerrainPlanner(RoughTerrainPlannerKind kind, const ElevationMap& map, const RoughTerrainPlannerOptions& options = {});
  // Shares an analysis (several planners on one map). Its unobserved policy must equal
  // options.unobserved (Error "unobserved" otherwise); AOEA* reuses its expanded obstacle mask
  // when its thresholds and radius match, else derives its own.
  RoughTerrainPlanner(RoughTerrainPlannerKind kind, std::shared_ptr<const TerrainAnalysis> analysis,
                      const RoughTerrainPlannerOptions& options = {});

  std::string_view name() const override;
  // OA*, AOEA* and IA* with the admissible H: true; IA* with the paper's H: false.
  bool admissible() const override;
  // Cells; cost: OA*/AOEA* the path length in metres, IA* the sum of its move costs (G of the
  // goal, recomputed in double precision); length: the horizontal length in metres.
  PlanResult plan(Cell start, Cell goal, const SearchLimits& limits = {}) override;
  const std::vector<Cell>& trace() const override;
  // Time to build the masks or the move-cost table (not the shared analysis).
  double preprocess_ms() const override { return preprocess_ms_; }

  RoughTerrainPlannerKind kind() const { return kind_; }
  const RoughTerrainPlannerOptions& options() const { return options_; }
  const TerrainAnalysis& analysis() const { return *analysis_; }
  // OA* / AOEA*: the cells the search treats as blocked (row-major, 1 = blocked); empty for IA*.
  const std::vector<std::uint8_t>& blocked_mask() const { return blocked_; }
  // IA* searches with the paper's H and reopening: states reopened by the last query.
  std::uint64_t reopened() const { return reopened_; }

 private:
  void build();
  PlanResult plan_ia(Cell start, Cell goal, const SearchLimits& limits);

  RoughTerrainPlannerKind kind_;
  RoughTerrainPlannerOptions options_;
  std::shared_ptr<const TerrainAnalysis> analysis_;
  double preprocess_ms_ = 0.0;
  std::uint64_t reopened_ = 0;
  // OA*, AOEA*
  std::vector<std::uint8_t> blocked_;
  std::unique_ptr<GridPlanner> grid_planner_;
  // IA*
  MoveCostTable<float> table_;
  BestFirstSearch<double> search_;
  BestFirstSearch<double, DefaultOpenList<double>, ReopenClosed> reopening_;
  std::vector<std::uint32_t> path_states_;
  std::vector<std::uint32_t> trace_states_;
  std::vector<Cell> trace_;
};

std::unique_ptr<RoughTerrainPlanner> make_rough_terrain_planner(std::string_view name, const ElevationMap& map,
                                                                const RoughTerrainPlannerOptions& options = {});

// The parameters the three planners declare in the registry (robot_radius_m, reopen, unobserved):
// a scenario's navigation.<planner> section; `starnav plan` takes them too (experiment/plan_query.hpp).
const ParamTable<RoughTerrainPlannerOptions>& rough_terrain_params();

// The registry entry of a rough-terrain planner (capability needs_elevation).
GlobalPlannerDef rough_terrain_global_planner(RoughTerrainPlannerKind kind);

}  // namespace starnav
