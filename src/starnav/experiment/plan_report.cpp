#include "starnav/experiment/plan_report.hpp"

#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav {

namespace {

// The path metrics as JSON (non-finite clearances, e.g. on a map without obstacles, are null).
nlohmann::ordered_json metrics_json(const PathMetrics& m) {
  nlohmann::ordered_json j;
  j["length"] = m.length;
  j["vertices"] = m.vertices;
  j["turning_points"] = m.turning_points;
  j["turn_total_rad"] = m.turn_total_rad;
  j["turn_max_rad"] = m.turn_max_rad;
  j["clearance_min"] = std::isfinite(m.clearance_min) ? nlohmann::ordered_json(m.clearance_min) : nullptr;
  j["clearance_mean"] = std::isfinite(m.clearance_mean) ? nlohmann::ordered_json(m.clearance_mean) : nullptr;
  j["smoothness"] = m.smoothness;
  return j;
}

}  // namespace

std::string plan_json(const PlanOutcome& outcome, const PlanReportContext& c) {
  const GridPlanner* planner = outcome.planner.get();
  const PlanResult& r = outcome.result;
  const std::optional<GradientSmoothingResult>& smoothed = outcome.smoothed;
  const double smoothing_ms = outcome.smoothing_ms;
  const PathMetrics& metrics = outcome.metrics;
  const std::vector<Cell>& unsmoothed = planner->unsmoothed_path();
  const PathMetrics& unsmoothed_metrics = outcome.unsmoothed_metrics;
  const bool index_grid = c.index_grid;
  // Points in the map's units: cells on index grids, metres (cell centres, any-angle vertices)
  // on metric maps.
  nlohmann::ordered_json path = nlohmann::ordered_json::array(), path_cells = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.path_cells.size(); ++i) {
    path_cells.push_back({r.path_cells[i].x, r.path_cells[i].y});
    if (index_grid) path.push_back({r.path_cells[i].x, r.path_cells[i].y});
    else path.push_back({json_coordinate(r.path_world[i].x()), json_coordinate(r.path_world[i].y())});
  }
  // Smoothed points in the map's units; on index grids in cells, a cell's centre at its indices.
  auto map_units = [&](const Vec2& w) { return index_grid ? Vec2(w - Vec2(0.5, 0.5)) : w; };
  nlohmann::ordered_json smoothed_path = nlohmann::ordered_json::array();
  if (smoothed)
    for (const Vec2& w : smoothed->points) smoothed_path.push_back({json_coordinate(map_units(w).x()), json_coordinate(map_units(w).y())});

  nlohmann::ordered_json j;
  j["planner"] = std::string(planner->name());
  j["admissible"] = planner->admissible();
  j["found"] = r.found();
  if (!r.found()) j["reason"] = plan_status_reason(r.status);
  j["cost"] = r.found() ? nlohmann::ordered_json(r.cost) : nlohmann::ordered_json(nullptr);
  j["length"] = r.found() ? nlohmann::ordered_json(r.length) : nlohmann::ordered_json(nullptr);
  j["units"] = index_grid ? "cells" : "m";
  j["expanded"] = r.expanded;
  j["generated"] = r.generated;
  j["path"] = path;
  j["path_cells"] = path_cells;
  if (smoothed) {
    j["smoothed_path"] = smoothed_path;
    j["smoothing"] = {{"method", "gradient"},
                      {"iterations", smoothed->iterations},
                      {"energy_input", smoothed->energy_input},
                      {"energy_output", smoothed->energy_output},
                      {"time_ms", smoothing_ms}};
  }
  if (r.found()) {
    j["metrics"] = metrics_json(metrics);
    if (!unsmoothed.empty()) j["metrics_before_smoothing"] = metrics_json(unsmoothed_metrics);
  }
  if (c.expanded) {
    nlohmann::ordered_json cells = nlohmann::ordered_json::array();
    for (const Cell& c : planner->trace()) cells.push_back({c.x, c.y});
    j["expanded_cells"] = cells;
  }
  j["time_ms"] = r.time_ms;
  return j.dump() + "\n";
}

std::string plan_text(const PlanOutcome& outcome, const PlanReportContext& c) {
  const GridPlanner* planner = outcome.planner.get();
  const PlanResult& r = outcome.result;
  const std::optional<GradientSmoothingResult>& smoothed = outcome.smoothed;
  const PathMetrics& metrics = outcome.metrics;
  const std::vector<Cell>& unsmoothed = planner->unsmoothed_path();
  const PathMetrics& unsmoothed_metrics = outcome.unsmoothed_metrics;
  const bool index_grid = c.index_grid;
  std::ostringstream out;
  const char* unit = index_grid ? "cells" : "m";
  out << "planner:    " << planner->name() << (planner->admissible() ? "" : " (inadmissible)") << "\n";
  if (r.found()) {
    out << "found:      yes, " << r.path_cells.size() << " points\n";
    out << "cost:       " << format_readable(r.cost) << "\n";
    out << "length:     " << format_readable(r.length) << " " << unit << "\n";
    if (smoothed)
      out << "gradient:   " << smoothed->points.size() << " points, " << format_readable(metrics.length) << " " << unit
                << " long, energy " << format_readable(smoothed->energy_input) << " -> " << format_readable(smoothed->energy_output)
                << " in " << smoothed->iterations << " sweeps\n";
    if (!unsmoothed.empty())
      out << "smoothing:  " << unsmoothed_metrics.vertices << " -> " << metrics.vertices << " vertices, "
                << unsmoothed_metrics.turning_points << " -> " << metrics.turning_points << " turning points\n";
    else out << "turns:      " << metrics.turning_points << " turning points\n";
    out << "turning:    " << format_readable(metrics.turn_total_rad) << " rad total, " << format_readable(metrics.turn_max_rad)
              << " rad max\n";
    out << "clearance:  " << format_readable(metrics.clearance_min) << " min, " << format_readable(metrics.clearance_mean)
              << " mean (" << unit << ")\n";
  } else {
    out << "found:      no (" << plan_status_reason(r.status) << ")\n";
  }
  out << "expanded:   " << r.expanded << "\ngenerated:  " << r.generated << "\n";
  out << "time:       " << format_readable(r.time_ms) << " ms\n";
  return out.str();
}

std::string plan_path_csv(const PlanOutcome& outcome, const PlanReportContext& c) {
  const PlanResult& r = outcome.result;
  const std::optional<GradientSmoothingResult>& smoothed = outcome.smoothed;
  const bool index_grid = c.index_grid;
  // Smoothed points in the map's units; on index grids in cells, a cell's centre at its indices.
  auto map_units = [&](const Vec2& w) { return index_grid ? Vec2(w - Vec2(0.5, 0.5)) : w; };
  std::ostringstream out;
  out << std::setprecision(10);
  if (smoothed) {
    out << (index_grid ? "x_cell,y_cell\n" : "x_m,y_m\n");
    for (const Vec2& w : smoothed->points) out << map_units(w).x() << "," << map_units(w).y() << "\n";
  } else if (index_grid) {
    out << "x_cell,y_cell\n";
    for (const Cell& c : r.path_cells) out << c.x << "," << c.y << "\n";
  } else {
    out << "x_m,y_m,ix,iy\n";
    for (std::size_t i = 0; i < r.path_cells.size(); ++i)
      out << r.path_world[i].x() << "," << r.path_world[i].y() << "," << r.path_cells[i].x << ","
          << r.path_cells[i].y << "\n";
  }
  return out.str();
}

void write_plan_picture(const PlanOutcome& outcome, const PlanReportContext& c, const GridPlannerOptions& options,
                        const std::string& path) {
  const GridPlanner* planner = outcome.planner.get();
  const PlanResult& r = outcome.result;
  const std::optional<InflatedMap>& inflated = outcome.inflated;
  const std::optional<GradientSmoothingResult>& smoothed = outcome.smoothed;
  const std::vector<Cell>& unsmoothed = planner->unsmoothed_path();
  const bool index_grid = c.index_grid;
  const GridGeometry& geometry = c.grid->geometry();
  const Cell start = c.start, goal = c.goal;
  // The map, the expanded cells (--expanded) and the path; world coordinates (cell centres
  // on index grids).
  viz::PictureOptions picture_options;
  picture_options.title =
      std::string(planner->name()) + ": " + (r.found() ? "cost " + format_readable(r.cost) : plan_status_reason(r.status));
  viz::MapPicture picture(*c.grid, picture_options);
  if (options.ou2022.inflation.hard()) {
    // The cells blocked by hard inflation alone.
    std::vector<Cell> cells;
    for (std::size_t i = 0; i < inflated->blocked.size(); ++i)
      if (inflated->blocked[i] && inflated->clearance_m[i] > 0.0) cells.push_back(geometry.cell_of_index(i));
    picture.add_cells(cells, viz::parse_colour("orange"), 0.35, "inflation");
  }
  if (c.expanded) picture.add_cells(planner->trace(), viz::parse_colour("sky"), 0.45, "expanded");
  auto point_of = [&](const Cell& c) { return index_grid ? Vec2(c.x + 0.5, c.y + 0.5) : geometry.cell_center(c); };
  if (r.found() && !unsmoothed.empty()) {
    std::vector<Vec2> points;
    for (const Cell& c : unsmoothed) points.push_back(point_of(c));
    viz::LineStyle line;
    line.colour = viz::categorical_colour(0);
    line.width_px = 1.5;
    line.dashed = true;
    picture.add_polyline(points, line, "before smoothing");
  }
  if (r.found()) {
    std::vector<Vec2> points;
    for (std::size_t i = 0; i < r.path_cells.size(); ++i)
      points.push_back(index_grid ? point_of(r.path_cells[i]) : r.path_world[i]);
    viz::LineStyle line;
    line.colour = viz::categorical_colour(0);
    line.width_px = smoothed ? 1.2 : 2.5;
    picture.add_polyline(points, line, smoothed ? "line of sight" : "path");
    if (smoothed) {
      line.colour = viz::categorical_colour(3);
      line.width_px = 2.5;
      picture.add_polyline(smoothed->points, line, "path (gradient smoothing)");
    }
  }
  viz::MarkerStyle marker;
  marker.radius_px = 4.5;
  marker.fill = viz::categorical_colour(2);
  if (geometry.contains(start)) picture.add_points({point_of(start)}, marker, "start");
  marker.fill = viz::categorical_colour(1);
  if (geometry.contains(goal)) picture.add_points({point_of(goal)}, marker, "goal");
  picture.write_svg(path);
}

namespace {

struct PoseRunStats {
  std::size_t cusps = 0;
  double reverse_length = 0.0;
};

PoseRunStats pose_run_stats(const PlanResult& r) {
  PoseRunStats s;
  for (std::size_t i = 0; i + 1 < r.path_poses.size(); ++i) {
    if (i > 0 && r.path_reversing[i] != r.path_reversing[i - 1]) ++s.cusps;
    if (r.path_reversing[i])
      s.reverse_length += std::hypot(r.path_poses[i + 1].x - r.path_poses[i].x, r.path_poses[i + 1].y - r.path_poses[i].y);
  }
  return s;
}

}  // namespace

std::string pose_plan_json(const std::string& planner, const PlanResult& r) {
  const PoseRunStats stats = pose_run_stats(r);
  nlohmann::ordered_json path = nlohmann::ordered_json::array(), reversing = nlohmann::ordered_json::array(),
                         cells = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.path_poses.size(); ++i) {
    const Pose2& p = r.path_poses[i];
    path.push_back({json_coordinate(p.x), json_coordinate(p.y), json_coordinate(p.yaw)});
    reversing.push_back(static_cast<int>(r.path_reversing[i]));
  }
  for (const Cell& c : r.path_cells) cells.push_back({c.x, c.y});
  nlohmann::ordered_json j;
  j["planner"] = planner;
  j["found"] = r.found();
  if (!r.found()) j["reason"] = plan_status_reason(r.status);
  j["cost"] = r.found() ? nlohmann::ordered_json(r.cost) : nlohmann::ordered_json(nullptr);
  j["length"] = r.found() ? nlohmann::ordered_json(r.length) : nlohmann::ordered_json(nullptr);
  j["units"] = "m";
  j["expanded"] = r.expanded;
  j["generated"] = r.generated;
  j["cusps"] = stats.cusps;
  j["reverse_length"] = json_coordinate(stats.reverse_length);
  j["path"] = path;
  j["reversing"] = reversing;
  j["path_cells"] = cells;
  j["time_ms"] = r.time_ms;
  return j.dump() + "\n";
}

std::string pose_plan_text(const std::string& planner, const PlanResult& r) {
  std::ostringstream out;
  out << "planner:    " << planner << "\n";
  if (r.found()) {
    const PoseRunStats stats = pose_run_stats(r);
    out << "found:      yes, " << r.path_poses.size() << " poses\n";
    out << "cost:       " << format_readable(r.cost) << "\n";
    out << "length:     " << format_readable(r.length) << " m (" << format_readable(stats.reverse_length)
        << " m in reverse, " << stats.cusps << " cusps)\n";
  } else {
    out << "found:      no (" << plan_status_reason(r.status) << ")\n";
  }
  out << "expanded:   " << r.expanded << "\ngenerated:  " << r.generated << "\n";
  out << "time:       " << format_readable(r.time_ms) << " ms\n";
  return out.str();
}

std::string pose_plan_csv(const PlanResult& r) {
  std::ostringstream out;
  out << std::setprecision(10) << "x_m,y_m,yaw_rad,reverse\n";
  for (std::size_t i = 0; i < r.path_poses.size(); ++i)
    out << r.path_poses[i].x << "," << r.path_poses[i].y << "," << r.path_poses[i].yaw << ","
        << static_cast<int>(r.path_reversing[i]) << "\n";
  return out.str();
}

}  // namespace starnav
