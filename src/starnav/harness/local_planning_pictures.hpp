#pragma once
// Pictures of a local controller's work (docs/local_planning.md), for any controller:
//   controller_step  one control step from above, from the controller's diagnostics: the local
//                    obstacle map around the robot, the path, every candidate's trajectory
//                    (valid ones shaded by cost, colliding ones red; rejected ones not drawn), the
//                    chosen one thick green, the robot's footprint and the controller's named points
//                    (a local goal, a look-ahead point);
//   speed            the achieved vx, vy and wz over time (the profile of the run).
// Snapshots of controller steps are taken by NavigationRun at the times NavigationOptions asks for.
#include <string>
#include <vector>

#include "starnav/control/local_controller.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sim/simulation.hpp"
#include "starnav/viz/map_picture.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

// One controller step as captured: its diagnostics and the obstacle map around it.
struct ControllerSnapshot {
  ControlDiagnostics step;
  OccupancyGrid local_map;   // the raw obstacles in a square around the robot
  std::vector<Vec2> path;    // the path the controller followed
  Footprint footprint;
};

viz::MapPicture controller_step_picture(const ControllerSnapshot& snapshot, const std::string& title);
viz::LinePlot speed_profile_plot(const std::vector<TrajectorySample>& trajectory, const std::string& title);

// The square of `map` of side `side_m` around `centre` (cells outside the map unknown).
OccupancyGrid crop_map(const OccupancyGrid& map, const Vec2& centre, double side_m);

}  // namespace starnav
