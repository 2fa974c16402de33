#pragma once
// Ren et al. 2022 Table 1 (docs/papers/ren2022.md): A* against Dijkstra as the indoor robot's
// global planner. The paper times one query from (1, 1) m to (18, 18) m in a 20 m x 20 m room,
// empty and with obstacles, as ROS wall times of the whole planner call (2.8 / 3.8 s Dijkstra,
// 1.9 / 2.1 s A*). Here: the same query on the same kind of room at 0.05 m (scenarios/maps/
// ren_room_*.yaml), the map inflated by the robot's inscribed radius as the navigation does, each
// planner's search timed `repeats` times in thread CPU time (the search alone: the inflation is
// done once per map and reported apart), nodes expanded and path cost; and `queries` random
// queries between free cells of the indoor map (scenarios/maps/indoor_rooms.yaml), the same
// queries for both planners, whose costs must agree (both are optimal).
#include <cstdint>
#include <string>
#include <vector>

namespace starnav {

struct RenTable1Config {
  std::string empty_room = "scenarios/maps/ren_room_empty.yaml";
  std::string obstacle_room = "scenarios/maps/ren_room_obstacles.yaml";
  std::string indoor_map = "scenarios/maps/indoor_rooms.yaml";
  double start_x = 1.0, start_y = 1.0, goal_x = 18.0, goal_y = 18.0;
  double inflation_m = 0.25;  // the indoor robot's inscribed radius
  int repeats = 20;
  int queries = 1000;
  std::uint64_t seed = 0;
  void validate() const;  // Error naming the flag
};

struct RenTable1Row {
  std::string map;      // empty | obstacles | indoor (random queries)
  std::string planner;  // dijkstra | astar
  int queries = 0;
  double expanded_mean = 0.0;
  std::uint64_t expanded_total = 0;
  double cost_m = 0.0;        // the single query's path cost, or the mean over the random queries
  double median_ms = 0.0;     // single query: median over repeats; random: median over queries
  double mean_ms = 0.0;
  double inflation_ms = 0.0;  // the map's inflation, once
};

struct RenTable1Result {
  RenTable1Config config;
  std::vector<RenTable1Row> rows;  // empty, obstacles, indoor; dijkstra then astar
  int cost_mismatches = 0;         // random queries where the two planners' costs differ
  int unreachable = 0;             // random queries without a path (both planners agree)
};

RenTable1Result run_ren_table1(const RenTable1Config& config);
std::string ren_table1_markdown(const RenTable1Result& result);
std::string ren_table1_json(const RenTable1Result& result);
std::string ren_table1_csv(const RenTable1Result& result);

}  // namespace starnav
