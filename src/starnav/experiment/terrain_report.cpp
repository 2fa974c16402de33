#include "starnav/experiment/terrain_report.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

using json = nlohmann::ordered_json;

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
