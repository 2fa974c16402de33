#pragma once
// Large building floors for the SLAM benchmark of scale (docs/slam.md, "Large buildings"): a grid
// of corridors whose blocks are lined with identical rooms, drawn as a map_server occupancy map
// (every cell occupied or free) that a scenario's world.occupancy_map turns into walls, and a route
// through it that drives every block's ring of corridors, visits rooms and closes every loop.
//
// The corridors run along the lines x = corridor_x[i] and y = corridor_y[j]; every segment between
// two neighbouring junctions exists, so each block between four corridors is a loop (the floor has
// (nx - 1)(ny - 1) of them). Rooms line both sides of every corridor: the blocks' four sides and
// an outer strip beyond the outer corridors; all rooms of a floor have one size and one door
// position, so they repeat exactly (the case place recognition gets wrong). Walls are the cells
// left occupied: everything is solid rock but the corridors, the rooms and their doors.
//
// Kinds: `grid` (4 x 3 corridors: six blocks), `ladder` (two long corridors joined by seven rungs:
// six tall, narrow blocks), `courtyard` (3 x 3 corridors: four large blocks, and an atrium where
// the middle corridors cross). The seed jitters the corridors' positions and width, the rooms'
// size, the door's place in a room, which doors are shut, and which rooms the route visits.
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

enum class BuildingKind : std::uint8_t { Grid, Ladder, Courtyard };
const char* building_kind_name(BuildingKind k);
// "grid", "ladder", "courtyard"; throws Error naming `field` otherwise.
BuildingKind parse_building_kind(const std::string& text, const std::string& field);

struct BuildingOptions {
  BuildingKind kind = BuildingKind::Grid;
  std::uint64_t seed = 0;
  double resolution_m = 0.05;
  double room_visit_probability = 0.1;  // an open room beside the route is driven into
  double shut_door_probability = 0.2;   // a room's door is wall (flush with the corridor's)
};

struct AxisBox {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  bool contains(const Vec2& p) const { return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1; }
};

struct BuildingRoom {
  AxisBox interior;
  AxisBox door;        // the gap in the wall to the corridor
  Vec2 outside;        // on the corridor's centre line in front of the door
  bool open = true;    // a shut door stays wall
};

struct BuildingFloor {
  BuildingKind kind = BuildingKind::Grid;
  OccupancyGrid map;                      // 100 occupied, 0 free; origin (0, 0)
  double corridor_width_m = 0;
  double wall_m = 0;                      // wall thickness
  Vec2 room_size_m;                       // along the corridor, away from it
  std::vector<double> corridor_x, corridor_y;  // centre lines, increasing
  std::vector<AxisBox> blocks;            // each ringed by corridors: the loops
  std::vector<BuildingRoom> rooms;
  std::vector<Vec2> route;                // one lap's waypoints (closed: the last leads back to the first)
  Pose2 start;                            // on the first waypoint, facing the second
};

BuildingFloor generate_building(const BuildingOptions& options);

// The route's length from waypoint to waypoint, closed (straight legs; the driven path is the
// planned one and a little longer where it enters rooms).
double route_length_m(const std::vector<Vec2>& route);

// The drive of the benchmark: the whole lap `laps` times when `length_m` reaches at least one lap
// (laps = length / lap, rounded up), else the lap's first waypoints up to `length_m` of straight
// legs, closed back to the start (the outer ring comes first, so a short route still closes the
// largest loop once it is long enough to go round it).
struct BuildingRoute {
  std::vector<Vec2> waypoints;
  int laps = 1;
};
BuildingRoute building_route(const BuildingFloor& floor, double length_m);

// A scenario (docs/scenarios.md) that drives `route` through the floor whose map_server files
// `map_file` names (relative to the scenario): a differential robot like a Pioneer with a SICK
// LMS151 logged at `scan_rate_hz`, wheel encoders slipping, at `speed_mps`. Each wheel's encoder
// also counts a fixed fraction off its travel (a tyre radius not quite the nominal one), drawn
// from the seed uniformly within +-`wheel_scale_error` (0.005: 0.5 %): a systematic drift the
// zero-mean slip does not have, which bends every straight corridor the same way.
struct BuildingScenarioOptions {
  std::string name;
  std::string map_file;
  std::uint64_t seed = 0;
  double speed_mps = 0.6;
  double scan_rate_hz = 5.0;
  double wheel_scale_error = 0.005;
};
std::string building_scenario_yaml(const BuildingFloor& floor, const BuildingRoute& route, const BuildingScenarioOptions& options);

// The two wheels' scale errors (left, right) that building_scenario_yaml writes for these options.
std::vector<double> building_wheel_scale_errors(const BuildingScenarioOptions& options);

}  // namespace starnav
