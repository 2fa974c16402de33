#include "starnav/terrain/rough_terrain_planners.hpp"

#include <chrono>
#include <cmath>
#include <utility>

#include "starnav/core/error.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/grid_plan_support.hpp"
#include "starnav/plan/grid_planners.hpp"

namespace starnav {

const char* rough_terrain_planner_name(RoughTerrainPlannerKind k) {
  switch (k) {
    case RoughTerrainPlannerKind::OA: return "oa";
    case RoughTerrainPlannerKind::AOEA: return "aoea";
    case RoughTerrainPlannerKind::IA: return "ia";
  }
  return "?";
}

RoughTerrainPlannerKind parse_rough_terrain_planner(const std::string& name, const std::string& field) {
  if (name == "oa" || name == "oastar") return RoughTerrainPlannerKind::OA;
  if (name == "aoea" || name == "aoeastar") return RoughTerrainPlannerKind::AOEA;
  if (name == "ia" || name == "iastar") return RoughTerrainPlannerKind::IA;
  throw Error("unknown rough-terrain planner '" + name + "' (oa, aoea, ia)", {}, 0, field);
}

std::vector<std::string> rough_terrain_planner_names() { return {"oa", "aoea", "ia"}; }

void RoughTerrainPlannerOptions::validate() const {
  cost.validate();
  if (!std::isfinite(robot_radius_m) || robot_radius_m < 0.0)
    throw Error("must be a finite number >= 0", {}, 0, "robot_radius_m");
}

// ---- IA* move costs ---------------------------------------------------------------------------

namespace {

// Cost of move k ignoring the diagonal rule.
double ia_single_move_cost(const TerrainAnalysis& t, int x, int y, int k, const LiuCostParams& p) {
  const int nx = x + kMoveDx[k], ny = y + kMoveDy[k];
  if (!t.contains(nx, ny)) return kImpassable;
  const double d = t.move_length(k);
  const bool from_obs = t.observed(x, y), to_obs = t.observed(nx, ny);
  if (from_obs && to_obs) {
    const MoveTerrain m = t.move(x, y, k);
    return liu_move_cost(m.a, m.h, t.ruggedness(nx, ny), d, t.resolution(), p);
  }
  switch (t.options().unobserved) {
    case UnobservedPolicy::Blocked: return kImpassable;
    case UnobservedPolicy::FreeFlat:
      return liu_move_cost(0.0, 0.0, to_obs ? t.ruggedness(nx, ny) : 0.0, d, t.resolution(), p);
    case UnobservedPolicy::UnknownCost: {
      if (to_obs && !(t.ruggedness(nx, ny) < p.s_y)) return kImpassable;
      const double scale = p.cost_per_metre ? d / t.resolution() : 1.0;
      return p.w1 * p.unobserved_g * scale + p.w2 * d;
    }
  }
  return kImpassable;
}

}  // namespace

double ia_move_cost(const TerrainAnalysis& analysis, int x, int y, int k, const LiuCostParams& p) {
  const double c = ia_single_move_cost(analysis, x, y, k, p);
  if (c == kImpassable || !move_is_diagonal(k)) return c;
  if (ia_single_move_cost(analysis, x, y, kDiagonalSideA[k], p) == kImpassable ||
      ia_single_move_cost(analysis, x, y, kDiagonalSideB[k], p) == kImpassable)
    return kImpassable;
  return c;
}

double ia_path_cost(const TerrainAnalysis& analysis, const std::vector<Cell>& path, const LiuCostParams& p) {
  double total = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const int k = move_index(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
    if (k < 0 || !analysis.contains(path[i - 1].x, path[i - 1].y)) return kImpassable;
    total += ia_move_cost(analysis, path[i - 1].x, path[i - 1].y, k, p);
  }
  return total;
}

namespace {

// f_s and f_e of the move between two cells (the same both ways): Ok when both are observed and
// the move is below the slope and step thresholds, Blocked when it reaches one, Special when an
// end is unobserved or outside the map (decided by ia_single_move_cost).
struct PairTerms {
  enum State : std::uint8_t { Blocked, Ok, Special };
  double f_s = 0.0;
  double f_e = 0.0;
  State state = Special;
};

PairTerms pair_terms(const TerrainAnalysis& t, int x, int y, int k, const LiuCostParams& p) {
  PairTerms r;
  const MoveTerrain m = t.move(x, y, k);
  if (!m.known) return r;
  // Exactly the tests of liu_move_cost (liu_passable), in the same order of evaluation.
  if (!(m.a < p.a_y && m.h < p.h_y)) {
    r.state = PairTerms::Blocked;
    return r;
  }
  r.f_s = liu_f_slope(m.a, p);
  r.f_e = liu_f_step(m.h, p);
  r.state = PairTerms::Ok;
  return r;
}

}  // namespace

// Costs bit for bit equal to ia_move_cost, computed with f_s and f_e once per neighbour pair
// (four per cell: E, N, NE, NW; the other four moves reuse their neighbours') and f_r once per
// cell: 4 atan and 9 tan per cell instead of 8 and 24.
template <class Store>
MoveCostTable<Store>::MoveCostTable(const TerrainAnalysis& t, const LiuCostParams& p)
    : width_(t.width()), height_(t.height()) {
  for (int k = 0; k < kMoveCount; ++k) offsets_[k] = static_cast<std::int64_t>(kMoveDy[k]) * width_ + kMoveDx[k];
  const std::size_t w = static_cast<std::size_t>(width_);
  costs_.resize(w * static_cast<std::size_t>(height_) * kMoveCount);
  // f_r per cell (only used for observed cells below s_y).
  std::vector<double> f_r(t.ruggedness().size(), 0.0);
  for (std::size_t i = 0; i < f_r.size(); ++i)
    if (t.observed()[i] && t.ruggedness()[i] < p.s_y) f_r[i] = liu_f_rugged(t.ruggedness()[i], p);
  // Forward pairs of the current and the previous row: [x * 4 + slot], slots E, N, NE, NW.
  constexpr int kForward[4] = {0, 1, 4, 5};
  std::vector<PairTerms> prev(w * 4), cur(w * 4);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x)
      for (int s = 0; s < 4; ++s) cur[static_cast<std::size_t>(x) * 4 + static_cast<std::size_t>(s)] = pair_terms(t, x, y, kForward[s], p);
    for (int x = 0; x < width_; ++x) {
      // The pair of each move k out of (x, y).
      const PairTerms* pk[kMoveCount] = {
          &cur[static_cast<std::size_t>(x) * 4 + 0],                               // E
          &cur[static_cast<std::size_t>(x) * 4 + 1],                               // N
          x > 0 ? &cur[static_cast<std::size_t>(x - 1) * 4 + 0] : nullptr,          // W = E of (x-1, y)
          y > 0 ? &prev[static_cast<std::size_t>(x) * 4 + 1] : nullptr,             // S = N of (x, y-1)
          &cur[static_cast<std::size_t>(x) * 4 + 2],                               // NE
          &cur[static_cast<std::size_t>(x) * 4 + 3],                               // NW
          x > 0 && y > 0 ? &prev[static_cast<std::size_t>(x - 1) * 4 + 2] : nullptr,  // SW = NE of (x-1, y-1)
          x + 1 < width_ && y > 0 ? &prev[static_cast<std::size_t>(x + 1) * 4 + 3] : nullptr,  // SE = NW of (x+1, y-1)
      };
      double c[kMoveCount];
      for (int k = 0; k < kMoveCount; ++k) {
        const int nx = x + kMoveDx[k], ny = y + kMoveDy[k];
        if (!t.contains(nx, ny)) {
          c[k] = kImpassable;
          continue;
        }
        const PairTerms& pt = *pk[k];
        if (pt.state == PairTerms::Special) {
          c[k] = ia_single_move_cost(t, x, y, k, p);
        } else if (pt.state == PairTerms::Blocked) {
          c[k] = kImpassable;
        } else {
          const std::size_t j = t.index(nx, ny);
          c[k] = t.ruggedness()[j] < p.s_y
                     ? liu_move_cost_from_terms(pt.f_s, pt.f_e, f_r[j], t.move_length(k), t.resolution(), p)
                     : kImpassable;
        }
      }
      for (int k = 4; k < kMoveCount; ++k)
        if (c[kDiagonalSideA[k]] == kImpassable || c[kDiagonalSideB[k]] == kImpassable) c[k] = kImpassable;
      Store* out = costs_.data() + t.index(x, y) * kMoveCount;
      for (int k = 0; k < kMoveCount; ++k) out[k] = static_cast<Store>(c[k]);
    }
    std::swap(prev, cur);
  }
}

template class MoveCostTable<float>;
template class MoveCostTable<double>;

// ---- Planner -------------------------------------------------------------------------------------

namespace {

std::shared_ptr<const TerrainAnalysis> analyse(const ElevationMap& map, const RoughTerrainPlannerOptions& o) {
  o.validate();
  TerrainAnalysisOptions ao;
  ao.unobserved = o.unobserved;
  ao.thresholds = o.cost;
  ao.robot_radius_m = o.robot_radius_m;
  return std::make_shared<const TerrainAnalysis>(map, ao);
}

bool same_thresholds(const LiuCostParams& a, const LiuCostParams& b) {
  return a.h_y == b.h_y && a.a_y == b.a_y && a.s_y == b.s_y;
}

}  // namespace

RoughTerrainPlanner::RoughTerrainPlanner(RoughTerrainPlannerKind kind, const ElevationMap& map,
                                         const RoughTerrainPlannerOptions& options)
    : RoughTerrainPlanner(kind, analyse(map, options), options) {}

RoughTerrainPlanner::RoughTerrainPlanner(RoughTerrainPlannerKind kind, std::shared_ptr<const TerrainAnalysis> analysis,
                                         const RoughTerrainPlannerOptions& options)
    : kind_(kind), options_(options), analysis_(std::move(analysis)) {
  options_.validate();
  if (!analysis_) throw Error("no terrain analysis given", {}, 0, "analysis");
  if (analysis_->options().unobserved != options_.unobserved)
    throw Error(std::string("the analysis treats unobserved cells as ") +
                    unobserved_policy_name(analysis_->options().unobserved) + ", the planner as " +
                    unobserved_policy_name(options_.unobserved),
                {}, 0, "unobserved");
  build();
}

void RoughTerrainPlanner::build() {
  const auto started = std::chrono::steady_clock::now();
  const TerrainAnalysis& t = *analysis_;
  if (kind_ == RoughTerrainPlannerKind::IA) {
    table_ = MoveCostTable<float>(t, options_.cost);
    search_.resize(table_.state_count());
    reopening_.resize(table_.state_count());
  } else {
    if (kind_ == RoughTerrainPlannerKind::OA) {
      blocked_.assign(t.observed().size(), 0);
      if (options_.unobserved == UnobservedPolicy::Blocked)
        for (std::size_t i = 0; i < blocked_.size(); ++i) blocked_[i] = t.observed()[i] ? 0 : 1;
    } else if (same_thresholds(options_.cost, t.options().thresholds) &&
               options_.robot_radius_m == t.options().robot_radius_m) {
      blocked_ = t.expanded_obstacle_mask();
    } else {
      blocked_ = inflate_mask(liu_obstacle_mask(t, options_.cost), t.width(), t.height(),
                             options_.robot_radius_m / t.resolution());
    }
    OccupancyGrid grid(t.geometry(), kFreeOccupancy);
    for (int y = 0; y < t.height(); ++y)
      for (int x = 0; x < t.width(); ++x)
        if (blocked_[t.index(x, y)]) grid(x, y) = kOccupiedOccupancy;
    GridPlannerOptions go;
    go.record_trace = options_.record_trace;
    grid_planner_ = std::make_unique<BestFirstGridPlanner>(BestFirstGridPlanner::Kind::AStar, grid, go);
  }
  preprocess_ms_ = elapsed_ms(started);
}

std::string_view RoughTerrainPlanner::name() const { return rough_terrain_planner_name(kind_); }

bool RoughTerrainPlanner::admissible() const {
  return kind_ != RoughTerrainPlannerKind::IA || options_.heuristic == LiuHeuristic::Admissible;
}

const std::vector<Cell>& RoughTerrainPlanner::trace() const {
  if (grid_planner_) return grid_planner_->trace();
  return trace_;
}

PlanResult RoughTerrainPlanner::plan(Cell start, Cell goal, const SearchLimits& limits) {
  if (kind_ != RoughTerrainPlannerKind::IA) return grid_planner_->plan(start, goal, limits);
  return plan_ia(start, goal, limits);
}

namespace {

// The search loop as a function of its own, not inlined into plan_ia: GCC inlined both loops (with
// and without reopening) there, and the plain loop then ran 12-18 % slower per expansion
// (bench/bench_terrain.cpp BM_RoughTerrainPlan).
template <class Search, class Listener = NullListener>
[[gnu::noinline]] SearchOutcome run_search(Search& search, const TerrainMoveGraph<float>& graph,
                                           const TerrainEuclideanHeuristic& h, std::uint32_t start, std::uint32_t goal,
                                           const SearchLimits& limits, Listener&& listener = {}) {
  return search.run(graph, h, start, SingleGoal{goal}, limits, std::forward<Listener>(listener));
}

}  // namespace

PlanResult RoughTerrainPlanner::plan_ia(Cell start, Cell goal, const SearchLimits& limits) {
  PlanResult result;
  trace_.clear();
  reopened_ = 0;
  const TerrainAnalysis& t = *analysis_;
  if (!t.contains(start.x, start.y)) {
    result.status = PlanStatus::StartOutsideMap;
    return result;
  }
  if (!t.contains(goal.x, goal.y)) {
    result.status = PlanStatus::GoalOutsideMap;
    return result;
  }
  const bool unobserved_blocked = options_.unobserved == UnobservedPolicy::Blocked;
  if (unobserved_blocked && !t.observed(start.x, start.y)) {
    result.status = PlanStatus::StartBlocked;
    return result;
  }
  if (!(start == goal)) {
    // No move can enter the goal: unobserved and blocked, or too rugged.
    const bool goal_obs = t.observed(goal.x, goal.y);
    if ((unobserved_blocked && !goal_obs) || (goal_obs && !(t.ruggedness(goal.x, goal.y) < options_.cost.s_y))) {
      result.status = PlanStatus::GoalBlocked;
      return result;
    }
  }
  const auto s = static_cast<std::uint32_t>(t.index(start.x, start.y));
  const auto g = static_cast<std::uint32_t>(t.index(goal.x, goal.y));
  TerrainMoveGraph<float> graph(table_);
  const bool paper_h = options_.heuristic == LiuHeuristic::Paper;
  const bool paper = paper_h && options_.reopen;  // the reopening search
  TerrainEuclideanHeuristic h(t.width(), t.resolution(), paper_h ? 1.0 : options_.cost.w2);
  h.set_goal(g);
  trace_states_.clear();
  const auto started = std::chrono::steady_clock::now();
  SearchOutcome outcome;
  if (paper) {
    outcome = options_.record_trace ? run_search(reopening_, graph, h, s, g, limits, TraceListener{&trace_states_})
                                    : run_search(reopening_, graph, h, s, g, limits);
  } else {
    outcome = options_.record_trace ? run_search(search_, graph, h, s, g, limits, TraceListener{&trace_states_})
                                    : run_search(search_, graph, h, s, g, limits);
  }
  result.time_ms = elapsed_ms(started);
  const SearchStats& st = paper ? reopening_.stats() : search_.stats();
  result.expanded = st.expanded;
  result.generated = st.generated;
  reopened_ = st.reopened;
  if (options_.record_trace) {
    trace_.reserve(trace_states_.size());
    for (const std::uint32_t id : trace_states_) trace_.push_back(t.geometry().cell_of_index(id));
  }
  if (outcome != SearchOutcome::Found) {
    result.status = plan_status_of(outcome);
    return result;
  }
  if (paper) reopening_.path_to(g, path_states_);
  else search_.path_to(g, path_states_);
  std::vector<Cell> cells;
  cells.reserve(path_states_.size());
  for (const std::uint32_t id : path_states_) cells.push_back(t.geometry().cell_of_index(id));
  set_found_path(result, t.geometry(), std::move(cells));
  result.cost = ia_path_cost(t, result.path_cells, options_.cost);
  return result;
}

std::unique_ptr<RoughTerrainPlanner> make_rough_terrain_planner(std::string_view name, const ElevationMap& map,
                                                                const RoughTerrainPlannerOptions& options) {
  return std::make_unique<RoughTerrainPlanner>(parse_rough_terrain_planner(std::string(name)), map, options);
}

}  // namespace starnav

// ---- the component -------------------------------------------------------------------------------

namespace starnav {

const ParamTable<RoughTerrainPlannerOptions>& rough_terrain_params() {
  static const ParamTable<RoughTerrainPlannerOptions> table = [] {
    using C = RoughTerrainPlannerOptions;
    ParamTable<C> t;
    t.real("robot_radius_m", &C::robot_radius_m, non_negative(), "m", "AOEA*: obstacle expansion radius");
    t.boolean("reopen", &C::reopen, "IA*: reopen closed states reached again with a lower G (the paper's Algorithm 1)");
    t.choice("unobserved", {"blocked", "free_flat", "unknown_cost"},
             [](C& c, const std::string& v) { c.unobserved = parse_unobserved_policy(v); },
             [](const C& c) { return std::string(unobserved_policy_name(c.unobserved)); },
             "how unobserved cells are treated");
    return t;
  }();
  return table;
}

namespace {

// A rough-terrain planner as a GlobalPlanner: a search on the elevation layer per call.
class TerrainGlobalPlanner final : public GlobalPlanner {
 public:
  TerrainGlobalPlanner(std::string name, const RoughTerrainPlannerOptions& o) : name_(std::move(name)), options_(o) {}
  std::string_view name() const override { return name_; }
  PlanResult plan(const PlanningLayers& layers, Cell start, Cell goal, std::span<const CellChange> /*changed*/) override {
    if (!layers.elevation) throw Error("planner '" + name_ + "' plans on elevation maps only", {}, 0, "planner");
    return make_rough_terrain_planner(name_, *layers.elevation, options_)->plan(start, goal);
  }

 private:
  std::string name_;
  RoughTerrainPlannerOptions options_;
};

}  // namespace

GlobalPlannerDef rough_terrain_global_planner(RoughTerrainPlannerKind kind) {
  GlobalPlannerDef d;
  const std::string name = rough_terrain_planner_name(kind);
  d.info.role = Role::GlobalPlanner;
  d.info.name = name;
  d.info.section = name;
  d.info.summary = kind == RoughTerrainPlannerKind::OA     ? "OA*: A* on traversable cells of an elevation map (Liu et al. 2024)"
                   : kind == RoughTerrainPlannerKind::AOEA ? "AOEA*: OA* with obstacle expansion (Liu et al. 2024)"
                                                           : "IA*: slope, step and ruggedness costs (Liu et al. 2024)";
  d.info.capabilities = {Capability::NeedsElevation};
  if (kind != RoughTerrainPlannerKind::IA) d.info.capabilities.add(Capability::Admissible);
  d.info.params = rough_terrain_params().specs();
  d.make = [name](const GlobalPlannerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<GlobalPlanner> {
    const RoughTerrainPlannerOptions o = configured(rough_terrain_params(), settings, ctx.file);
    try {
      o.validate();
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
    return std::make_unique<TerrainGlobalPlanner>(name, o);
  };
  return d;
}

}  // namespace starnav
