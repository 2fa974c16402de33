#pragma once
// The query-level interface of every planner on occupancy grids, used by the CLI, the
// benchmarks and (later) the navigation stack. Virtual dispatch happens once per query; inside a
// search everything is templated (see search_core.hpp), so the interface costs nothing per node.
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/ou2022_options.hpp"
#include "starnav/plan/plan_result.hpp"

namespace starnav {

// A cell whose occupancy changed, with its new value (incremental planners, map updates).
struct CellChange {
  Cell cell;
  std::int8_t occupancy = kOccupiedOccupancy;  // new value, -1..100 (classified with the thresholds)
};

struct GridPlannerOptions {
  int connectivity = 8;           // 4 or 8 (8: no corner cutting, conventions.md)
  bool unknown_is_free = false;   // optimistic planning in unknown space
  OccupancyThresholds thresholds;
  double weight = 1.0;            // weighted A*: f = g + w*h, w >= 1
  std::string heuristic;          // "" = the planner's default; "octile", "manhattan", "euclidean", "zero"
  bool record_trace = false;      // keep the expanded cells (for pictures)
  Ou2022Options ou2022;           // inflation, smoothing, steering cost, adaptive weight (docs/papers/ou2022.md)
};

class GridPlanner {
 public:
  virtual ~GridPlanner() = default;
  virtual std::string_view name() const = 0;
  // False when the returned cost may exceed the optimum (weighted A*, inadmissible heuristics).
  virtual bool admissible() const = 0;
  // True for planners whose heuristic takes options.weight (weighted A*).
  virtual bool takes_weight() const { return false; }
  virtual PlanResult plan(Cell start, Cell goal, const SearchLimits& limits = {}) = 0;
  // Per-map preprocessing time (e.g. JPS+ jump tables), not counted in any query's time.
  virtual double preprocess_ms() const { return 0.0; }
  // Cells expanded by the last query when options.record_trace was set.
  virtual const std::vector<Cell>& trace() const {
    static const std::vector<Cell> empty;
    return empty;
  }
  // Incremental planners (D* Lite) keep their search between queries: after a first plan(),
  // replan() takes the cells whose occupancy changed since (with their new values) and the
  // robot's new start cell, and repairs the search toward the same goal.
  virtual bool incremental() const { return false; }
  virtual PlanResult replan(Cell start, std::span<const CellChange> changed);
  // The grid path of the last query before line-of-sight smoothing (empty when the planner did
  // not smooth it); path_cells of the result is then the smoothed path.
  virtual const std::vector<Cell>& unsmoothed_path() const {
    static const std::vector<Cell> empty;
    return empty;
  }
};

// Names: dijkstra, astar, wastar, jps, jpsplus, thetastar, dstar_lite (alias dstarlite), ou2022 (see ou2022_options.hpp
// for which planner honours which of options.ou2022). Throws Error for an unknown
// name or options the planner cannot honour (e.g. jps with connectivity 4).
std::unique_ptr<GridPlanner> make_grid_planner(std::string_view name, const OccupancyGrid& grid,
                                               const GridPlannerOptions& options = {});
std::vector<std::string> grid_planner_names();

}  // namespace starnav
