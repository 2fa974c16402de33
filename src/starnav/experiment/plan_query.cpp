#include "starnav/experiment/plan_query.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/thread_pool.hpp"
#include "starnav/plan/global_planner.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

namespace {

// The last setting of `key` (a later one wins, as in ParamTable::apply), or nullptr.
const ParamSetting* find_setting(std::span<const ParamSetting> settings, const std::string& key) {
  for (auto it = settings.rbegin(); it != settings.rend(); ++it)
    if (it->key == key) return &*it;
  return nullptr;
}

[[noreturn]] void fail_at(const ParamSetting& s, const std::string& message) {
  throw Error(message, s.file, s.line, s.field.empty() ? s.key : s.field);
}

// An Error of a check deeper in the library, whose field is a library name, attributed to the
// setting that gave the value: its key is the field itself or, where the declared name differs
// from the library's field, the key `renamed` maps it to. Without such a setting the error names
// the key.
[[noreturn]] void rethrow_at_key(const Error& e, std::span<const ParamSetting> settings,
                                 std::initializer_list<std::pair<const char*, const char*>> renamed) {
  std::string key = e.field();
  for (const auto& [field, declared] : renamed)
    if (key == field) key = declared;
  if (const ParamSetting* s = find_setting(settings, key)) fail_at(*s, e.message());
  throw Error(e.message(), e.file(), e.line(), key);
}

// The library's fields of the occupancy options that are declared under other names.
constexpr std::initializer_list<std::pair<const char*, const char*>> kOccupancyRenamed = {
    {"inflate_cost_radius", "cost_radius_m"},
    {"inflate_cost", "cost_scale_per_m"},
    {"inflate_cost_weight", "cost_weight"},
    {"start_heading", "start_heading_deg"}};

template <class Config>
void declare_limits(ParamTable<Config>& t, SearchLimits& (*limits)(Config&)) {
  t.integer("max_expansions", [limits](Config& c) -> std::uint64_t& { return limits(c).max_expansions; },
            non_negative(), "", "stop after this many expansions (0: no limit)");
  t.real("time_budget", [limits](Config& c) -> double& { return limits(c).time_budget_s; }, non_negative(), "s",
         "stop after this many seconds of search (0: no limit)");
}

}  // namespace

const ParamTable<PlanRequest>& occupancy_plan_params() {
  static const ParamTable<PlanRequest> table = [] {
    using R = PlanRequest;
    ParamTable<R> t;
    ParamSpec connectivity{"connectivity", ParamType::Integer, {}, closed(4, 8), {}, "",
                           "4 or 8 neighbours (8: diagonal moves, never cutting a corner)"};
    t.custom(
        std::move(connectivity),
        [](R& r, const ParamSetting& v) {
          const long long n = parse_param_integer(v);
          if (n != 4 && n != 8) fail_at(v, "must be 4 or 8, got " + v.value);
          r.options.connectivity = static_cast<int>(n);
        },
        [](const R& r) { return std::to_string(r.options.connectivity); });
    t.choice(
        "unknown", {"free", "blocked"}, [](R& r, const std::string& v) { r.options.unknown_is_free = v == "free"; },
        [](const R& r) { return std::string(r.options.unknown_is_free ? "free" : "blocked"); },
        "unknown cells are free (optimistic) or blocked");
    t.real("weight", [](R& r) -> double& { return r.options.weight; }, ParamRange{1.0, kInfinity, false, false}, "",
           "f = g + weight * h (planners with the heuristic_weight capability; > 1 is inadmissible)");
    t.choice(
        "heuristic", {"octile", "manhattan", "euclidean", "zero"},
        [](R& r, const std::string& v) { r.options.heuristic = v; }, [](const R& r) { return r.options.heuristic; },
        "the search's heuristic (manhattan on 8-connected grids is inadmissible)");
    t.default_rule("heuristic", "octile on 8-connected grids; manhattan on 4-connected ones and for ou2022");
    t.real("inflate", [](R& r) -> double& { return r.options.ou2022.inflation.radius_m; }, non_negative(), "m",
           "block every cell within this distance of an obstacle (cells on MovingAI maps)");
    t.nest("", cost_band_params(), [](R& r) -> InflationOptions& { return r.options.ou2022.inflation; });
    // Options whose absence means "the planner's default" (ou2022 turns them on): a setting makes
    // the optional hold a value.
    t.real(
        "turn_cost",
        [](R& r) -> double& {
          auto& v = r.options.ou2022.turn_cost;
          if (!v) v = 0.0;
          return *v;
        },
        non_negative(), "", "steering cost k: a turn of D degrees costs k * D / 45 cells (astar, ou2022)");
    t.default_rule("turn_cost", "1 for ou2022, 0 (off) otherwise");
    t.boolean("turn_exact", [](R& r) -> bool& { return r.options.ou2022.turn_exact; },
              "search (cell, incoming direction) states: optimal for the turn-inclusive cost (astar, ou2022)");
    t.boolean(
        "adaptive_weight",
        [](R& r) -> bool& {
          auto& v = r.options.ou2022.adaptive_weight;
          if (!v) v = false;
          return *v;
        },
        "f = g + (1 + d/D) h, inadmissible (astar, ou2022)");
    t.default_rule("adaptive_weight", "true for ou2022, false otherwise");
    t.choice(
        "smooth", {"none", "los", "gradient"}, [](R& r, const std::string& v) { r.smoothing = parse_plan_smoothing(v); },
        [](const R& r) -> std::string {
          switch (r.smoothing) {
            case PlanSmoothing::None: return "none";
            case PlanSmoothing::LineOfSight: return "los";
            case PlanSmoothing::Gradient: return "gradient";
            case PlanSmoothing::PlannerDefault: break;
          }
          return "";
        },
        "remove redundant nodes by line of sight (los); gradient: then smooth the curvature on the inflated map");
    t.default_rule("smooth", "los for ou2022, none otherwise");
    t.real("smooth_clearance", [](R& r) -> double& { return r.gradient.min_clearance_m; }, non_negative(), "m",
           "with smooth gradient: keep at least this clearance where the path had it (cells on MovingAI maps)");
    t.real(
        "start_heading_deg",
        [](R& r) -> double& {
          auto& v = r.options.ou2022.start_heading_rad;
          if (!v) v = 0.0;
          return *v;
        },
        any_value(), "deg",
        "the robot's initial yaw (map frame; cell axes on MovingAI maps), so the first move's turn is charged", kPi / 180.0);
    t.default_rule("start_heading_deg", "none (the first move turns for free)");
    declare_limits<R>(t, [](R& r) -> SearchLimits& { return r.limits; });
    t.boolean("expanded", [](R& r) -> bool& { return r.options.record_trace; }, "also report the expanded cells");
    return t;
  }();
  return table;
}

PlanRequest occupancy_plan_request(const std::string& planner, std::span<const ParamSetting> settings,
                                   const GridGeometry& geometry, bool index_grid, const OccupancyThresholds& thresholds,
                                   const std::string& map_name, const std::string& planner_field, std::string* warning) {
  const GlobalPlannerDef& def = find_global_planner(planner, planner_field, warning);
  if (def.info.has(Capability::NeedsElevation))
    throw Error("'" + planner + "' plans on elevation maps; " + map_name + " is an occupancy map", {}, 0, planner_field);
  if (def.info.has(Capability::NeedsHeadings))
    throw Error("'" + planner + "' plans between poses (start and goal headings), not between cells", {}, 0, planner_field);
  PlanRequest rq = configured(occupancy_plan_params(), settings, {});
  rq.planner = planner;
  rq.options.thresholds = thresholds;
  if (rq.options.weight != 1.0 && !def.info.has(Capability::HeuristicWeight)) {
    std::string weighted;
    for (const GlobalPlannerDef& d : global_planners())
      if (d.info.has(Capability::HeuristicWeight)) weighted += (weighted.empty() ? "" : ", ") + d.info.name;
    const std::string message = "'" + planner + "' takes no weight (planners that do: " + weighted + ")";
    if (const ParamSetting* s = find_setting(settings, "weight")) fail_at(*s, message);
    throw Error(message, {}, 0, "weight");
  }
  if (rq.smoothing == PlanSmoothing::Gradient) {
    try {
      validate_gradient_smoothing(rq.gradient);
    } catch (const Error& e) {
      rethrow_at_key(e, settings, {});
    }
  } else if (const ParamSetting* s = find_setting(settings, "smooth_clearance")) {
    fail_at(*s, "only with --smooth gradient");
  }
  // A world yaw becomes one in the grid's cell axes (index grids have no yaw of their own).
  if (rq.options.ou2022.start_heading_rad && !index_grid) *rq.options.ou2022.start_heading_rad -= geometry.origin.yaw;
  return rq;
}

PlanOutcome plan_query_on_grid(const OccupancyGrid& grid, Cell start, Cell goal, const PlanRequest& request,
                               std::span<const ParamSetting> settings) {
  try {
    return plan_on_grid(grid, start, goal, request);
  } catch (const Error& e) {
    if (e.field().empty() || e.field() == "planner") throw;
    rethrow_at_key(e, settings, kOccupancyRenamed);
  }
}

// ---- elevation maps ----------------------------------------------------------------------------

const ParamTable<TerrainPlanQuery>& terrain_plan_params() {
  static const ParamTable<TerrainPlanQuery> table = [] {
    using Q = TerrainPlanQuery;
    ParamTable<Q> t;
    t.real("h_y", [](Q& q) -> double& { return q.options.cost.h_y; }, positive(), "m",
           "step threshold: a height difference from this on is impassable (aoea, ia)");
    t.real("a_y", [](Q& q) -> double& { return q.options.cost.a_y; }, open(0.0, kPi / 2), "rad",
           "slope threshold (aoea, ia)");
    t.real("s_y", [](Q& q) -> double& { return q.options.cost.s_y; }, positive(), "m^2",
           "ruggedness threshold, the 3x3 height variance (aoea, ia)");
    t.real("w_s", [](Q& q) -> double& { return q.options.cost.w_s; }, non_negative(), "",
           "weight of the slope term of g (ia; w_s + w_e + w_r = 1)");
    t.real("w_e", [](Q& q) -> double& { return q.options.cost.w_e; }, non_negative(), "",
           "weight of the step term of g (ia)");
    t.real("w_r", [](Q& q) -> double& { return q.options.cost.w_r; }, non_negative(), "",
           "weight of the ruggedness term of g (ia)");
    t.real("w1", [](Q& q) -> double& { return q.options.cost.w1; }, non_negative(), "",
           "weight of g in the move cost w1 * g + w2 * d (ia)");
    t.real("w2", [](Q& q) -> double& { return q.options.cost.w2; }, non_negative(), "",
           "weight of the distance d in the move cost (ia)");
    t.boolean("cost_per_metre", [](Q& q) -> bool& { return q.options.cost.cost_per_metre; },
              "charge g per metre (g * d / resolution) instead of per move (ia)");
    ParamSpec admissible{"admissible", ParamType::Boolean, {}, {}, {}, "",
                         "H = w2 * distance (admissible, optimal) instead of the paper's H = distance (ia)"};
    t.custom(
        std::move(admissible),
        [](Q& q, const ParamSetting& v) {
          q.options.heuristic = parse_param_boolean(v) ? LiuHeuristic::Admissible : LiuHeuristic::Paper;
        },
        [](const Q& q) { return std::string(q.options.heuristic == LiuHeuristic::Admissible ? "true" : "false"); });
    t.nest("", rough_terrain_params(), [](Q& q) -> RoughTerrainPlannerOptions& { return q.options; });
    declare_limits<Q>(t, [](Q& q) -> SearchLimits& { return q.limits; });
    t.boolean("expanded", [](Q& q) -> bool& { return q.options.record_trace; }, "also report the expanded cells");
    return t;
  }();
  return table;
}

TerrainPlanQuery terrain_plan_query(std::span<const ParamSetting> settings,
                                    std::span<const RoughTerrainPlannerKind> planners) {
  TerrainPlanQuery defaults;
  defaults.options.heuristic = LiuHeuristic::Paper;  // `starnav plan`'s: the paper's Algorithm 1
  TerrainPlanQuery q = configured(terrain_plan_params(), settings, {}, defaults);
  const auto runs = [&](RoughTerrainPlannerKind k) { return std::find(planners.begin(), planners.end(), k) != planners.end(); };
  const bool aoea = runs(RoughTerrainPlannerKind::AOEA), ia = runs(RoughTerrainPlannerKind::IA);
  for (const ParamSetting& s : settings) {
    const std::string& k = s.key;
    if ((k == "h_y" || k == "a_y" || k == "s_y") && !aoea && !ia) fail_at(s, "applies to --planner aoea and ia only");
    if ((k == "w_s" || k == "w_e" || k == "w_r" || k == "w1" || k == "w2" || k == "admissible" ||
         k == "cost_per_metre" || k == "reopen") &&
        !ia)
      fail_at(s, "applies to --planner ia only");
    if (k == "robot_radius_m" && !aoea) fail_at(s, "applies to --planner aoea only");
  }
  try {
    q.options.validate();
  } catch (const Error& e) {
    // The weights' sum names them together: the last of the three given.
    if (e.field() == "weights") {
      const ParamSetting* given = nullptr;
      for (const ParamSetting& s : settings)
        if (s.key == "w_s" || s.key == "w_e" || s.key == "w_r") given = &s;
      if (given) fail_at(*given, e.message());
    }
    rethrow_at_key(e, settings, {});
  }
  return q;
}

RoughTerrainPlannerKind terrain_plan_planner(const std::string& name, const std::string& field) {
  const std::vector<std::string> occupancy = grid_planner_names();
  if (std::find(occupancy.begin(), occupancy.end(), name) != occupancy.end())
    throw Error("'" + name + "' plans on occupancy maps; on an elevation map use oa (A* on the map's own obstacles), "
                "aoea or ia",
                {}, 0, field);
  return parse_rough_terrain_planner(name, field);
}

// ---- both ---------------------------------------------------------------------------------------

std::string plan_query_flag(const std::string& key) {
  static const std::pair<const char*, const char*> kFlags[] = {
      {"cost_radius_m", "--inflate-cost-radius"}, {"cost_scale_per_m", "--inflate-cost"},
      {"cost_weight", "--inflate-cost-weight"},   {"h_y", "--hy-m"},
      {"a_y", "--ay-rad"},                        {"s_y", "--sy-m2"},
      {"w_s", "--weights"},                       {"w_e", "--weights"},
      {"w_r", "--weights"},                       {"w1", "--weights"},
      {"w2", "--weights"}};
  for (const auto& [k, flag] : kFlags)
    if (key == k) return flag;
  std::string flag = "--" + key;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

Cell plan_endpoint_cell(const Vec2& p, bool in_cells, const GridGeometry& geometry, const std::string& field,
                        const std::string& text) {
  if (in_cells) {
    const double lim = static_cast<double>(std::numeric_limits<int>::max());
    if (p.x() != std::floor(p.x()) || p.y() != std::floor(p.y()) || std::abs(p.x()) > lim || std::abs(p.y()) > lim)
      throw Error("expected cell indices X,Y (two integers), got '" + one_line(text, 60) + "'", {}, 0, field);
    return {static_cast<int>(p.x()), static_cast<int>(p.y())};
  }
  const Vec2 c = geometry.world_to_cell_continuous(p);
  const double lim = 1e9;
  if (!(std::abs(c.x()) <= lim) || !(std::abs(c.y()) <= lim)) return {-1, -1};  // far outside the map (or NaN)
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

// ---- many queries ------------------------------------------------------------------------------

std::vector<PlanResult> plan_many(std::span<const PlanEndpoints> queries,
                                  const std::function<std::unique_ptr<GridPlanner>()>& make_planner,
                                  const SearchLimits& limits, unsigned threads) {
  std::vector<PlanResult> results(queries.size());
  ThreadPool pool(threads);
  const std::size_t tasks = std::min<std::size_t>(pool.size(), std::max<std::size_t>(queries.size(), 1));
  pool.run(tasks, [&](std::size_t task) {
    const std::size_t begin = queries.size() * task / tasks, end = queries.size() * (task + 1) / tasks;
    if (begin == end) return;
    const std::unique_ptr<GridPlanner> planner = make_planner();
    for (std::size_t i = begin; i < end; ++i) results[i] = planner->plan(queries[i].start, queries[i].goal, limits);
  });
  return results;
}

std::vector<PlanResult> plan_many_on_grid(const OccupancyGrid& grid, std::span<const PlanEndpoints> queries,
                                          const PlanRequest& request, std::span<const ParamSetting> settings,
                                          unsigned threads) {
  if (request.smoothing == PlanSmoothing::Gradient) {
    const ParamSetting* s = find_setting(settings, "smooth");
    throw Error("gradient smoothing is per query: plan the queries one by one", {}, 0, s && !s->field.empty() ? s->field : "smooth");
  }
  if (request.options.record_trace) throw Error("expanded cells are kept by single queries only", {}, 0, "expanded");
  const GridPlannerOptions options = grid_planner_options(request);
  try {
    // Bad options fail where the first planner is built (the pool passes its error on).
    return plan_many(queries, [&] { return make_grid_planner(request.planner, grid, options); }, request.limits, threads);
  } catch (const Error& e) {
    if (e.field().empty() || e.field() == "planner") throw;
    rethrow_at_key(e, settings, kOccupancyRenamed);
  }
}

std::vector<PlanResult> plan_many_on_terrain(const ElevationMap& map, std::span<const PlanEndpoints> queries,
                                             const TerrainPlanQuery& query, unsigned threads) {
  if (query.options.record_trace) throw Error("expanded cells are kept by single queries only", {}, 0, "expanded");
  const std::string name = rough_terrain_planner_name(query.kind);
  return plan_many(
      queries, [&]() -> std::unique_ptr<GridPlanner> { return make_rough_terrain_planner(name, map, query.options); },
      query.limits, threads);
}

}  // namespace starnav
