#include "terrain_cli.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "starnav/core/error.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav::cli {

namespace {

using json = nlohmann::ordered_json;

bool uses_thresholds(RoughTerrainPlannerKind k) { return k != RoughTerrainPlannerKind::OA; }
bool uses_costs(RoughTerrainPlannerKind k) { return k == RoughTerrainPlannerKind::IA; }

// Five comma-separated finite numbers.
std::vector<double> parse_weights(const std::string& text) {
  std::vector<double> w;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    const std::string part = text.substr(begin, comma - begin);
    char* end = nullptr;
    errno = 0;
    const double v = part.empty() ? 0.0 : std::strtod(part.c_str(), &end);
    if (part.empty() || errno != 0 || end != part.c_str() + part.size() || !std::isfinite(v))
      throw Error("expected ws,we,wr,w1,w2 (five numbers), got '" + text + "'", {}, 0, "--weights");
    w.push_back(v);
    begin = comma + 1;
  }
  if (w.size() != 5) throw Error("expected ws,we,wr,w1,w2 (five numbers), got '" + text + "'", {}, 0, "--weights");
  return w;
}

}  // namespace

const CLI::Option* TerrainPlanFlags::first_given() const {
  for (const CLI::Option* o : {hy, ay, sy, weights_opt, admissible_opt, cost_per_metre_opt, robot_radius, unobserved_opt})
    if (o && o->count() > 0) return o;
  return nullptr;
}

void add_terrain_plan_flags(CLI::App* cmd, TerrainPlanFlags& f) {
  f.hy = cmd->add_option("--hy-m", f.hy_m, "elevation maps (aoea, ia): step threshold h_y, metres (default 0.05)");
  f.ay = cmd->add_option("--ay-rad", f.ay_rad, "elevation maps (aoea, ia): slope threshold a_y, radians (default 0.5)");
  f.sy = cmd->add_option("--sy-m2", f.sy_m2,
                         "elevation maps (aoea, ia): ruggedness threshold S_y (3x3 height variance), m^2 (default 0.02)");
  f.weights_opt = cmd->add_option("--weights", f.weights,
                                  "elevation maps (ia): ws,we,wr,w1,w2 (default 0.33,0.33,0.34,0.5,0.5; ws+we+wr = 1)");
  f.admissible_opt = cmd->add_flag("--admissible", f.admissible,
                                   "elevation maps (ia): H = w2 * distance (admissible, optimal) instead of the paper's "
                                   "H = distance (inadmissible, searched with reopening as its Algorithm 1)");
  f.cost_per_metre_opt = cmd->add_flag(
      "--cost-per-metre", f.cost_per_metre,
      "elevation maps (ia): charge g per metre (g * d / resolution) instead of per move, so costs do not depend on "
      "the resolution");
  f.robot_radius = cmd->add_option("--robot-radius-m", f.robot_radius_m,
                                   "elevation maps (aoea): obstacle expansion radius, metres (default 0.36)");
  f.unobserved_opt = cmd->add_option("--unobserved", f.unobserved,
                                     "elevation maps: unobserved cells are blocked (default), free_flat or unknown_cost");
}

RoughTerrainPlannerOptions terrain_planner_options(const TerrainPlanFlags& f,
                                                   const std::vector<RoughTerrainPlannerKind>& planners) {
  const bool thresholds = std::any_of(planners.begin(), planners.end(), uses_thresholds);
  const bool costs = std::any_of(planners.begin(), planners.end(), uses_costs);
  const bool aoea =
      std::find(planners.begin(), planners.end(), RoughTerrainPlannerKind::AOEA) != planners.end();
  auto refuse = [](const CLI::Option* o, const char* who) {
    if (o && o->count() > 0) throw Error(std::string("applies to ") + who + " only", {}, 0, o->get_name());
  };
  if (!thresholds) {
    refuse(f.hy, "--planner aoea and ia");
    refuse(f.ay, "--planner aoea and ia");
    refuse(f.sy, "--planner aoea and ia");
  }
  if (!costs) {
    refuse(f.weights_opt, "--planner ia");
    refuse(f.admissible_opt, "--planner ia");
    refuse(f.cost_per_metre_opt, "--planner ia");
  }
  if (!aoea) refuse(f.robot_radius, "--planner aoea");

  RoughTerrainPlannerOptions o;
  o.cost.h_y = f.hy_m;
  o.cost.a_y = f.ay_rad;
  o.cost.s_y = f.sy_m2;
  if (!f.weights.empty()) {
    const std::vector<double> w = parse_weights(f.weights);
    o.cost.w_s = w[0];
    o.cost.w_e = w[1];
    o.cost.w_r = w[2];
    o.cost.w1 = w[3];
    o.cost.w2 = w[4];
  }
  o.cost.cost_per_metre = f.cost_per_metre;
  o.heuristic = f.admissible ? LiuHeuristic::Admissible : LiuHeuristic::Paper;
  o.reopen = true;
  o.robot_radius_m = f.robot_radius_m;
  o.unobserved = parse_unobserved_policy(f.unobserved, "--unobserved");
  try {
    o.validate();
  } catch (const Error& e) {
    // Name the flag the user typed.
    const std::string& field = e.field();
    const std::string flag = field == "h_y"              ? "--hy-m"
                             : field == "a_y"            ? "--ay-rad"
                             : field == "s_y"            ? "--sy-m2"
                             : field == "robot_radius_m" ? "--robot-radius-m"
                                                         : "--weights";
    throw Error(e.message(), {}, 0, flag);
  }
  return o;
}

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

}  // namespace starnav::cli
