#pragma once
// The navigation loop of Li et al. 2019 (docs/papers/li2019.md; docs/navigation.md, "The
// navigation loop"), independent of where scans and poses come from.
//
// Per sensor cycle (on_scan):
//   1. the scan updates the navigation map, a layered costmap (costmap/layered_costmap.hpp: by
//      default the prior map's obstacles and Li 2019's 3D nodes, expanded by the barrier distance);
//   2. the first cycle plans (cause "initial"); afterwards the navigator replans exactly when a
//      cell of the remaining path is now blocked for planning (cause "blocked"; the cells of an
//      escape prefix only when raw blocked), or when the follower reports it cannot reach the
//      path's end (cause "missed"); otherwise it keeps the path;
//   3. a plan starts at the robot's cell; when that cell lies inside the expansion band the path
//      first leaves the band by LayeredCostmap::escape_cell and is planned from there. Unknown
//      cells are free. No path (goal blocked, start raw blocked, goal enclosed) -> status NoPath,
//      reported once; the caller stops.
// Per control step (command): arrived when within goal_tolerance of the goal (status Arrived,
// zero twist); otherwise the PathFollower's twist for the current path. A layer of the map that
// limits the speed (speed-limit zones) lowers the controller's translation limits to the lowest
// limit over the robot's footprint at its pose, at every step the controller is asked.
//
// The parts play roles and are given to the navigator by whoever builds it (NavigatorParts; the
// harness builds them by name from the registry, a test may hand in its own): the global planner
// plans on the node map's occupancy (a planner with Capability::Incremental keeps one search and
// at a replan is given the cells whose occupancy changed since its last search, their values now);
// the local controller turns the path into twists; the goal checker says when the goal is reached;
// the progress checker when the robot is stuck; the recoveries run in order when it is (each
// moving the robot only while the map-level footprint check says its motion is clear). With
// compare_astar, every plan of an incremental planner also runs A* from scratch on the same map,
// from the robot to the goal and from the goal to the robot (expansions and costs recorded; the
// robot follows the incremental planner's path).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "starnav/control/goal_checker.hpp"
#include "starnav/control/local_controller.hpp"
#include "starnav/control/progress_checker.hpp"
#include "starnav/control/recovery.hpp"
#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/costmap/layered_costmap.hpp"
#include "starnav/plan/global_planner.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/robot/robot_model.hpp"
#include "starnav/sense/lidar.hpp"

namespace starnav {

// When the navigator starts its recoveries: the controller blocked this long (a new plan is asked
// for at once), or the progress checker says the robot is stuck; and how often per goal.
struct RecoveryConfig {
  double blocked_patience_s = 1.0;
  int max_recoveries = 8;  // per goal; then the navigation gives up (status NoPath)
  void validate() const;   // Error naming the field (prefix "recovery.")
};

// The parts of a navigator, each playing its role. The capabilities are the components' (the
// navigator asks them, never a name): a planner's Incremental, a controller's GoalHeading.
struct NavigatorParts {
  std::unique_ptr<GlobalPlanner> planner;
  Capabilities planner_capabilities;
  std::unique_ptr<LocalController> controller;
  Capabilities controller_capabilities;
  std::unique_ptr<GoalChecker> goal_checker;
  std::unique_ptr<ProgressChecker> progress_checker;
  std::vector<std::unique_ptr<Recovery>> recoveries;  // run in order; none: the robot never recovers
  std::vector<std::unique_ptr<CostmapLayer>> layers;  // the navigation map's, in order (built on config.geometry)
};

struct NavigatorConfig {
  GridGeometry geometry;  // the map's grid (world-aligned, y up)
  NodeMapParams map;
  std::vector<std::uint8_t> prior_obstacles;  // obstacles known before the run (2D map mode; the static_map layer's), empty: none
  bool compare_astar = false;     // incremental planners: also A* from scratch at every plan
  double goal_tolerance_m = 0.15;
  double goal_yaw_tolerance_rad = 0.08726646259971647;  // 5 deg: with a goal heading, arrived within it
  double no_return_clear_m = 0.0;
  double no_path_retry_s = 0.0;  // > 0: no path keeps the robot waiting and planning this long before giving up
  RecoveryConfig recovery;
  std::vector<std::string> warnings;  // from whoever built the configuration; Navigator::warnings() repeats them
  void validate() const;  // Error naming the field
};

enum class NavStatus : std::uint8_t { Waiting, Navigating, Arrived, NoPath };
const char* nav_status_name(NavStatus s);  // "waiting", "navigating", "arrived", "no_path"

// One plan (P1, P2, ...).
struct NavPlan {
  int id = 0;                  // 1-based
  double t_s = 0.0;
  std::string cause;           // initial | blocked | missed | controller_blocked | recovery
  std::string status;          // plan_status_reason of the search ("found", "no_path", ...)
  std::uint64_t expanded = 0;  // the planner's search (D* Lite: the repair)
  double cost_m = 0.0;         // path cost on the grid, metres (escape prefix excluded)
  double time_ms = 0.0;        // wall time of the search (not deterministic)
  bool compared = false;       // A* from scratch ran too (compare_astar)
  std::uint64_t astar_expanded = 0;
  double astar_cost_m = 0.0;
  std::string astar_status;
  // compare_astar: A* from scratch from the goal to the robot, the direction D* Lite searches in;
  // separates what D* Lite's repair saves from what its search direction costs.
  std::uint64_t astar_backward_expanded = 0;
  double astar_backward_cost_m = 0.0;
  std::string astar_backward_status;
  Pose2 from;                       // the robot's pose when it planned
  std::size_t escape_cells = 0;     // cells of the escape prefix (0: the start was outside the band)
  std::vector<Cell> cells;          // robot cell .. escape cell .. goal cell
  std::vector<Vec2> points;         // what the follower got: robot position, turning points, goal
  // A planner between poses: the path's poses and, per pose, 1 when the motion leaving it drives
  // in reverse (what the controller got); empty for the grid planners.
  std::vector<Pose2> poses;
  std::vector<std::uint8_t> reversing;
};

// Something the navigator did besides planning (recoveries, giving up).
struct NavEvent {
  double t_s = 0.0;
  std::string kind;    // recovery, stuck, no_path_wait, speed_limit
  std::string detail;  // controller_blocked | no_progress; rotate | back_up | replan; the limit in m/s or "none"
};

// What one sensor cycle did.
struct NavCycle {
  double t_s = 0.0;
  CostmapUpdate update;
  bool planned = false;
  std::string cause;  // when planned
};

class Navigator {
 public:
  // Takes the parts (each must be given; recoveries may be none). Throws Error naming the field for
  // a bad configuration, a planner that needs an elevation map, a goal outside the map or a goal
  // heading the controller cannot turn to.
  Navigator(const NavigatorConfig& config, const RobotConfig& robot, NavigatorParts parts, const Vec2& goal,
            std::optional<double> goal_yaw = std::nullopt);
  // A new goal: navigation starts again (status Waiting; the next cycle plans, cause "initial").
  void set_goal(const Vec2& goal, std::optional<double> goal_yaw = std::nullopt);
  ~Navigator();
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  // Called after every plan (tests compare planners here).
  std::function<void(const Navigator&, const NavPlan&)> on_plan;

  // One sensor cycle at time t with the robot's pose (ground truth or estimate).
  NavCycle on_scan(const LidarScan& scan, const Pose2& pose, double t);
  // A scan of another LiDAR (a rear one): into the map only; the next cycle plans with it.
  CostmapUpdate add_scan(const LidarScan& scan);
  // The same with a scan given as sensor origin and world points (tests, other sensors).
  NavCycle on_points(const Vec3& sensor_origin, std::span<const Vec3> points, const Pose2& pose, double t);
  // One control step at the localizer's pose, with the robot's current body twist. A controller
  // with a control period is asked at that period; its command is held in between. Arrived when
  // within goal_tolerance_m of the goal and, with a goal heading, within goal_yaw_tolerance_rad;
  // the position, once reached, stays reached while the robot turns (a latching goal check).
  BodyTwist command(const Pose2& pose, double t, const BodyTwist& velocity = {});
  // Another source commands the robot at t (a manual command, a bumper stop): the navigator's
  // timers (progress, blocked) restart and its next command() asks the controller afresh.
  void hold(double t);

  NavStatus status() const { return status_; }
  const std::string& no_path_reason() const { return no_path_reason_; }
  double arrival_time_s() const { return arrival_t_; }
  const LayeredCostmap& map() const { return map_; }
  const NavigatorConfig& config() const { return config_; }
  const LocalController& controller() const { return *controller_; }
  LocalController& controller() { return *controller_; }
  const GlobalPlanner& planner() const { return *planner_; }
  const GoalChecker& goal_checker() const { return *goal_checker_; }
  const Capabilities& controller_capabilities() const { return controller_capabilities_; }
  // What whoever built the configuration warned about (deprecated names, ignored sections).
  const std::vector<std::string>& warnings() const { return warnings_; }
  const Vec2& goal() const { return goal_; }
  const std::optional<double>& goal_yaw() const { return goal_yaw_; }
  const std::vector<NavEvent>& events() const { return events_; }
  // The controller's status at its last compute().
  ControlStatus control_status() const { return control_status_; }
  // The speed limit (m/s) the map's layers set at the robot's footprint at the controller's last
  // compute(); nothing when none did. Each change is an event ("speed_limit").
  const std::optional<double>& speed_limit() const { return speed_limit_; }
  // The lowest speed limit the map's layers set on the footprint of a robot at `pose`.
  std::optional<double> speed_limit_at(const Pose2& pose) const;
  const std::vector<NavPlan>& plans() const { return plans_; }
  // The index of the remaining path's first cell in plans().back().cells.
  std::size_t progress() const { return progress_; }
  // True when a cell of the current plan's remaining path is blocked (the replan test).
  bool remaining_path_blocked() const;
  // Distance from `p` to the path being followed (0 without one).
  double distance_to_path(const Vec2& p) const;

 private:
  NavCycle after_update(CostmapUpdate update, const Pose2& pose, double t);
  void note_changes(const CostmapUpdate& update);  // cells an incremental planner repairs at the next plan
  // Recovery: starts the recoveries (false when the navigation gives up), and the twist of the
  // running one.
  bool start_recovery(const Pose2& pose, double t, const std::string& why);
  std::optional<BodyTwist> recovery_twist(const Pose2& pose, double t);
  RecoveryInput recovery_input(const Pose2& pose, double t) const;
  void plan(const Pose2& pose, double t, const std::string& cause);
  void advance_progress(const Vec2& p);
  std::vector<Vec2> follower_points(const std::vector<Cell>& cells, const Vec2& robot) const;

  NavigatorConfig config_;
  Vec2 goal_;
  Cell goal_cell_{};
  LayeredCostmap map_;
  std::unique_ptr<GlobalPlanner> planner_;
  std::unique_ptr<LocalController> controller_;
  std::unique_ptr<GoalChecker> goal_checker_;
  std::unique_ptr<ProgressChecker> progress_checker_;
  std::vector<std::unique_ptr<Recovery>> recoveries_list_;
  Capabilities controller_capabilities_;
  std::vector<std::string> warnings_;
  bool planner_checks_footprint_ = false;
  bool incremental_ = false;
  Footprint footprint_;
  std::unique_ptr<MotionCheck> motion_check_;  // the footprint against the raw obstacles
  VelocityLimits limits_;
  std::vector<CellChange> pending_;        // cells changed since the incremental planner's last search
  std::vector<std::uint8_t> pending_mark_;  // 1 = in pending_
  std::vector<NavPlan> plans_;
  std::size_t progress_ = 0;
  std::string replan_cause_;  // a plan asked for by the controller or a recovery ("" none)
  std::optional<double> goal_yaw_;
  std::vector<NavEvent> events_;
  ControlStatus control_status_ = ControlStatus::Idle;
  std::optional<double> speed_limit_;
  BodyTwist held_;
  double next_control_t_ = -1.0;
  // Recovery state: the index of the running recovery (none: size of the list).
  std::size_t recovery_ = 0;
  double blocked_since_ = -1.0;
  int recoveries_ = 0;
  double no_path_since_ = -1.0;  // first failed plan of the current wait
  NavStatus status_ = NavStatus::Waiting;
  std::string no_path_reason_;
  double arrival_t_ = -1.0;
};

}  // namespace starnav
