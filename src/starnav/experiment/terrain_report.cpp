#include "starnav/experiment/terrain_report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "starnav/core/angle.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/experiment/detail/terrain_json.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

using json = nlohmann::ordered_json;

namespace detail {

json terrain_options_json(const RoughTerrainPlannerOptions& o) {
  json j;
  j["h_y_m"] = o.cost.h_y;
  j["a_y_rad"] = o.cost.a_y;
  j["s_y_m2"] = o.cost.s_y;
  j["w_s"] = o.cost.w_s;
  j["w_e"] = o.cost.w_e;
  j["w_r"] = o.cost.w_r;
  j["w1"] = o.cost.w1;
  j["w2"] = o.cost.w2;
  j["heuristic"] = liu_heuristic_name(o.heuristic);
  j["reopen"] = o.heuristic == LiuHeuristic::Paper && o.reopen;
  j["cost_per_metre"] = o.cost.cost_per_metre;
  j["robot_radius_m"] = o.robot_radius_m;
  j["unobserved"] = unobserved_policy_name(o.unobserved);
  return j;
}

const std::vector<std::string>& terrain_metric_keys() {
  static const std::vector<std::string> keys = {
      "lv_m",           "av_rad",        "hv_m",           "sv_m2",         "roll_mean_deg",      "roll_max_deg",
      "pitch_mean_deg", "pitch_max_deg", "tilt_mean_deg",  "tilt_max_deg",  "roll_mean_abs_deg",  "pitch_mean_abs_deg",
      "moves_measured", "cells_measured", "attitude_nodes"};
  return keys;
}

void add_terrain_metrics_json(json& j, const TerrainPathMetrics* m) {
  if (!m) {
    for (const std::string& k : terrain_metric_keys()) j[k] = nullptr;
    return;
  }
  j["lv_m"] = m->lv_m;
  j["av_rad"] = m->av_rad;
  j["hv_m"] = m->hv_m;
  j["sv_m2"] = m->sv_m2;
  j["roll_mean_deg"] = m->roll_mean_deg;
  j["roll_max_deg"] = m->roll_max_deg;
  j["pitch_mean_deg"] = m->pitch_mean_deg;
  j["pitch_max_deg"] = m->pitch_max_deg;
  j["tilt_mean_deg"] = m->tilt_mean_deg;
  j["tilt_max_deg"] = m->tilt_max_deg;
  j["roll_mean_abs_deg"] = m->roll_mean_abs_deg;
  j["pitch_mean_abs_deg"] = m->pitch_mean_abs_deg;
  j["moves_measured"] = m->moves_measured;
  j["cells_measured"] = m->cells_measured;
  j["attitude_nodes"] = m->attitude_nodes;
}

}  // namespace detail

TerrainPlanOutcome plan_on_terrain(const ElevationMap& map, Cell start, Cell goal, RoughTerrainPlannerKind kind,
                                   const RoughTerrainPlannerOptions& options, const SearchLimits& limits) {
  TerrainPlanOutcome o;
  o.kind = kind;
  o.options = options;
  RoughTerrainPlanner planner(kind, map, options);
  o.planner = std::string(planner.name());
  o.admissible = planner.admissible();
  o.result = planner.plan(start, goal, limits);
  o.reopened = planner.reopened();
  o.trace = planner.trace();
  o.blocked = planner.blocked_mask();
  const TerrainAnalysis& analysis = planner.analysis();
  if (o.result.found()) o.metrics = terrain_path_metrics(analysis, o.result.path_cells);
  for (const Cell& c : o.result.path_cells)
    o.path_z.push_back(analysis.observed(c.x, c.y) ? analysis.z(c.x, c.y) : std::numeric_limits<double>::quiet_NaN());
  return o;
}

std::string terrain_plan_json(const TerrainPlanOutcome& o) {
  const PlanResult& r = o.result;
  const bool ia = o.kind == RoughTerrainPlannerKind::IA;
  json j;
  j["planner"] = o.planner;
  j["admissible"] = o.admissible;
  if (ia) j["heuristic"] = liu_heuristic_name(o.options.heuristic);
  j["found"] = r.found();
  if (!r.found()) j["reason"] = plan_status_reason(r.status);
  j["cost"] = r.found() ? json(r.cost) : json(nullptr);
  j["length"] = r.found() ? json(r.length) : json(nullptr);
  j["units"] = "m";
  j["expanded"] = r.expanded;
  j["generated"] = r.generated;
  if (ia) j["reopened"] = o.reopened;
  json path = json::array(), path_cells = json::array();
  for (std::size_t i = 0; i < r.path_cells.size(); ++i) {
    path_cells.push_back({r.path_cells[i].x, r.path_cells[i].y});
    path.push_back({json_coordinate(r.path_world[i].x()), json_coordinate(r.path_world[i].y())});
  }
  j["path"] = path;
  j["path_cells"] = path_cells;
  detail::add_terrain_metrics_json(j, r.found() ? &o.metrics : nullptr);
  j["options"] = detail::terrain_options_json(o.options);
  if (o.options.record_trace) {
    json cells = json::array();
    for (const Cell& c : o.trace) cells.push_back({c.x, c.y});
    j["expanded_cells"] = cells;
  }
  j["time_ms"] = r.time_ms;
  return j.dump() + "\n";
}

std::string terrain_plan_text(const TerrainPlanOutcome& o) {
  const PlanResult& r = o.result;
  const TerrainPathMetrics& m = o.metrics;
  const bool ia = o.kind == RoughTerrainPlannerKind::IA;
  std::ostringstream out;
  out << "planner:    " << o.planner << (o.admissible ? "" : " (inadmissible)");
  if (ia)
    out << ", " << liu_heuristic_name(o.options.heuristic) << " H"
        << (o.options.cost.cost_per_metre ? ", g per metre" : ", g per move");
  out << "\n";
  if (r.found()) {
    out << "found:      yes, " << r.path_cells.size() << " points\n";
    out << "cost:       " << format_readable(r.cost) << "\n";
    out << "length:     " << format_readable(r.length) << " m horizontal, lv " << format_readable(m.lv_m) << " m\n";
    out << "terrain:    av " << format_readable(m.av_rad) << " rad, hv " << format_readable(m.hv_m) << " m, Sv "
        << format_readable(m.sv_m2) << " m^2\n";
    out << "attitude:   roll " << format_readable(m.roll_mean_deg) << " / " << format_readable(m.roll_max_deg)
        << " deg, pitch " << format_readable(m.pitch_mean_deg) << " / " << format_readable(m.pitch_max_deg)
        << " deg, tilt " << format_readable(m.tilt_mean_deg) << " / " << format_readable(m.tilt_max_deg)
        << " deg (|mean| / max)\n";
  } else {
    out << "found:      no (" << plan_status_reason(r.status) << ")\n";
  }
  out << "expanded:   " << r.expanded << "\ngenerated:  " << r.generated << "\n";
  if (ia && o.reopened > 0) out << "reopened:   " << o.reopened << "\n";
  out << "time:       " << format_readable(r.time_ms) << " ms\n";
  return out.str();
}

std::string terrain_plan_path_csv(const TerrainPlanOutcome& o) {
  const PlanResult& r = o.result;
  std::ostringstream out;
  out << std::setprecision(10) << "x_m,y_m,z_m,ix,iy\n";
  for (std::size_t i = 0; i < r.path_cells.size(); ++i) {
    const Cell c = r.path_cells[i];
    out << r.path_world[i].x() << "," << r.path_world[i].y() << ",";
    if (!std::isnan(o.path_z[i])) out << o.path_z[i];
    out << "," << c.x << "," << c.y << "\n";
  }
  return out.str();
}

void write_terrain_plan_picture(const TerrainPlanOutcome& o, const ElevationMap& map, Cell start, Cell goal,
                                const std::string& path) {
  const PlanResult& r = o.result;
  const bool expanded = o.options.record_trace;
  std::vector<Cell> shaded;
  if (expanded) {
    shaded = o.trace;
  } else if (o.kind != RoughTerrainPlannerKind::IA) {
    for (std::size_t i = 0; i < o.blocked.size(); ++i)
      if (o.blocked[i]) shaded.push_back(map.geometry().cell_of_index(i));
  }
  const std::string title = o.planner + ": " +
                            (r.found() ? "lv " + format_readable(o.metrics.lv_m) + " m, cost " + format_readable(r.cost)
                                       : plan_status_reason(r.status));
  // Expanded cells (when asked) take the place of the obstacle band: one translucent layer.
  write_terrain_paths_svg(path, map, title, {{o.planner, r.found() ? &r.path_cells : nullptr}}, shaded,
                          expanded ? "expanded" : (o.kind == RoughTerrainPlannerKind::OA ? "blocked" : "obstacles"), start,
                          goal);
}

void write_terrain_paths_svg(const std::string& path, const ElevationMap& map, const std::string& title,
                             const std::vector<TerrainPathLayer>& paths, const std::vector<Cell>& shaded_cells,
                             const std::string& shaded_label, Cell start, Cell goal) {
  viz::PictureOptions po;
  po.title = title;
  viz::MapPicture picture(map, po);
  if (!shaded_cells.empty()) picture.add_cells(shaded_cells, viz::parse_colour("orange"), 0.3, shaded_label);
  const GridGeometry& g = map.geometry();
  const double widths[] = {3.0, 2.5, 2.0};
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (!paths[i].cells || paths[i].cells->empty()) continue;
    std::vector<Vec2> points;
    points.reserve(paths[i].cells->size());
    for (const Cell& c : *paths[i].cells) points.push_back(g.cell_center(c));
    viz::LineStyle line;
    line.colour = viz::categorical_colour(i);
    line.width_px = widths[std::min<std::size_t>(i, 2)];
    picture.add_polyline(std::move(points), line, paths[i].label);
  }
  viz::MarkerStyle marker;
  marker.radius_px = 4.5;
  marker.fill = viz::categorical_colour(4);
  if (g.contains(start)) picture.add_points({g.cell_center(start)}, marker, "start");
  marker.fill = viz::categorical_colour(5);
  if (g.contains(goal)) picture.add_points({g.cell_center(goal)}, marker, "goal");
  picture.write_svg(path);
}

void write_attitude_profile_svg(const std::string& path, const std::string& title, AttitudeAngle angle,
                                const std::vector<std::pair<std::string, const std::vector<AttitudeSample>*>>& series) {
  const char* name = angle == AttitudeAngle::Roll ? "roll" : angle == AttitudeAngle::Pitch ? "pitch" : "tilt";
  viz::PlotOptions po;
  po.title = title;
  po.x_label = "distance along the path [m]";
  po.y_label = std::string(name) + " [deg]";
  viz::LinePlot plot(po);
  for (std::size_t i = 0; i < series.size(); ++i) {
    if (!series[i].second || series[i].second->empty()) continue;
    std::vector<Vec2> points;
    for (const AttitudeSample& s : *series[i].second) {
      const double v = angle == AttitudeAngle::Roll ? s.attitude.roll
                       : angle == AttitudeAngle::Pitch ? s.attitude.pitch
                                                       : s.attitude.tilt;
      // Nodes without a valid attitude break the line (NaN is skipped by the plot).
      points.emplace_back(s.s_m, s.attitude.valid ? rad_to_deg(v) : std::nan(""));
    }
    viz::SeriesStyle style;
    style.colour = viz::categorical_colour(i);
    plot.add_series(std::move(points), style, series[i].first);
  }
  plot.write_svg(path);
}

}  // namespace starnav
