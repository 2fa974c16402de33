#pragma once
// The local-controller role: at every control step, from the robot's pose and velocity, the
// local obstacle map, the robot's footprint and limits and the global path, a body twist
// (vx, vy, yaw rate in base_link) and a status. The path follower of Li et al. 2019 is one;
// a DWA controller is another. A controller is built by name from the component registry
// (registry/components.hpp) with its declared parameters; it knows nothing of the simulator.
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/plane_fit.hpp"
#include "starnav/map/footprint_checker.hpp"
#include "starnav/map/obstacle_distance_field.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/robot/robot_model.hpp"

namespace starnav {

enum class ControlStatus : std::uint8_t {
  Idle,        // no path: zero twist
  Tracking,    // moving (or turning) toward the path's end
  Arrived,     // at the path's end: zero twist until a new path is set
  CannotReach, // the path's end cannot be reached from here (stopped): the navigator replans
  Blocked,     // no command is safe (e.g. every DWA sample collides): zero twist, recovery needed
  AtCusp,      // at a cusp of a path with reversals (or stopped short of it): the navigator plans the
               // rest from the pose the robot reached
};
const char* control_status_name(ControlStatus s);  // "idle", "tracking", "arrived", "cannot_reach", "blocked"

// The robot as a controller sees it: its outline in base_link (core/plane_fit.hpp's Footprint)
// and its limits.
// A speed limit (a costmap layer's zone, docs/navigation.md "Speed-limit zones") lowers all three
// translation limits for the controller's step; every controller keeps its command within them.
struct VelocityLimits {
  double max_vx_mps = 0.5;
  double max_vy_mps = 0.0;  // 0: cannot translate sideways
  double max_yaw_rate_radps = 1.0;
  double max_speed_mps = std::numeric_limits<double>::infinity();  // of the translation |(vx, vy)|
};

// The robot of `config`: its body box and the speeds its wheels allow.
Footprint footprint_of(const RobotConfig& config);
// The same box as the footprint checks take it, centred where the body is in base_link (ahead of
// a car's rear axle).
FootprintModel body_footprint_model(const RobotConfig& config);
// The smallest turning radius of a robot that cannot turn on the spot (Ackermann: wheelbase /
// tan(max steer)); 0 for the others.
double min_turning_radius_of(const RobotConfig& config);
VelocityLimits velocity_limits_of(const RobotConfig& config);
// `limits` with every translation limit lowered to `max_speed_mps` (the yaw rate unchanged).
VelocityLimits with_speed_limit(VelocityLimits limits, double max_speed_mps);
// The factor in [0, 1] that brings the translation (vx, vy) of `twist` within the limits of
// `limits` (|vx| <= max_vx, |vy| <= max_vy, |(vx, vy)| <= max_speed), keeping its direction: 1 when
// it is within them already.
double translation_scale(const BodyTwist& twist, const VelocityLimits& limits);

struct ControlInput {
  double t_s = 0.0;
  Pose2 pose;                               // map frame (from the localizer)
  BodyTwist velocity;                       // current body twist (odometry or estimate)
  const OccupancyGrid* local_map = nullptr; // obstacles as sensed, not inflated (occupied cells); may be null
  const ObstacleDistanceField* clearance = nullptr; // the same obstacles' distance field, up to date (controllers that
                                             // check their footprint get it; they read it instead of
                                             // transforming local_map themselves)
  Footprint footprint;
  VelocityLimits limits;
  Vec2 goal = Vec2::Zero();
  std::optional<double> goal_yaw;           // rad (map frame), when the goal has a heading
  double goal_tolerance_m = 0.05;           // the navigator's goal check: arrived within this distance
  double goal_yaw_tolerance_rad = 0.05;     // and, with a goal heading, within this angle of it
  bool goal_xy_reached = false;             // the navigator's goal check has latched the position
                                            // (reached at low speed): only the heading remains
};

struct ControlOutput {
  BodyTwist twist;  // base_link
  ControlStatus status = ControlStatus::Idle;
};

// What a controller considered at one step, in terms every controller can fill and one picture
// writer can draw (harness/local_planning_pictures): the candidate motions it scored (sampling
// controllers: every rollout; others: none or the one it follows), the one it chose, named points
// (a look-ahead point, a local goal) and named scalar terms.
enum class CandidateStatus : std::uint8_t { Valid, Collides, Rejected };
struct ControlCandidate {
  BodyTwist twist;
  std::vector<Pose2> trajectory;  // the poses it would pass through, from the step's pose on (excluded)
  CandidateStatus status = CandidateStatus::Valid;
  double cost = 0.0;              // valid candidates: the controller's objective (lower is better)
};
struct ControlDiagnostics {
  double t_s = 0.0;
  Pose2 pose;                     // where the step was computed from
  ControlStatus status = ControlStatus::Idle;
  BodyTwist command;
  std::vector<ControlCandidate> candidates;
  int chosen = -1;                // index into candidates; -1: none chosen
  std::vector<std::pair<std::string, Vec2>> points;    // "local goal", "look-ahead", ...
  std::vector<std::pair<std::string, double>> terms;   // "cross_track_m", "margin_cut_m", ...
};

class LocalController {
 public:
  virtual ~LocalController() = default;
  virtual std::string_view name() const = 0;
  // A new global path (world x, y), starting near the robot. Throws Error (field "path") for an
  // empty path or a non-finite point.
  virtual void set_path(std::span<const Vec2> points) = 0;
  // A path of poses from a planner between poses, with per pose 1 when the motion leaving it
  // drives in reverse. A controller that cannot follow reversals takes the positions (this
  // default); one that can overrides it. Throws Error (field "path") as set_path, or when the
  // two spans differ in size.
  virtual void set_path_poses(std::span<const Pose2> poses, std::span<const std::uint8_t> reversing);
  virtual void clear() = 0;
  virtual bool has_path() const = 0;
  // The path being followed (for deviation metrics and pictures).
  virtual const std::vector<Vec2>& path() const = 0;
  // One control step. Deterministic: a function of the path, the parameters and the inputs.
  virtual ControlOutput compute(const ControlInput& input) = 0;
  // The grid path's vertices this controller wants: true when it cannot turn on the spot and
  // needs line-of-sight smoothed paths instead of 45-degree grid corners.
  virtual bool wants_smoothed_path() const { return false; }
  // Time between two compute() calls the controller is designed for (its command is held in
  // between); 0: every simulation step.
  virtual double control_period_s() const { return 0.0; }
  // A controller with several motion modes (the path follower's turn_then_drive, holonomic,
  // pure_pursuit): the one it runs; empty for the others.
  virtual std::string motion_mode() const { return {}; }
  // Keep what diagnostics() needs at every step (it may cost time: off by default).
  virtual void keep_diagnostics(bool /*on*/) {}
  // The last compute()'s diagnostics, when the controller keeps them; nothing otherwise.
  virtual std::optional<ControlDiagnostics> diagnostics() const { return std::nullopt; }
};

// What a controller is built from: the robot, the scenario file its settings came from, and the
// scenario's seed (a sampling controller's draws come from it).
struct LocalControllerContext {
  RobotConfig robot;
  std::string file;
  double map_resolution_m = 0.0;  // of the map it will read (0: not known yet): bounds its windows in cells
  std::uint64_t seed = 0;
};
using LocalControllerDef = ComponentDef<LocalController, LocalControllerContext>;

}  // namespace starnav
