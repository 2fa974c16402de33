#pragma once
// Hybrid-A* (Dolgov et al. 2010; Nav2's Smac Hybrid-A* planner): a search over (x, y, heading bin)
// for robots that cannot turn on the spot. Each state keeps its exact continuous pose; states are
// merged by their cell and heading bin. The successors of a pose are arcs of the minimum turning
// radius R (left, straight, right), driven forward and, for Reeds-Shepp, in reverse; the "diff"
// and "omni" models may also turn on the spot (omni also step sideways). Every motion is checked
// with the robot's footprint (a rectangle or a circle) at every collision step along it.
//
// Costs (Nav2's, in metres): a motion of length L entering a cell at clearance d costs
//     L * (1 + cost_penalty * c(d))      c(d) = 1 for d <= r_in, exp(-k (d - r_in)) up to the
//                                        inflation radius, 0 beyond (Nav2's normalised costmap cost)
// times non_straight_penalty for an arc (plus change_penalty when it turns the other way than the
// motion before), times reverse_penalty in reverse, plus cusp_penalty_m at each change between
// forward and reverse. Every factor is >= 1, so a path never costs less than its length.
//
// Heuristic: the larger of (a) the length of the shortest obstacle-free Reeds-Shepp (or Dubins)
// curve to the goal pose (plan/car_curves.hpp), or the straight-line distance for the models that
// turn on the spot, and (b) the 8-connected obstacle distance to the goal from a Dijkstra on the
// cells the robot's centre can occupy, divided by the octile/Euclidean ratio and less one cell
// diagonal (docs/planning.md says why each is a lower bound); that Dijkstra runs lazily, only as
// far as the search asks (an A* from the goal toward the start, resumed on demand), and the curve
// from the start is tried before any of it. A path reaches the goal pose exactly:
// the search ends with an analytic expansion (the obstacle-free curve from a state to the goal,
// footprint-checked), tried every N expansions with N shrinking near the goal as Nav2 does.
//
// The path found is then shortened by replacing stretches with the shortest curve between their
// end poses where that curve is free and cheaper (so the curvature stays within 1/R exactly), and
// sampled: every motion's ends are samples, with at most `path_step` between samples.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/map/clearance_window.hpp"
#include "starnav/map/footprint_checker.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/plan/global_planner.hpp"
#include "starnav/plan/plan_result.hpp"

namespace starnav {

enum class HybridMotionModel : std::uint8_t {
  Dubins,      // forward arcs and straights only
  ReedsShepp,  // forward and reverse
  Diff,        // Reeds-Shepp's motions plus turning on the spot (a differential drive)
  Omni,        // Diff's plus sideways steps (an omnidirectional base)
};
// "dubins", "reeds_shepp", "diff", "omni"
const char* hybrid_motion_model_name(HybridMotionModel m);

struct HybridAStarOptions {
  HybridMotionModel motion_model = HybridMotionModel::ReedsShepp;
  double minimum_turning_radius_m = 0.4;  // Nav2's default; a car sets its own
  int angle_bins = 72;
  // Nav2's penalties: non-straight >= 1 multiplies arcs, change adds to it on a change of turning
  // side, reverse >= 1 multiplies reverse motions; cusp adds metres per forward/reverse change.
  double non_straight_penalty = 1.2;
  double change_penalty = 0.0;
  double reverse_penalty = 2.0;
  double cusp_penalty_m = 0.0;
  double rotation_penalty_m_per_rad = 0.5;  // diff/omni: turning on the spot costs this per radian
  // Costmap costs: cost_penalty times Nav2's normalised inflation cost (cost_scaling_factor 1/m,
  // out to inflation_radius_m from the nearest obstacle).
  double cost_penalty = 2.0;
  double inflation_radius_m = 0.55;
  double cost_scaling_factor = 10.0;
  // Footprint: a rectangle when footprint_length_m > 0, else a circle; centred footprint_center_x_m
  // ahead of base_link. In navigation the robot's body box and turning radius unless set.
  double robot_radius_m = 0.25;
  double footprint_length_m = 0.0;
  double footprint_width_m = 0.0;
  double footprint_center_x_m = 0.0;  // the outline's centre ahead of base_link (a car's rear axle)
  double collision_step_m = 0.0;  // spacing of the footprint checks along a motion; 0: half a cell
  double path_step_m = 0.0;       // spacing of the output samples; 0: one cell
  // f = g + heuristic_weight * h: 1 keeps the heuristic admissible; above 1 the search is
  // weighted A* (much faster among obstacles, at some cost in path cost).
  double heuristic_weight = 1.0;
  double analytic_expansion_ratio = 3.5;
  double analytic_expansion_max_length_m = 3.0;  // 0: no limit
  std::uint64_t max_iterations = 1000000;
  // 0: no limit (Nav2: 5 s). A wall-clock limit makes the same query answer differently as the
  // machine's load changes; max_iterations bounds the search by expansions, the same on any machine.
  double max_planning_time_s = 0.0;
  bool smooth = true;
  // From the grid options of the context, not declared: unknown cells free or blocked.
  bool unknown_is_free = false;
  OccupancyThresholds thresholds;

  // Throws Error naming the key of a value out of range.
  void validate() const;
  FootprintModel footprint() const;
};

// The declared parameters (every field but the grid's).
const ParamTable<HybridAStarOptions>& hybrid_astar_params();

// One motion of a path: an arc (curvature +-1/R or a straight) of signed length (negative:
// reverse), a turn on the spot by `length` radians, or a sideways step of `length` metres (+ left).
struct HybridMotion {
  enum class Kind : std::uint8_t { Arc, Rotate, Sideways };
  Kind kind = Kind::Arc;
  Pose2 start;
  double curvature = 0.0;  // Arc: 1/m
  double length = 0.0;
  Pose2 pose_at(double t) const;  // t in [0, |length|]: metres along (radians for Rotate)
  Pose2 end() const { return pose_at(std::abs(length)); }
  bool reverse() const { return kind == Kind::Arc && length < 0.0; }
};

class HybridAStar {
 public:
  // Builds the footprint checker's distance field and the costs over all of `grid` (whose cells
  // outside count as obstacles). Throws Error for bad options or a map too large for one window.
  HybridAStar(const OccupancyGrid& grid, const HybridAStarOptions& options);
  ~HybridAStar();
  HybridAStar(const HybridAStar&) = delete;
  HybridAStar& operator=(const HybridAStar&) = delete;

  // A path from `start` to `goal` (map frame; headings in radians). The result's path_poses and
  // path_reversing hold the samples; path_world their positions, path_cells the cells they pass.
  PlanResult plan(const Pose2& start, const Pose2& goal, const SearchLimits& limits = {});

  // The motions of the last path found, after smoothing (tests).
  const std::vector<HybridMotion>& motions() const { return motions_; }
  // The planner's footprint test (the map's cells and everything outside it are obstacles).
  bool collides(const Pose2& pose) const;
  // The heuristic toward the last plan's goal at `pose` (tests; plan() must have run).
  double heuristic(const Pose2& pose) const;
  // Parts of the heuristic: the obstacle-free curve length, the obstacle distance bound.
  double curve_heuristic(const Pose2& pose) const;
  double obstacle_heuristic(const Pose2& pose) const;
  // The length of the search's motions (m) and their heading change in bins.
  double primitive_length() const { return step_; }
  int primitive_turn_bins() const { return turn_bins_; }
  const HybridAStarOptions& options() const { return options_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  HybridAStarOptions options_;
  double step_ = 0.0;
  int turn_bins_ = 1;
  std::vector<HybridMotion> motions_;
};

// Samples of a list of motions: each motion from its start every `step` metres (radians for a
// turn on the spot) plus its end; reversing[i] is 1 when the motion leaving sample i (for the last
// sample, arriving at it) drives in reverse.
void sample_hybrid_motions(const std::vector<HybridMotion>& motions, double step, std::vector<Pose2>& poses,
                           std::vector<std::uint8_t>& reversing);

// The registry entry of the planner (`hybrid_astar`).
GlobalPlannerDef hybrid_astar_global_planner();

}  // namespace starnav
