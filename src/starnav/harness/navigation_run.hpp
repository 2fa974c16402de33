#pragma once
// A navigation scenario run: the simulator drives the localization chain (wheel odometry from the
// encoders, the localizer fed by odometry, IMU, scans and, in simulation, ground truth) and a
// Navigator (map, planner, controller) through Simulation's sensor feeds; the navigator reads its
// pose from the localizer. The recorder writes what the run did (docs/navigation.md, "Running
// navigation scenarios").
//
//   ScenarioSpec spec = load_scenario("scenarios/e4_dynamic_dead_end.yaml");
//   NavigationRun run(spec);
//   run.run();
//   write_navigation_records(run, "out/e4");
//
// The run ends at the goal, when no path exists, or at sim.duration_s (a timeout: success false).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "starnav/harness/command_arbiter.hpp"
#include "starnav/harness/local_planning_pictures.hpp"
#include "starnav/harness/localization_chain.hpp"
#include "starnav/harness/run_record.hpp"
#include "starnav/nav/navigator.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {

struct NavigationOptions {
  std::optional<std::string> motion_mode;  // overrides the scenario's motion_mode
  std::optional<std::string> planner;      // overrides navigation.planner (a registry name)
  std::optional<std::string> controller;   // overrides navigation.controller
  bool compare_astar = false;              // incremental planners: A* from scratch beside every plan
  bool record_steps = true;                // keep the per-cycle records for steps.jsonl
  bool step_all_hits = false;              // steps.jsonl: every return, not only the obstacle hits
  std::size_t step_particles = kStepParticles;  // steps.jsonl: at most this many particles per cycle
  // Called with each cycle's steps.jsonl line as it is recorded (a live viewer's feed); the run
  // never waits on it beyond the call.
  std::function<void(const std::string&)> on_step_line;
  // Keep the controller's first step at or after each time (its diagnostics and the map around it;
  // a controller that gives no diagnostics is refused).
  std::vector<double> controller_snapshot_times_s;
  // A local controller given by whoever runs the scenario instead of the one navigation.controller
  // names (a Python object through the bindings, a test's fake): made once from the robot, the
  // scenario file and the map's resolution, with the capabilities it declares (GoalHeading: it can
  // turn to a goal heading). The named controller's settings are still checked.
  std::function<std::unique_ptr<LocalController>(const LocalControllerContext&)> make_controller;
  Capabilities controller_capabilities;
};

// The most cells of a navigation map (2^24): each costs about kNavigationMapCellBytes (the layers,
// the obstacle mask and its expansion, the distance field, the occupancy views, the planner's
// search; measured with D* Lite and DWA), so the largest takes about 2.7 GB.
inline constexpr std::int64_t kMaxNavigationMapCells = std::int64_t{1} << 24;
inline constexpr int kNavigationMapCellBytes = 160;

// The navigation section's own parameters (docs/parameters.md); the planner and controller
// sections belong to the chosen components.
struct NavigationSettings {
  std::string planner = "astar";
  std::string controller = "path_follower";
  std::string goal_checker = "latching";
  std::string progress_checker = "simple_progress";
  std::vector<std::string> recoveries = {"rotate", "back_up"};
  std::vector<std::string> layers = {"static_map", "node_height"};
  double goal_tolerance_m = 0.15;
  double goal_yaw_tolerance_rad = 0.08726646259971647;
  std::string prior_map;   // "" none, "world" (world.occupancy_map), or a map_server YAML (relative to the scenario)
  RecoveryConfig recovery;
  double no_path_retry_s = 0.0;
  CommandArbiterConfig bumper;
  double settle_speed_mps = 0.01;  // an arrival is measured once the robot is this slow (or after settle_max_s)
  double settle_max_s = 3.0;
  double resolution_m = 0.1;
  std::string extent = "world";
  double paper_min_size_m = 4.0;
  std::string map_mode = "auto";
  NodeMapParams map;
  double no_return_clear_m = 0.0;
};
const ParamTable<NavigationSettings>& navigation_params();

// Checks a navigation scenario's settings against its components' declared parameters without
// building its world (the errors of NavigationRun's set-up that need no terrain).
void check_navigation_scenario(const ScenarioSpec& spec);

// The components a navigation scenario chooses (navigation.planner, .controller, .goal_checker,
// .progress_checker, .recoveries; --planner, --controller), each with its own section's settings.
struct NavigationComponents {
  ComponentChoice planner, controller, goal_checker, progress_checker;
  std::vector<ComponentChoice> recoveries;
  std::vector<ComponentChoice> layers;  // the navigation map's, in order
};

// The navigator's configuration for a scenario: the map grid (world bounds or the paper's
// extent), node-map parameters (defaults from the robot: max_step from robot.max_step_m,
// barrier distance = the body's circumscribed radius, or its inscribed radius for a controller
// that checks the whole footprint), the prior map; `components` receives the chosen components
// (names checked against the registry). Errors name the scenario file, line and field.
// `settings`, when given, receives the navigation section's own settings.
NavigatorConfig navigator_config(const ScenarioSpec& spec, const WorldDescription& world,
                                 const NavigationOptions& options = {}, NavigationSettings* settings = nullptr,
                                 NavigationComponents* components = nullptr);

// The parts of `components` built from the registry for `robot`, the map's layers on `config`'s
// grid (errors name where each name or setting was given); `seed` is the scenario's.
NavigatorParts make_navigator_parts(const NavigationComponents& components, const NavigatorConfig& config,
                                    const RobotConfig& robot, std::uint64_t seed = 0);

// `scan` (taken at the true pose `truth`) with its world-framed points and sensor pose placed as
// a robot that believes it is at `estimate` places them.
LidarScan scan_placed_at(const LidarScan& scan, const Pose2& truth, const Pose2& estimate);

// One sensor cycle as recorded for steps.jsonl.
struct NavStepRecord {
  double t_s = 0.0;
  Pose3 pose;
  std::size_t returns = 0;
  std::vector<Vec3> hits;  // the highest return in each raw blocked cell hit (every return: step_all_hits)
  std::vector<std::pair<Cell, std::int8_t>> changed;  // occupancy changes: cell, new value
  int path_id = 0;                                // current plan (0: none)
  bool new_path = false;                          // planned in this cycle
  std::optional<Pose2> estimate;                  // the localization chain's pose (scenarios with one)
  std::vector<Pose2> particles;                   // a subsample of its belief (particle filters)
  std::optional<Pose2> reference;                 // localization on a log: the corrected pose, where there is one
};

// One arrival at a goal: the true pose once the robot has come to rest there.
struct NavArrival {
  int goal = 0;            // index into the scenario's goals
  int lap = 0;             // 0-based
  double t_s = 0.0;        // when the navigator declared it (within the goal tolerances)
  double settled_t_s = 0.0;
  Pose2 goal_pose;         // yaw 0 when the goal has no heading
  bool has_yaw = false;
  Pose2 truth, estimate;   // at settled_t_s
  double error_x_m() const { return truth.x - goal_pose.x; }
  double error_y_m() const { return truth.y - goal_pose.y; }
  double error_yaw_rad() const;
};

struct NavigationMetrics {
  bool success = false;
  std::string outcome;          // arrived | no_path | timeout
  std::string reason;           // no_path: why
  double time_to_goal_s = -1.0; // -1 unless arrived
  double duration_s = 0.0;
  double distance_m = 0.0;
  int plans = 0;
  int replans = 0;              // plans after the first
  std::uint64_t expanded_total = 0;
  std::uint64_t replan_expanded = 0;        // over the replans (initial plan excluded)
  std::uint64_t astar_replan_expanded = 0;  // compare_astar: A* from scratch over the same replans
  std::uint64_t astar_backward_replan_expanded = 0;  // the same, searching from the goal to the robot
  bool costs_match = true;  // compare_astar: every plan's cost equal to A*'s in both directions
  std::int64_t collisions = 0;
  double deviation_mean_m = 0.0, deviation_max_m = 0.0;  // robot to the path it was following, every step
  double goal_distance_m = 0.0;  // at the end
  std::string planner, controller, motion_mode;
  int goals_total = 1;          // goals x laps
  int arrivals = 0;
  int recoveries = 0;
  int bumper_stops = 0;
};

class NavigationRun {
 public:
  // Throws Error (file, line, field) when the scenario has no navigation section or no LiDAR.
  explicit NavigationRun(const ScenarioSpec& spec, const NavigationOptions& options = {});
  ~NavigationRun();
  NavigationRun(const NavigationRun&) = delete;
  NavigationRun& operator=(const NavigationRun&) = delete;

  void run(const std::function<void(double)>& progress = {});

  const ScenarioSpec& spec() const { return spec_; }
  const NavigationOptions& options() const { return options_; }
  Simulation& simulation() { return *sim_; }
  const Simulation& simulation() const { return *sim_; }
  Navigator& navigator() { return *nav_; }
  const Navigator& navigator() const { return *nav_; }
  const Localizer& localizer() const { return chain_->localizer(); }
  const LocalizationConfig& localization() const { return localization_; }
  const LocalizationChain& localization_chain() const { return *chain_; }
  // Wheel odometry from the encoder hook (odometry: wheel or ekf), else null.
  const WheelOdometry* odometry() const { return chain_->odometry(); }
  const std::vector<NavStepRecord>& steps() const { return steps_; }
  // The navigator's occupancy before the first scan (the prior map, or all unknown).
  const std::vector<std::int8_t>& initial_occupancy() const { return initial_occupancy_; }
  const std::vector<NavArrival>& arrivals() const { return arrivals_; }
  const CommandArbiter& arbiter() const { return *arbiter_; }
  // The controller steps kept at NavigationOptions::controller_snapshot_times_s.
  const std::vector<ControllerSnapshot>& controller_snapshots() const { return snapshots_; }
  NavigationMetrics metrics() const;
  double setup_s() const { return setup_s_; }
  double wall_s() const { return wall_s_; }

 private:
  ScenarioSpec spec_;
  NavigationOptions options_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<Navigator> nav_;
  LocalizationConfig localization_;
  std::unique_ptr<LocalizationChain> chain_;
  std::vector<NavStepRecord> steps_;
  std::vector<std::int8_t> initial_occupancy_;
  std::unique_ptr<CommandArbiter> arbiter_;
  NavigationSettings settings_;
  std::vector<NavArrival> arrivals_;
  std::vector<ControllerSnapshot> snapshots_;
  std::size_t goal_index_ = 0;  // into the flattened goals x laps
  bool settling_ = false;
  double deviation_sum_ = 0.0, deviation_max_ = 0.0;
  std::int64_t deviation_n_ = 0;
  double setup_s_ = 0.0, wall_s_ = 0.0;
};

// Deterministic records in `dir` (besides Simulation's trajectory.csv, events.csv and sensor CSVs):
//   paths.csv     plan_id,t_s,x_m,y_m        the follower's points of every plan
//   replans.csv   plan_id,t_s,cause,status,expanded,cost_m[,astar_status,astar_expanded,astar_cost_m,
//                 astar_backward_expanded,astar_backward_cost_m]
//   steps.jsonl   one object per sensor cycle (docs/navigation.md)
//   estimate.csv  the localization chain's estimate beside the truth (scenarios with a localization section)
//   arrivals.csv  goal,lap,t_s,settled_t_s,goal_x_m,goal_y_m,goal_yaw_deg,x_m,y_m,yaw_deg,est_x_m,est_y_m,
//                 est_yaw_deg,error_x_m,error_y_m,error_yaw_deg   (scenarios with several goals, laps or a heading)
//   nav_events.csv  t_s,kind,detail: recoveries, bumper stops, manual commands (when there are any)
//   map.yaml + map.pgm   the final occupancy (ROS map_server; unknown -1)
//   metrics.json  NavigationMetrics plus the simulator's metrics under "sim"
//   timing.json   wall-clock figures incl. real_time_factor and each plan's search time
//                 (plan_ms, by plan_id): the only non-deterministic file
// Throws Error naming the file when one cannot be written.
void write_navigation_records(const NavigationRun& run, const std::string& dir);
std::string navigation_metrics_json(const NavigationRun& run);
std::string paths_csv(const NavigationRun& run);
// One line of steps.jsonl (without its newline; docs/run-records.md).
std::string step_json_line(const NavigationRun& run, const NavStepRecord& record);
// The same for any run: `new_path` is the plan the cycle made, when it made one.
std::string step_record_json(const NavStepRecord& record, const std::vector<Vec2>* new_path = nullptr);

}  // namespace starnav
