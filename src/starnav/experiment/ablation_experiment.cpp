#include "starnav/experiment/ablation_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/core/run_limits.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/experiment/runner.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/ou2022.hpp"
#include "starnav/plan/path_smoothing.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::vector<AblationVariant> variants_for(const AblationConfig& o) {
  const double k = o.turn_cost;
  std::vector<AblationVariant> v = {
      {"A*", false, 0.0, false, false, false},
      {"A* + turn_w", false, k, false, false, false},
      {"A* + turn_w + W", false, k, true, false, false},
      {"A* + turn_w + W + LOS", false, k, true, false, true},
  };
  if (o.exact_variant) v.push_back({"A* + turn_w (exact)", false, k, false, true, false});
  v.push_back({"JPS", true, 0.0, false, false, false});
  v.push_back({"JPS + LOS", true, 0.0, false, false, true});
  return v;
}

std::unique_ptr<GridPlanner> make_variant(const AblationVariant& v, const std::string& heuristic, double inflate,
                                          const OccupancyGrid& grid, const OccupancyThresholds& thresholds) {
  GridPlannerOptions options;
  options.thresholds = thresholds;
  options.ou2022.inflation.radius_m = inflate;
  if (v.smooth) options.ou2022.smoothing = PathSmoothing::LineOfSight;
  if (v.jps) return make_grid_planner("jps", grid, options);
  options.heuristic = heuristic;
  options.ou2022.turn_cost = v.turn_cost;
  options.ou2022.adaptive_weight = v.adaptive;
  options.ou2022.turn_exact = v.exact;
  options.ou2022.smoothing = v.smooth ? PathSmoothing::LineOfSight : PathSmoothing::None;
  // Every A* row through the same planner class, so that only the features differ.
  return std::make_unique<ImprovedAStarPlanner>(grid, options, false);
}

}  // namespace

std::vector<AblationQuery> read_ablation_queries(const std::string& path, int map_width, int map_height,
                                                 const std::string& map_name) {
  std::vector<AblationQuery> out;
  if (lower_extension(path) == ".scen") {
    const MovingAiScenario scen = read_movingai_scenario(path);
    check_scenario_map_size(scen, path, map_width, map_height, map_name);
    for (const ScenarioEntry& e : scen.entries) out.push_back({{e.start_x, e.start_y}, {e.goal_x, e.goal_y}});
    return out;
  }
  std::istringstream in([&] {
    try {
      return read_text_lines_file(path, kMaxInputFileBytes, "a query file (start_x,start_y,goal_x,goal_y)", [](std::string_view) {});
    } catch (const Error& e) {
      throw Error(e.message(), path, 0, "--queries");
    }
  }());
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line_no == 1 && line.find_first_of("0123456789") != 0 && line[0] != '-') {
      if (line != "start_x,start_y,goal_x,goal_y")
        throw Error("expected the header start_x,start_y,goal_x,goal_y", path, line_no);
      continue;
    }
    std::istringstream s(line);
    long long v[4];
    char comma = 0;
    bool ok = static_cast<bool>(s >> v[0]);
    for (int i = 1; ok && i < 4; ++i) ok = (s >> comma) && comma == ',' && (s >> v[i]);
    std::string rest;
    if (!ok || (s >> rest)) throw Error("expected four integers start_x,start_y,goal_x,goal_y", path, line_no);
    if (v[0] < 0 || v[2] < 0 || v[0] >= map_width || v[2] >= map_width || v[1] < 0 || v[3] < 0 || v[1] >= map_height ||
        v[3] >= map_height)
      throw Error("a cell outside the " + std::to_string(map_width) + " x " + std::to_string(map_height) + " map " + map_name,
                  path, line_no);
    out.push_back({{static_cast<int>(v[0]), static_cast<int>(v[1])}, {static_cast<int>(v[2]), static_cast<int>(v[3])}});
  }
  if (out.empty()) throw Error("no queries", path, 0, "--queries");
  return out;
}

namespace {

std::vector<AblationQuery> random_queries(const AblationConfig& o, const OccupancyGrid& grid, const GridSearchMap& inflated) {
  std::vector<Cell> free;
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x)
      if (inflated.passable(x, y)) free.push_back({x, y});
  if (free.empty()) throw Error("no free cell (after inflation) to draw queries from", o.map, 0, "--random");
  // Connected components of the inflated map under the planners' moves (8-connected, no corner
  // cutting): a query is solvable when its start and goal share one.
  std::vector<std::uint32_t> component(inflated.state_count(), 0);
  {
    std::uint32_t label = 0;
    std::vector<std::uint32_t> stack;
    for (const Cell& c : free) {
      const std::uint32_t s0 = inflated.state(c);
      if (component[s0]) continue;
      component[s0] = ++label;
      stack.push_back(s0);
      while (!stack.empty()) {
        const std::uint32_t u = stack.back();
        stack.pop_back();
        for_each_grid_move<8>(inflated, u, [&](std::uint32_t v, int, bool) {
          if (!component[v]) {
            component[v] = label;
            stack.push_back(v);
          }
        });
      }
    }
  }
  Rng rng(o.seed);
  std::vector<AblationQuery> out;
  const std::uint64_t max_attempts = static_cast<std::uint64_t>(o.random) * 100000 + 1000000;
  const int reach = static_cast<int>(std::ceil(o.max_dist));
  for (std::uint64_t attempt = 0; attempt < max_attempts && out.size() < o.random; ++attempt) {
    const Cell s = free[static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(free.size()) - 1))];
    const int dx = static_cast<int>(rng.uniform_int(-reach, reach)), dy = static_cast<int>(rng.uniform_int(-reach, reach));
    const double d = std::sqrt(static_cast<double>(dx) * dx + static_cast<double>(dy) * dy);
    if (d < o.min_dist || d > o.max_dist) continue;
    const Cell g{s.x + dx, s.y + dy};
    if (!inflated.passable(g.x, g.y)) continue;
    if (component[inflated.state(s)] != component[inflated.state(g)]) continue;
    out.push_back({s, g});
  }
  if (out.size() < o.random)
    throw Error("found only " + std::to_string(out.size()) + " of " + std::to_string(o.random) +
                    " solvable queries at distance " + format_fixed(o.min_dist, 0) + ".." + format_fixed(o.max_dist, 0) + " cells",
                o.map, 0, "--random");
  return out;
}

AblationRun run_query(GridPlanner& planner, const AblationQuery& q, int repeat, const GridSearchMap& los_map,
              const GridGeometry& geometry, const ClearanceField& clearance) {
  AblationRun run;
  std::vector<double> walls;
  PlanResult r;
  run.time_ms = std::numeric_limits<double>::infinity();
  for (int i = 0; i < repeat; ++i) {
    const double t0 = thread_cpu_s();
    r = planner.plan(q.start, q.goal);
    run.time_ms = std::min(run.time_ms, 1e3 * (thread_cpu_s() - t0));
    walls.push_back(r.time_ms);
  }
  run.wall_ms = sample_stats(std::move(walls)).median;
  run.found = r.found();
  run.expanded = r.expanded;
  run.generated = r.generated;
  if (!run.found) {
    run.reason = plan_status_reason(r.status);
    return run;
  }
  run.cost = r.cost;
  run.path = r.path_cells;
  run.metrics = compute_path_metrics(r.path_world, &clearance);
  const std::vector<Cell> los = remove_redundant_nodes(los_map, r.path_cells);
  const PathMetrics los_metrics = compute_path_metrics(cell_centres(los, geometry));
  run.vertices_los = los_metrics.vertices;
  run.turning_points_los = los_metrics.turning_points;
  return run;
}

double improvement_percent(double base, double value) { return base > 0 ? 100.0 * (base - value) / base : 0.0; }

std::vector<AblationSummary> summarise(const AblationTable& t, std::size_t queries) {
  std::vector<bool> common(queries, true);
  for (const auto& runs : t.runs)
    for (std::size_t q = 0; q < queries; ++q) common[q] = common[q] && runs[q].found;
  std::vector<AblationSummary> out(t.variants.size());
  double base_time = 0, base_expanded = 0;
  for (std::size_t v = 0; v < t.variants.size(); ++v) {
    AblationSummary& s = out[v];
    for (std::size_t q = 0; q < queries; ++q) {
      const AblationRun& r = t.runs[v][q];
      s.solved += r.found;
      if (!common[q]) continue;
      const AblationRun& a = t.runs[0][q];
      ++s.common;
      s.time_ms += r.time_ms;
      s.expanded += static_cast<double>(r.expanded);
      s.tir += improvement_percent(a.time_ms, r.time_ms);
      s.enr += improvement_percent(static_cast<double>(a.expanded), static_cast<double>(r.expanded));
      s.cost += r.cost;
      s.length += r.metrics.length;
      s.vertices += static_cast<double>(r.metrics.vertices);
      s.turning_points += static_cast<double>(r.metrics.turning_points);
      s.vertices_los += static_cast<double>(r.vertices_los);
      s.turning_points_los += static_cast<double>(r.turning_points_los);
      s.turn_total += r.metrics.turn_total_rad;
      s.turn_max += r.metrics.turn_max_rad;
      s.clearance_min += r.metrics.clearance_min;
      s.clearance_mean += r.metrics.clearance_mean;
      s.smoothness += r.metrics.smoothness;
    }
    if (v == 0) {
      base_time = s.time_ms;
      base_expanded = s.expanded;
    }
    s.tir_total = improvement_percent(base_time, s.time_ms);
    s.enr_total = improvement_percent(base_expanded, s.expanded);
    if (s.common > 0) {
      const double n = static_cast<double>(s.common);
      for (double* x : {&s.time_ms, &s.expanded, &s.tir, &s.enr, &s.cost, &s.length, &s.vertices, &s.turning_points,
                        &s.vertices_los, &s.turning_points_los, &s.turn_total, &s.turn_max, &s.clearance_min,
                        &s.clearance_mean, &s.smoothness})
        *x /= n;
    }
  }
  return out;
}

void write_summary_markdown(std::ostream& out, const AblationResult& r, const AblationTable& t) {
  const std::vector<AblationSummary>& s = t.summaries;
  const std::size_t queries = r.queries.size();
  const std::string& unit = r.unit;
  out << "### " << ablation_table_title(r, t) << "\n\n";
  out << "Means over the " << (s.empty() ? 0 : s[0].common) << " of " << queries
      << " queries every variant solved. Tir / Enr: % less time / fewer expansions than A* (mean of the per-query "
         "figures; in brackets, of the totals). Turning points and vertices of the returned path; LOS: after "
         "line-of-sight smoothing of that path. Clearance and length in "
      << unit << ".\n\n";
  out << "| variant | solved | time (ms) | expansions | Tir (%) | Enr (%) | cost | length | turning points | vertices "
         "| turning points (LOS) | vertices (LOS) | turn total (rad) | clearance min | clearance mean | smoothness "
         "|\n";
  out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t v = 0; v < t.variants.size(); ++v) {
    const AblationSummary& x = s[v];
    std::string name = t.variants[v].name;
    if (t.variants[v].jps && t.heuristic != "octile") name += " (octile)";
    out << "| " << name << " | " << x.solved << " | " << format_fixed(x.time_ms, 4) << " | " << format_fixed(x.expanded, 1) << " | "
        << format_fixed(x.tir, 2) << " (" << format_fixed(x.tir_total, 2) << ") | " << format_fixed(x.enr, 2) << " (" << format_fixed(x.enr_total, 2)
        << ") | " << format_fixed(x.cost, 3) << " | " << format_fixed(x.length, 3) << " | " << format_fixed(x.turning_points, 2) << " | "
        << format_fixed(x.vertices, 2) << " | " << format_fixed(x.turning_points_los, 2) << " | " << format_fixed(x.vertices_los, 2) << " | "
        << format_fixed(x.turn_total, 3) << " | " << format_fixed(x.clearance_min, 3) << " | " << format_fixed(x.clearance_mean, 3) << " | "
        << format_fixed(x.smoothness, 4) << " |\n";
  }
  out << "\n";
}

void write_per_query_markdown(std::ostream& out, const AblationResult& res, const AblationTable& t) {
  const std::vector<AblationQuery>& queries = res.queries;
  out << "### Per query: " << ablation_table_title(res, t) << "\n\n";
  out << "| query | start | goal | variant | time (ms) | expansions | Tir (%) | Enr (%) | length | turning points | "
         "vertices | vertices (LOS) | clearance min |\n";
  out << "|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t q = 0; q < queries.size(); ++q) {
    const AblationRun& a = t.runs[0][q];
    for (std::size_t v = 0; v < t.variants.size(); ++v) {
      const AblationRun& r = t.runs[v][q];
      out << "| " << q << " | (" << queries[q].start.x << ", " << queries[q].start.y << ") | (" << queries[q].goal.x
          << ", " << queries[q].goal.y << ") | " << t.variants[v].name << " | ";
      if (!r.found) {
        out << "- | " << r.expanded << " | - | - | " << r.reason << " | - | - | - | - |\n";
        continue;
      }
      const bool cmp = a.found;
      out << format_fixed(r.time_ms, 4) << " | " << r.expanded << " | "
          << (cmp ? format_fixed(improvement_percent(a.time_ms, r.time_ms), 2) : "-") << " | "
          << (cmp ? format_fixed(improvement_percent(static_cast<double>(a.expanded), static_cast<double>(r.expanded)), 2) : "-")
          << " | " << format_fixed(r.metrics.length, 3) << " | " << r.metrics.turning_points << " | " << r.metrics.vertices
          << " | " << r.vertices_los << " | " << format_fixed(r.metrics.clearance_min, 3) << " |\n";
    }
  }
  out << "\n";
}

json table_json(const AblationTable& t, const std::vector<AblationQuery>& queries) {
  const std::vector<AblationSummary>& s = t.summaries;
  json j;
  j["heuristic"] = t.heuristic;
  j["map"] = t.inflated ? "inflated" : "original";
  json variants = json::array();
  for (std::size_t v = 0; v < t.variants.size(); ++v) {
    const AblationSummary& x = s[v];
    json m;
    m["variant"] = t.variants[v].name;
    m["heuristic"] = t.variants[v].jps ? "octile" : t.heuristic;
    m["solved"] = x.solved;
    m["common"] = x.common;
    m["time_ms"] = x.time_ms;
    m["expanded"] = x.expanded;
    m["tir_percent"] = x.tir;
    m["enr_percent"] = x.enr;
    m["tir_total_percent"] = x.tir_total;
    m["enr_total_percent"] = x.enr_total;
    m["cost"] = x.cost;
    m["length"] = x.length;
    m["turning_points"] = x.turning_points;
    m["vertices"] = x.vertices;
    m["turning_points_los"] = x.turning_points_los;
    m["vertices_los"] = x.vertices_los;
    m["turn_total_rad"] = x.turn_total;
    m["turn_max_rad"] = x.turn_max;
    m["clearance_min"] = number_or_null(x.clearance_min);
    m["clearance_mean"] = number_or_null(x.clearance_mean);
    m["smoothness"] = x.smoothness;
    variants.push_back(m);
  }
  j["mean"] = variants;
  json per = json::array();
  for (std::size_t q = 0; q < queries.size(); ++q)
    for (std::size_t v = 0; v < t.variants.size(); ++v) {
      const AblationRun& r = t.runs[v][q];
      const AblationRun& a = t.runs[0][q];
      json e;
      e["query"] = q;
      e["variant"] = t.variants[v].name;
      e["found"] = r.found;
      if (!r.found) e["reason"] = r.reason;
      e["time_ms"] = r.time_ms;
      e["wall_ms"] = r.wall_ms;
      e["expanded"] = r.expanded;
      e["generated"] = r.generated;
      if (r.found && a.found) {
        e["tir_percent"] = improvement_percent(a.time_ms, r.time_ms);
        e["enr_percent"] = improvement_percent(static_cast<double>(a.expanded), static_cast<double>(r.expanded));
      }
      if (r.found) {
        e["cost"] = r.cost;
        e["length"] = r.metrics.length;
        e["vertices"] = r.metrics.vertices;
        e["turning_points"] = r.metrics.turning_points;
        e["vertices_los"] = r.vertices_los;
        e["turning_points_los"] = r.turning_points_los;
        e["turn_total_rad"] = r.metrics.turn_total_rad;
        e["turn_max_rad"] = r.metrics.turn_max_rad;
        e["clearance_min"] = number_or_null(r.metrics.clearance_min);
        e["clearance_mean"] = number_or_null(r.metrics.clearance_mean);
        e["smoothness"] = r.metrics.smoothness;
      }
      per.push_back(e);
    }
  j["per_query"] = per;
  return j;
}

void write_query_svg_picture(const std::string& path, const OccupancyGrid& grid, const OccupancyThresholds& thresholds,
                     const std::vector<std::uint8_t>& inflated, const AblationQuery& q, std::size_t index, const std::vector<std::pair<std::string, const AblationRun*>>& paths) {
  const GridGeometry& g = grid.geometry();
  int x0 = std::min(q.start.x, q.goal.x), x1 = std::max(q.start.x, q.goal.x);
  int y0 = std::min(q.start.y, q.goal.y), y1 = std::max(q.start.y, q.goal.y);
  for (const auto& [label, run] : paths)
    if (run && run->found)
      for (const Cell& c : run->path) {
        x0 = std::min(x0, c.x), x1 = std::max(x1, c.x);
        y0 = std::min(y0, c.y), y1 = std::max(y1, c.y);
      }
  const int margin = std::max(8, std::max(x1 - x0, y1 - y0) / 4);
  x0 = std::max(0, x0 - margin), y0 = std::max(0, y0 - margin);
  x1 = std::min(g.width - 1, x1 + margin), y1 = std::min(g.height - 1, y1 + margin);
  GridGeometry cg = g;
  cg.width = x1 - x0 + 1;
  cg.height = y1 - y0 + 1;
  const Vec2 corner = g.grid_to_world(Vec2(x0 * g.resolution, y0 * g.resolution));
  cg.origin = Pose2(corner.x(), corner.y(), g.origin.yaw);
  OccupancyGrid crop(cg);
  std::vector<Cell> inflated_cells;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      crop(x - x0, y - y0) = grid(x, y);
      const std::size_t i = g.index(x, y);
      if (inflated[i] && grid.state(x, y, thresholds) == CellState::Free) inflated_cells.push_back({x - x0, y - y0});
    }

  viz::PictureOptions po;
  po.title = "query " + std::to_string(index) + ": (" + std::to_string(q.start.x) + ", " + std::to_string(q.start.y) +
             ") to (" + std::to_string(q.goal.x) + ", " + std::to_string(q.goal.y) + ")";
  viz::MapPicture picture(crop, po);
  if (!inflated_cells.empty()) picture.add_cells(inflated_cells, viz::parse_colour("orange"), 0.3, "inflation");
  const double widths[] = {3.5, 2.5, 2.0, 1.5};
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (!paths[i].second || !paths[i].second->found) continue;
    viz::LineStyle line;
    line.colour = viz::categorical_colour(i);
    line.width_px = widths[std::min<std::size_t>(i, 3)];
    line.dashed = i == 3;
    picture.add_polyline(cell_centres(paths[i].second->path, g), line, paths[i].first);
  }
  viz::MarkerStyle marker;
  marker.radius_px = 4.5;
  marker.fill = viz::categorical_colour(4);
  picture.add_points({g.cell_center(q.start)}, marker, "start");
  marker.fill = viz::categorical_colour(5);
  picture.add_points({g.cell_center(q.goal)}, marker, "goal");
  picture.write_svg(path);
}

}  // namespace

std::string ablation_table_title(const AblationResult& r, const AblationTable& t) {
  return std::string(t.heuristic == "manhattan" ? "Manhattan" : "Octile") + " heuristic, " +
         (t.inflated ? "inflated map (R = " + format_fixed(r.config.inflate, 3) + " " + r.unit + ")" : "original map");
}

AblationResult run_ablation_experiment(const AblationConfig& o) {
  const bool from_file = !o.queries.empty();
  if (!from_file && o.random == 0) throw Error("expected a number of queries >= 1", {}, 0, "--random");
  if (o.repeat < 1 || o.repeat > kMaxRepeats) throw Error("expected a number in 1.." + std::to_string(kMaxRepeats), {}, 0, "--repeat");
  if (!(o.min_dist >= 0) || !(o.max_dist >= o.min_dist) || !std::isfinite(o.max_dist))
    throw Error("expected 0 <= --min-dist <= --max-dist", {}, 0, "--max-dist");
  if (!std::isfinite(o.inflate) || o.inflate < 0) throw Error("expected a radius >= 0", {}, 0, "--inflate");
  if (!std::isfinite(o.turn_cost) || o.turn_cost < 0) throw Error("expected a number >= 0", {}, 0, "--turn-cost");

  AblationResult res;
  res.config = o;
  res.map = load_map(o.map);
  if (res.map.is_elevation()) throw Error("is an elevation map; the ablation needs an occupancy map", o.map, 0, "--map");
  const OccupancyGrid& grid = res.map.occupancy();
  const GridGeometry& geometry = grid.geometry();
  const OccupancyThresholds thresholds = res.map.thresholds();
  res.index_grid = res.map.format == MapFormat::MovingAi || geometry.y_down;
  res.unit = res.index_grid ? "cells" : "m";

  InflationOptions inflation;
  inflation.radius_m = o.inflate;
  InflatedMap inflated = inflate_obstacles(grid, thresholds, false, inflation);
  res.obstacle_cells = inflated.obstacle_cells;
  res.inflated_cells = inflated.inflated_cells;
  const GridSearchMap inflated_map(grid.width(), grid.height(), inflated.blocked);
  const GridSearchMap original_map(grid, thresholds, false);
  const ClearanceField clearance(geometry, inflated.clearance_m);
  res.inflated_blocked = std::move(inflated.blocked);
  res.queries = from_file ? read_ablation_queries(o.queries, grid.width(), grid.height(), o.map) : random_queries(o, grid, inflated_map);

  for (const char* h : {"manhattan", "octile"})
    for (bool infl : {false, true}) {
      if (infl && o.inflate <= 0) continue;
      AblationTable t;
      t.heuristic = h;
      t.inflated = infl;
      t.variants = variants_for(o);
      res.tables.push_back(std::move(t));
    }
  for (AblationTable& t : res.tables) {
    if (o.on_table) o.on_table(ablation_table_title(res, t), res.queries.size());
    const double r = t.inflated ? o.inflate : 0.0;
    const GridSearchMap& los_map = t.inflated ? inflated_map : original_map;
    std::vector<std::unique_ptr<GridPlanner>> planners;
    ExperimentGrid trials_grid;
    for (std::size_t q = 0; q < res.queries.size(); ++q) trials_grid.instances.push_back("query " + std::to_string(q));
    for (const AblationVariant& v : t.variants) {
      planners.push_back(make_variant(v, t.heuristic, r, grid, thresholds));
      trials_grid.variants.push_back({v.name, {}});
    }
    trials_grid.seeds = {0};
    // Queries x variants, each query's variants side by side.
    const auto trials = run_experiment<GridPlanner*, AblationRun>(
        trials_grid, [&](const TrialKey& key) { return planners[key.variant].get(); },
        [&](GridPlanner* planner, const TrialKey& key) {
          return run_query(*planner, res.queries[key.instance], o.repeat, los_map, geometry, clearance);
        });
    t.runs.assign(t.variants.size(), std::vector<AblationRun>(res.queries.size()));
    for (const Trial<AblationRun>& trial : trials) {
      AblationRun& run = t.runs[trial.key.variant][trial.key.instance];
      run = trial.record;
      if (!trial.completed) run.reason = trial.error;
    }
    t.summaries = summarise(t, res.queries.size());
  }
  return res;
}

std::string ablation_summary_markdown(const AblationResult& r) {
  const AblationConfig& o = r.config;
  const OccupancyGrid& grid = r.map.occupancy();
  std::ostringstream md;
  md << "## Ablation (Ou et al. 2022, Table 2): " << fs::path(o.map).filename().string() << "\n\n";
  md << "Map " << o.map << ": " << grid.width() << " x " << grid.height() << " cells"
     << (r.index_grid ? "" : ", " + format_fixed(grid.geometry().resolution, 3) + " m/cell") << "; " << r.obstacle_cells
     << " obstacle cells";
  if (o.inflate > 0)
    md << ", inflated by R = " << format_fixed(o.inflate, 3) << " " << r.unit << ": " << r.inflated_cells
       << " more cells blocked";
  md << ". " << r.queries.size() << " queries ("
     << (!o.queries.empty() ? "from " + o.queries
                            : "random, seed " + std::to_string(o.seed) + ", " + format_fixed(o.min_dist, 0) + ".." +
                                  format_fixed(o.max_dist, 0) + " cells apart")
     << "), turn cost k_turn = " << format_fixed(o.turn_cost, 3) << ", time = least thread CPU time of " << o.repeat
     << " runs of each query.\n\n";
  for (const AblationTable& t : r.tables) write_summary_markdown(md, r, t);
  return md.str();
}

std::string ablation_full_markdown(const AblationResult& r) {
  std::ostringstream full;
  full << ablation_summary_markdown(r);
  for (const AblationTable& t : r.tables) write_per_query_markdown(full, r, t);
  return full.str();
}

std::string ablation_queries_csv(const AblationResult& r) {
  std::ostringstream csv;
  csv << "start_x,start_y,goal_x,goal_y\n";
  for (const AblationQuery& q : r.queries) csv << q.start.x << "," << q.start.y << "," << q.goal.x << "," << q.goal.y << "\n";
  return csv.str();
}

std::string ablation_json(const AblationResult& r) {
  const AblationConfig& o = r.config;
  const OccupancyGrid& grid = r.map.occupancy();
  json j;
  j["benchmark"] = "ablation";
  j["paper"] = "Ou et al. 2022, Table 2";
  j["map"] = o.map;
  j["width"] = grid.width();
  j["height"] = grid.height();
  j["resolution"] = grid.geometry().resolution;
  j["units"] = r.unit;
  j["obstacle_cells"] = r.obstacle_cells;
  j["inflate"] = o.inflate;
  j["inflated_cells"] = r.inflated_cells;
  j["turn_cost"] = o.turn_cost;
  j["repeat"] = o.repeat;
  if (o.queries.empty()) {
    j["seed"] = o.seed;
    j["min_dist_cells"] = o.min_dist;
    j["max_dist_cells"] = o.max_dist;
  }
  json qs = json::array();
  for (const AblationQuery& q : r.queries) qs.push_back({{"start", {q.start.x, q.start.y}}, {"goal", {q.goal.x, q.goal.y}}});
  j["queries"] = qs;
  json ts = json::array();
  for (const AblationTable& t : r.tables) ts.push_back(table_json(t, r.queries));
  j["tables"] = ts;
  return j.dump(1) + "\n";
}

void write_ablation_query_svg(const AblationResult& r, std::size_t q, const std::string& path) {
  // The Manhattan tables' paths (the paper's heuristic): A* on the original map, A* + turn_w + W
  // and the full method on the inflated one (the original without inflation), and JPS + LOS there.
  const AblationTable* base = nullptr;
  const AblationTable* infl = nullptr;
  for (const AblationTable& t : r.tables)
    if (t.heuristic == "manhattan") (t.inflated ? infl : base) = &t;
  if (!infl) infl = base;
  auto find = [](const AblationTable* t, const std::string& name) -> std::size_t {
    for (std::size_t v = 0; v < t->variants.size(); ++v)
      if (t->variants[v].name == name) return v;
    return 0;
  };
  const bool inflated = r.config.inflate > 0;
  write_query_svg_picture(
      path, r.map.occupancy(), r.map.thresholds(), r.inflated_blocked, r.queries[q], q,
      {{inflated ? "A* (original map)" : "A*", &base->runs[0][q]},
       {inflated ? "A* + turn_w + W (inflated map)" : "A* + turn_w + W", &infl->runs[find(infl, "A* + turn_w + W")][q]},
       {inflated ? "full method (inflation + LOS + turn_w + W)" : "A* + turn_w + W + LOS",
        &infl->runs[find(infl, "A* + turn_w + W + LOS")][q]},
       {inflated ? "JPS + LOS (inflated map)" : "JPS + LOS", &infl->runs[find(infl, "JPS + LOS")][q]}});
}

}  // namespace starnav
