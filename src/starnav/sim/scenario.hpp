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
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "starnav/core/geometry.hpp"
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

struct ScenarioLidar {
  LidarConfig config;         // preset plus overrides, mount and self-filter resolved
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
};

// The `navigation` section (docs/scenarios.md): plain values, read by the navigation stack
// (nav/navigation_run), which fills every value not given from its own defaults. The simulator
// itself ignores the section.
struct ScenarioNavigation {
  Vec2 goal = Vec2::Zero();
  double goal_tolerance_m = 0.15;
  std::string planner = "astar";  // astar (from scratch at every replan, as the paper) | dstar_lite
  // map
  double resolution_m = 0.1;
  std::string extent = "world";   // world: the world's bounds; paper: 1.5 x |goal - start| per axis
  double paper_min_size_m = 4.0;  // extent: paper, smallest side
  std::string map_mode;           // "" (from the LiDAR: 3D -> nodes_3d, 2D -> lidar_2d) | nodes_3d | lidar_2d
  std::optional<double> barrier_distance_m;  // default: the body's circumscribed radius
  std::optional<double> max_step_m;          // default: robot.max_step_m
  std::optional<double> max_slope_rad;       // map.max_slope_deg
  std::optional<double> clear_margin_m;
  std::optional<int> hit_gain, miss_loss, evidence_max;
  double no_return_clear_m = 0.0;
  // follower (defaults: PathFollowerConfig)
  std::optional<double> cruise_speed_mps, look_ahead_m, pursuit_look_ahead_m, heading_gain, max_yaw_rate_radps,
      turn_tolerance_rad, slow_down_distance_m;
  ScenarioSource source;       // the section
  ScenarioSource goal_source;  // navigation.goal
};

struct ScenarioSpec {
  std::string file;  // the scenario file as given (errors name it)
  std::string name;
  std::string description;

  ScenarioTerrain terrain;
  std::vector<ScenarioObstacle> obstacles;

  VehicleConfig vehicle;  // robot and vehicle sections
  Pose2 start;            // robot.start (x_m, y_m, yaw_deg)
  ScenarioSource robot_source;
  ScenarioSource start_source;  // robot.start (the robot section's line when absent)

  std::optional<ScenarioLidar> lidar;
  std::optional<ScenarioImu> imu;
  std::optional<ScenarioEncoders> encoders;
  bool bumper = true;

  double dt_s = 0.01;
  double duration_s = 0.0;  // sim.duration_s, or the end of the command script when not given
  std::uint64_t seed = 0;

  std::vector<CommandSegment> commands;  // consecutive, starting at 0
  // navigation: "" (auto), turn_then_drive, holonomic, pure_pursuit (checked against the drive by
  // the navigation stack).
  std::string motion_mode;
  ScenarioSource motion_mode_source;
  std::optional<ScenarioNavigation> navigation;  // present: a navigation scenario (no command script)

  // metrics.reference_line_m: the line the robot is meant to follow (E1: the centre line); the
  // recorder reports the track's distance from it.
  std::vector<Vec2> reference_line;

  ScenarioOutputs outputs;

  // The command at time t: the segment with start_s <= t < end_s, zero after the script.
  BodyTwist command_at(double t) const;
  // Index of that segment, -1 after the script.
  int segment_at(double t) const;
};

// Parses a scenario. `file` names the document in errors and anchors relative paths.
ScenarioSpec parse_scenario(std::string_view yaml_text, const std::string& file);
ScenarioSpec load_scenario(const std::string& path);

// The world of a scenario: loads or generates the terrain, applies its features, places the
// obstacles on it (gravel from its seed). Errors name the scenario file, line and field.
WorldDescription build_world(const ScenarioSpec& spec);

const char* cloud_format_name(ScenarioOutputs::CloudFormat f);  // "none", "ply", "pcd"
ScenarioOutputs::CloudFormat parse_cloud_format(const std::string& s, const std::string& field);

}  // namespace starnav
