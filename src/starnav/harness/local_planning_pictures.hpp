#pragma once
// Pictures of a DWA run (docs/local_planning.md):
//   dwa_step     one control step from above: the local obstacle map around the robot, the path,
//                every sample's rollout (collision-free ones shaded by cost, colliding ones red),
//                the chosen one thick green, the robot's footprint and the local goal;
//   speed        the achieved vx, vy and wz over time (the profile of the run).
// Snapshots of DWA steps are taken by NavigationRun at the times NavigationOptions asks for.
#include <string>
#include <vector>

#include "starnav/control/dwa_controller.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sim/simulation.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

// One DWA step as captured: the step's record (every sample) and the obstacle map around it.
struct DwaSnapshot {
  DwaStepRecord step;
  OccupancyGrid local_map;   // the raw obstacles in a square around the robot
  std::vector<Vec2> path;    // the path the controller followed
  DwaConfig config;
  Footprint footprint;
};

viz::MapPicture dwa_step_picture(const DwaSnapshot& snapshot, const std::string& title);
viz::LinePlot speed_profile_plot(const std::vector<TrajectorySample>& trajectory, const std::string& title);

// The square of `map` of side `side_m` around `centre` (cells outside the map unknown).
OccupancyGrid crop_map(const OccupancyGrid& map, const Vec2& centre, double side_m);

}  // namespace starnav
