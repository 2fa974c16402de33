#include "starnav/plan/plan_pipeline.hpp"

#include <chrono>

#include "starnav/core/error.hpp"
#include "starnav/plan/grid_graph.hpp"

namespace starnav {

PlanSmoothing parse_plan_smoothing(const std::string& text, const std::string& field) {
  if (text == "none") return PlanSmoothing::None;
  if (text == "los") return PlanSmoothing::LineOfSight;
  if (text == "gradient") return PlanSmoothing::Gradient;
  throw Error("expected none, los or gradient, got '" + one_line(text, 40) + "'", {}, 0, field);
}

GridPlannerOptions grid_planner_options(const PlanRequest& request) {
  GridPlannerOptions options = request.options;
  switch (request.smoothing) {
    case PlanSmoothing::PlannerDefault: break;
    case PlanSmoothing::None: options.ou2022.smoothing = PathSmoothing::None; break;
    case PlanSmoothing::LineOfSight:
    case PlanSmoothing::Gradient: options.ou2022.smoothing = PathSmoothing::LineOfSight; break;
  }
  return options;
}

PlanOutcome plan_on_grid(const OccupancyGrid& grid, Cell start, Cell goal, const PlanRequest& request) {
  const GridPlannerOptions options = grid_planner_options(request);
  const bool gradient = request.smoothing == PlanSmoothing::Gradient;
  if (gradient) validate_gradient_smoothing(request.gradient);

  PlanOutcome out;
  out.planner = make_grid_planner(request.planner, grid, options);
  out.result = out.planner->plan(start, goal, request.limits);
  const PlanResult& r = out.result;
  // The inflated map, once, when the smoother or the caller needs it. Its clearance is the
  // distance transform the metrics use (the original map's obstacles, as the planner sees them).
  if ((gradient && r.found()) || (request.keep_inflated && options.ou2022.inflation.hard()))
    out.inflated = inflate_obstacles(grid, options.thresholds, options.unknown_is_free, options.ou2022.inflation);
  const GridGeometry& geometry = grid.geometry();
  const ClearanceField clearance = out.inflated ? ClearanceField(geometry, out.inflated->clearance_m)
                                                : ClearanceField::of_grid(grid, options.thresholds, !options.unknown_is_free);
  if (gradient && r.found()) {
    const GridSearchMap blocked(grid.width(), grid.height(), out.inflated->blocked);
    const auto t0 = std::chrono::steady_clock::now();
    out.smoothed = smooth_path_gradient(r.path_world, blocked, geometry, &clearance, request.gradient);
    out.smoothing_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  out.metrics = compute_path_metrics(out.path(), &clearance);
  out.unsmoothed_metrics = compute_path_metrics(cell_centres(out.planner->unsmoothed_path(), geometry), &clearance);
  return out;
}

}  // namespace starnav
