#pragma once
// A scenario's route (sim/scenario.hpp ScenarioRoute) driven in the simulator: a closed loop
// through the waypoints, each leg planned by Theta* on the world's occupancy map inflated by the
// route's clearance, followed by a pure-pursuit steering law on the robot's TRUE pose (the drive
// is the experiment's fixed input, not what it measures). The run stops after the last lap.
#include <memory>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav {

class RouteDrive {
 public:
  // Plans every leg and sets sim.command_source. Throws Error (the scenario's file and field
  // route.waypoints_m[i]) when a waypoint is blocked or a leg has no path. `sim` must outlive it.
  RouteDrive(Simulation& sim, const OccupancyGrid& map, const OccupancyThresholds& thresholds);
  // The planned path: the start, the approach to the first waypoint, then one closed lap.
  const std::vector<Vec2>& path() const { return path_; }
  double lap_length_m() const { return lap_length_m_; }
  int laps_done() const { return laps_done_; }
  // The kidnapped robot: at t_s the robot is carried to the first vertex of the route ahead at
  // least min_distance_m away (straight line) and turned by turn_rad, then drives on from there.
  void kidnap_at(double t_s, double min_distance_m, double turn_rad);
  // When the kidnap happened (-1 before), where to.
  double kidnap_time() const { return kidnapped_t_s_; }
  const Pose2& kidnap_pose() const { return kidnap_pose_; }

 private:
  BodyTwist command(double t);

  Simulation* sim_;
  std::vector<Vec2> path_;  // one closed lap: first point = last point
  double lap_length_m_ = 0.0;
  double speed_mps_ = 0.5;
  int laps_ = 1;
  int laps_done_ = 0;
  std::size_t loop_start_ = 0;  // index of the first waypoint in path_
  std::size_t target_ = 1;      // index of the point being driven to
  double kidnap_t_s_ = -1.0, kidnap_distance_m_ = 0.0, kidnap_turn_rad_ = 0.0;
  double kidnapped_t_s_ = -1.0;
  Pose2 kidnap_pose_;
};

// The route's scenario: a map loaded from world.occupancy_map with its thresholds, then the drive.
std::unique_ptr<RouteDrive> make_route_drive(Simulation& sim);

}  // namespace starnav
