#pragma once
// Scenario files (docs/scenarios.md): a YAML document describing a world (terrain and obstacles),
// a robot with its sensors, the fixed-step clock and a script of body-velocity commands.
//
//   ScenarioSpec spec = load_scenario("scenarios/e1_terrain_platform.yaml");
//   WorldDescription world = build_world(spec);     // loads / generates the terrain, places obstacles
//
// Parsing is strict: an unknown key, a value of the wrong type, a size out of range or a missing
// required key throws starnav::Error naming the scenario file, the line and the dotted field
// ("world.obstacles[2].size_m"). Nothing is loaded or generated while parsing; build_world does
// that, and its errors carry the file, line and field of the key that asked for it.
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/robot/robot_model.hpp"
#include "starnav/sense/imu.hpp"
#include "starnav/sense/lidar.hpp"
#include "starnav/sense/wheel_encoders.hpp"
#include "starnav/sim/obstacles.hpp"
#include "starnav/sim/vehicle.hpp"
#include "starnav/sim/world.hpp"
#include "starnav/terrain/terrain_generator.hpp"

namespace starnav {

// Where a value came from, for errors raised after parsing.
struct ScenarioSource {
  int line = 0;
  std::string field;
};

// world.occupancy_map: FILE, or {file: FILE, wall_height_m: H}: an indoor world from a map_server
// map, each occupied cell (map_server's occupied threshold) a wall H tall on z = 0 (default 2 m,
// above any 2D LiDAR's mount); sim/occupancy_world.hpp.
struct ScenarioOccupancyWorld {
  std::string file;           // as written
  std::string resolved_file;  // relative to the scenario's folder
  double wall_height_m = 2.0;
  ScenarioSource source;
};

// events[i]: {t_s, teleport: {x_m, y_m, yaw_deg}} moves the robot there at t_s without its wheels
// turning (the kidnapped robot: odometry and IMU do not see it); the target must be free.
struct ScenarioTeleport {
  double t_s = 0.0;
  Pose2 to;
  ScenarioSource source;
};

// route: {waypoints_m: [[x, y], ...], speed_mps, laps, clearance_m}: the robot drives a closed loop
// through the waypoints on paths planned on world.occupancy_map (harness/route_drive), steered by
// its true pose: a fixed drive for experiments that measure something else (localization).
struct ScenarioRoute {
  std::vector<Vec2> waypoints;
  double speed_mps = 0.5;
  int laps = 1;
  double clearance_m = 0.4;  // obstacle inflation for the planned paths
  ScenarioSource source;
};

struct ScenarioTerrain {
  enum class Kind : std::uint8_t { None, File, Flat, Hills, Road };
  Kind kind = Kind::None;
  std::string file;           // Kind::File: the path as written
  std::string resolved_file;  // ... relative to the scenario's folder
  double flat_z_m = 0.0;      // Kind::Flat: the height everywhere
  // Kind::Flat uses hills' width/height/resolution/origin. The generators' seeds are the
  // scenario seed unless `seed` is given (seed_given).
  HillsOptions hills;
  RoadOptions road;
  bool seed_given = false;
  std::vector<TerrainFeature> features;  // pits and mounds, added after generation (all kinds)
  ScenarioSource source;
};

struct ScenarioObstacle {
  using Shape = std::variant<Box, Cylinder, Prism, Sphere, SlopeStep, UndulatingGround, RoundConvex, Gravel>;
  std::string name;
  std::string kind;  // as written: box, cylinder, prism, sphere, slope_step, undulating_ground, round_convex, gravel
  // The shape with its position at (x, y, 0): build_world lifts it to `z` or, when z is not given,
  // to the terrain height under (x, y) (0 without terrain). The reference point is the centre of
  // the obstacle's footprint on the ground (a box's bottom face, a sphere's lowest point).
  Shape shape;
  Vec2 position = Vec2::Zero();
  std::optional<double> z;
  double appear_s = 0.0;
  double disappear_s = std::numeric_limits<double>::infinity();
  Vec3 velocity = Vec3::Zero();
  // Anchor positions over time; a waypoint without z keeps the obstacle's height.
  struct Point {
    double t_s = 0.0;
    Vec2 xy = Vec2::Zero();
    std::optional<double> z;
  };
  std::vector<Point> waypoints;
  bool gravel_seed_given = false;
  ScenarioSource source;  // the list element (line) and "world.obstacles[i]"
};

// sensors.lidars holds at most this many LiDARs besides sensors.lidar.
inline constexpr std::size_t kMaxOtherLidars = 8;

struct ScenarioLidar {
  LidarConfig config;         // preset plus overrides, mount and self-filter resolved
  std::string stream = "lidar";  // sensors.lidar: "lidar"; sensors.lidars.NAME: "lidar/NAME"
  std::string preset;         // "" for a fully custom sensor
  double horizontal_resolution_deg = 0.0;  // 0 = the preset's default
  ScenarioSource source;
};

struct ScenarioImu {
  ImuConfig config;
  ScenarioSource source;
};

struct ScenarioEncoders {
  EncoderConfig config;
  double rate_hz = 50.0;
  ScenarioSource source;
};

// One piece of the command script: a constant body twist until `end_s` (absolute), computed
// from duration_s (relative to the previous segment's end) or until_s.
struct CommandSegment {
  double start_s = 0.0;
  double end_s = 0.0;
  BodyTwist twist;
  int line = 0;
};

struct ScenarioOutputs {
  int trajectory_every_n_steps = 1;
  enum class CloudFormat : std::uint8_t { None, Ply, Pcd };
  CloudFormat point_clouds = CloudFormat::None;
  int clouds_every_n_scans = 1;
  // What a real robot records for 3D mapping: per scan a sensor-frame cloud and a frames.csv row
  // (harness/lidar_frame_recorder.hpp); 0 = not recorded.
  int lidar_frames_every_n_scans = 0;
};

// The `navigation` section (docs/scenarios.md): the goal, and every other value as a setting
// (dotted key relative to the section, its text and line). The navigation harness checks the
// settings against the declared parameters of the components the scenario names (planner,
// controller, the map, the navigator); the simulator knows none of them.
// A navigation goal: a position and, optionally, the heading to arrive with.
struct ScenarioGoal {
  Vec2 position = Vec2::Zero();
  std::optional<double> yaw_rad;
  ScenarioSource source;
};

// A manual command (a person with a joystick): this body twist from t_s for duration_s. It
// outranks the navigation's command; a bumper contact outranks both.
struct ScenarioManualCommand {
  double t_s = 0.0;
  double duration_s = 0.0;
  BodyTwist twist;
  ScenarioSource source;
};

struct ScenarioNavigation {
  Vec2 goal = Vec2::Zero();            // goals[0].position
  std::vector<ScenarioGoal> goals;     // navigation.goal (one) or navigation.goals (visited in order)
  int laps = 1;                        // the goals are visited this many times over
  std::vector<ScenarioManualCommand> manual;  // in time order, not overlapping
  std::vector<ParamSetting> settings;  // "planner", "goal_tolerance_m", "map.resolution_m", "follower.look_ahead_m", ...
  ScenarioSource source;       // the section
  ScenarioSource goal_source;  // navigation.goal
};

// A section read as settings only (localization: odometry, localizer, ground_truth.sigma_xy_m, ...).
struct ScenarioSettings {
  std::vector<ParamSetting> settings;
  ScenarioSource source;
};

struct ScenarioSpec {
  std::string file;  // the scenario file as given (errors name it)
  std::string name;
  std::string description;

  ScenarioTerrain terrain;
  std::optional<ScenarioOccupancyWorld> occupancy_map;
  std::vector<ScenarioObstacle> obstacles;

  VehicleConfig vehicle;  // robot and vehicle sections
  Pose2 start;            // robot.start (x_m, y_m, yaw_deg)
  ScenarioSource robot_source;
  ScenarioSource start_source;  // robot.start (the robot section's line when absent)

  std::optional<ScenarioLidar> lidar;
  std::vector<ScenarioLidar> other_lidars;  // sensors.lidars: more LiDARs by name (a rear one), in file order
  std::optional<ScenarioImu> imu;
  std::optional<ScenarioEncoders> encoders;
  bool bumper = true;

  double dt_s = 0.01;
  double duration_s = 0.0;  // sim.duration_s, or the end of the command script when not given
  std::uint64_t seed = 0;

  std::vector<CommandSegment> commands;  // consecutive, starting at 0
  std::vector<ScenarioTeleport> teleports;  // events: by time
  std::optional<ScenarioRoute> route;
  // navigation: "" (auto), turn_then_drive, holonomic, pure_pursuit (checked against the drive by
  // the navigation stack).
  std::string motion_mode;
  ScenarioSource motion_mode_source;
  std::optional<ScenarioNavigation> navigation;  // present: a navigation scenario (no command script)
  std::optional<ScenarioSettings> localization;  // navigation scenarios: the localization chain

  // metrics.reference_line_m: the line the robot is meant to follow (E1: the centre line); the
  // recorder reports the track's distance from it.
  std::vector<Vec2> reference_line;

  ScenarioOutputs outputs;

  // The command at time t: the segment with start_s <= t < end_s, zero after the script.
  BodyTwist command_at(double t) const;
  // Index of that segment, -1 after the script.
  int segment_at(double t) const;
};

// A value given on the command line for a dotted key of the scenario, applied to the YAML before
// it is read (`--set navigation.follower.look_ahead_m=0.4`): every key of every section can be
// set, and the value is checked exactly as if it were in the file. Errors name it "KEY (--set)".
struct ScenarioOverride {
  std::string key;    // dotted lower_snake_case names
  std::string value;  // a YAML value: 0.4, astar, [1.0, 2.0]
};
// "KEY=VALUE"; Error (field "--set") otherwise.
ScenarioOverride parse_scenario_override(const std::string& text);

// A scenario key that a command sets itself (a seed per run, the planners a bench compares, a
// flag's value): a --set of it would be overridden, so it is refused, with the reason.
struct CommandOwnedKey {
  std::string key;  // dotted; a --set of the key or of any key under it is refused
  std::string why;  // "bench nav runs dstar_lite and astar itself"
};
// Checks the user's --set values before anything is read: each key at most once (a second value
// would silently replace the first), none of the keys the command owns. Error naming "KEY (--set)".
void check_user_overrides(std::span<const ScenarioOverride> overrides, std::span<const CommandOwnedKey> owned = {});

// Largest generated terrain (4000 x 4000 cells: 400 m x 400 m at 0.1 m).
inline constexpr std::size_t kMaxTerrainCells = 16'000'000;
// Most gravel pieces over all gravel fields of a scenario (ten fields at the largest count): one
// line of YAML per field must not be able to ask for gigabytes.
inline constexpr long long kMaxGravelPieces = 1'000'000;

// A run is at most kMaxSimulationSteps fixed steps (duration_s / dt_s): 10 million steps are
// 28 simulated hours at the default 0.01 s; and it casts at most kMaxSimulationLidarRays LiDAR
// rays (scans x rays per scan): two billion rays are about half an hour of ray casting on one core.
inline constexpr double kMaxSimulationSteps = 1e7;
inline constexpr double kMaxSimulationLidarRays = 2e9;
// Error naming `field` when the run would take more steps or rays than these.
void check_simulation_steps(const ScenarioSpec& spec, const std::string& field);

// Parses a scenario. `file` names the document in errors and anchors relative paths.
ScenarioSpec parse_scenario(std::string_view yaml_text, const std::string& file,
                            std::span<const ScenarioOverride> overrides = {});
ScenarioSpec load_scenario(const std::string& path, std::span<const ScenarioOverride> overrides = {});

// The world of a scenario: loads or generates the terrain, applies its features, places the
// obstacles on it (gravel from its seed). Errors name the scenario file, line and field.
WorldDescription build_world(const ScenarioSpec& spec);

const char* cloud_format_name(ScenarioOutputs::CloudFormat f);  // "none", "ply", "pcd"
ScenarioOutputs::CloudFormat parse_cloud_format(const std::string& s, const std::string& field);

}  // namespace starnav
