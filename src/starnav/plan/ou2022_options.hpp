#pragma once
// Options of the improved A* of Ou et al. 2022 (docs/papers/ou2022.md, docs/papers/ou2022.md): obstacle
// inflation (hard radius + graded cost band), line-of-sight removal of redundant nodes, steering
// cost turn_w (paper variant and exact variant) and the adaptive heuristic weight. Each feature is
// switchable on its own. They live in GridPlannerOptions::ou2022 (grid_planner.hpp); every field's
// default leaves a planner exactly as it was without these options.
//
// Which planner honours what (make_grid_planner):
//   ou2022          everything; unset fields take the paper's values (turn cost k_turn = 1,
//                   adaptive weight on, line-of-sight smoothing on, Manhattan heuristic).
//   astar           everything; unset fields are off (octile heuristic on 8-connected grids).
//   jps, jpsplus,   hard inflation and smoothing only. JPS prunes symmetric paths assuming uniform
//   other planners  move costs, so a graded band, turn costs or the adaptive weight are refused
//                   with an Error (field inflate_cost_radius, turn_cost, turn_exact or
//                   adaptive_weight), never silently ignored.
#include <optional>

namespace starnav {

// Obstacle inflation through the exact Euclidean distance transform (map/distance_transform.hpp).
// d = distance from a cell centre to the nearest obstacle cell centre (metres; obstacles are the
// cells the planner may not enter: occupied, and unknown unless unknown_is_free; the map border
// is not an obstacle).
//   hard:   d <= radius_m  ->  blocked (inclusive; 1e-9 relative tolerance absorbs the decimal
//           rounding of radius_m / resolution). The paper uses the robot's diameter.
//   graded: radius_m < d <= cost_radius_m  ->  every move entering the cell costs its length times
//              m(d) = 1 + cost_weight * exp(-cost_scale * (d - radius_m)),
//           and m = 1 beyond cost_radius_m. This is ROS costmap_2d's inflation cost
//           (253 - 1) * exp(-cost_scaling_factor * (d - inscribed_radius)) turned into a
//           multiplier: cost_scale is ROS's cost_scaling_factor (1/m), cost_radius_m is what ROS
//           calls inflation_radius, radius_m plays the inscribed radius, and the default weight 4
//           is what navfn makes of it (COST_NEUTRAL 50 + COST_FACTOR 0.8 * 252 ~ 5 x neutral at
//           the inscribed edge). Multipliers >= 1 keep every heuristic as admissible as before.
struct InflationOptions {
  double radius_m = 0.0;       // hard radius (0: no hard inflation)
  double cost_radius_m = 0.0;  // outer edge of the graded band (<= radius_m: no band)
  double cost_scale = 10.0;    // 1/m, decay of the multiplier over the band (ROS default 10)
  double cost_weight = 4.0;    // the multiplier at the hard edge is 1 + cost_weight

  bool hard() const { return radius_m > 0.0; }
  bool graded() const { return cost_radius_m > radius_m && cost_weight > 0.0; }
  bool any() const { return hard() || graded(); }
};

enum class PathSmoothing {
  None,
  // Paper Fig. 5: from each anchor keep the farthest later vertex in line of sight (supercover
  // test on the inflated map), so the path never crosses a blocked cell and never gets longer.
  LineOfSight,
};

struct Ou2022Options {
  InflationOptions inflation;
  // Steering cost: turn_w = k_turn * (delta / 45 deg) * resolution for a heading change delta of
  // 0, 45, 90, 135 or 180 deg (paper Eq. 26 with the paper's k = 10 on steps of 10 and 14 being
  // k_turn = 1). Unset: 1 for ou2022, 0 (off) otherwise. Must be >= 0 and finite.
  std::optional<double> turn_cost;
  // false: the paper's search state is the cell alone (the turn is measured against the parent's
  // incoming direction; not optimal for the turn-inclusive cost). true: states are (cell,
  // incoming direction), optimal for the turn-inclusive cost with an admissible heuristic.
  bool turn_exact = false;
  // f = g + (1 + d/D) * h (paper Eq. 27): d, D Euclidean distances from the node and from the
  // start to the goal. Inadmissible. Unset: on for ou2022, off otherwise.
  std::optional<bool> adaptive_weight;
  // Unset: LineOfSight for ou2022, None otherwise.
  std::optional<PathSmoothing> smoothing;
  // The robot's heading at the start (radians, in the grid's cell axes: 0 along +x cells, pi/2
  // along +y cells), so that the first move's turn is charged. Unset: the first move is free.
  std::optional<double> start_heading_rad;

  // Whether anything here changes the search itself (not only the map or the path afterwards).
  bool changes_search() const {
    return inflation.graded() || (turn_cost && *turn_cost != 0.0) || turn_exact || adaptive_weight.value_or(false);
  }
  // Whether any field differs from its default (the planner registry then checks and applies them).
  bool any() const {
    return inflation.radius_m != 0.0 || inflation.cost_radius_m != 0.0 || turn_cost.has_value() || turn_exact ||
           adaptive_weight.has_value() || smoothing.has_value() || start_heading_rad.has_value();
  }
};

}  // namespace starnav
