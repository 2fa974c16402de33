#pragma once
// One planning query as `starnav plan` runs it, as one library call: a planner by name on an
// occupancy grid (with the Ou et al. 2022 features in its options), then, when asked, gradient
// smoothing of the path on the inflated map, and the path metrics measured with the clearance
// field the planner saw (the inflated map's when there is one, else the grid's own obstacles).
//
//   PlanRequest rq;
//   rq.planner = "astar";
//   rq.options.ou2022.inflation.radius_m = 0.3;
//   rq.smoothing = PlanSmoothing::Gradient;
//   const PlanOutcome out = plan_on_grid(grid, start, goal, rq);
//   if (out.result.found()) use(out.path(), out.metrics);
//
// The inflated map is computed once, only when the smoother needs it or the caller keeps it
// (pictures); its clearance is then the field of the metrics too (one distance transform).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/gradient_smoothing.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/path_metrics.hpp"

namespace starnav {

enum class PlanSmoothing : std::uint8_t {
  PlannerDefault,  // whatever the planner does (ou2022: line of sight; the others: none)
  None,
  LineOfSight,     // Ou et al. 2022, Fig. 5
  Gradient,        // line of sight, then gradient smoothing on the inflated map
};
// "none", "los", "gradient" (the CLI's --smooth); Error naming `field` otherwise.
PlanSmoothing parse_plan_smoothing(const std::string& text, const std::string& field = "smooth");

struct PlanRequest {
  std::string planner = "astar";      // a registry name of an occupancy planner (grid_planner.hpp)
  GridPlannerOptions options;         // connectivity, unknown cells, thresholds, weight, heuristic, Ou 2022
  PlanSmoothing smoothing = PlanSmoothing::PlannerDefault;
  GradientSmoothingOptions gradient;  // PlanSmoothing::Gradient
  SearchLimits limits;
  bool keep_inflated = false;         // compute and keep the inflated map even when smoothing does not need it
};

struct PlanOutcome {
  std::unique_ptr<GridPlanner> planner;  // name(), admissible(), trace(), unsmoothed_path()
  PlanResult result;
  std::optional<InflatedMap> inflated;   // when smoothing needed it or keep_inflated (with hard inflation)
  std::optional<GradientSmoothingResult> smoothed;
  double smoothing_ms = 0.0;             // the gradient smoother alone (wall clock)
  PathMetrics metrics;                   // of path()
  PathMetrics unsmoothed_metrics;        // of the grid path before line-of-sight smoothing (when there was one)
  // The path reported: the smoothed points with gradient smoothing, else the planner's world path.
  const std::vector<Vec2>& path() const { return smoothed ? smoothed->points : result.path_world; }
};

// The planner's options of a request: request.options with the smoothing asked for (gradient
// smoothing runs line of sight first).
GridPlannerOptions grid_planner_options(const PlanRequest& request);

// Throws Error for an unknown planner or options it cannot honour (fields as make_grid_planner:
// "planner", "connectivity", "weight", "heuristic", "inflate", ...; "smooth_clearance" for bad
// gradient options). A query without a path is a result (result.found() false), not an error.
PlanOutcome plan_on_grid(const OccupancyGrid& grid, Cell start, Cell goal, const PlanRequest& request);

}  // namespace starnav
