#include "starnav/harness/route_drive.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"

namespace starnav {

namespace {

constexpr double kReachedM = 0.3;       // a point counts as reached this close (then the next one)
constexpr double kTurnInPlaceRad = 0.6;  // beyond this heading error the robot turns before it drives
constexpr double kHeadingGain = 1.5;     // 1/s
constexpr double kMaxTurnRadps = 0.8;

}  // namespace

RouteDrive::RouteDrive(Simulation& sim, const OccupancyGrid& map, const OccupancyThresholds& thresholds) : sim_(&sim) {
  const ScenarioSpec& spec = sim.spec();
  if (!spec.route) throw Error("the scenario has no route", spec.file, 0, "route");
  const ScenarioRoute& route = *spec.route;
  speed_mps_ = route.speed_mps;
  laps_ = route.laps;
  InflationOptions inflation;
  inflation.radius_m = route.clearance_m;
  const OccupancyGrid grid = route.clearance_m > 0.0
                                 ? inflated_grid(map, inflate_obstacles(map, thresholds, false, inflation))
                                 : map;
  GridPlannerOptions options;
  options.thresholds = thresholds;
  auto planner = make_grid_planner("thetastar", grid, options);
  const auto cell_of = [&](const Vec2& p, std::size_t i) {
    const auto c = grid.geometry().world_to_cell(p);
    const std::string field = "route.waypoints_m[" + std::to_string(i) + "]";
    if (!c) throw Error("lies outside the map", spec.file, route.source.line, field);
    if (thresholds.classify(grid.at(c->x, c->y)) != CellState::Free)
      throw Error("is not free at the route's clearance (" + format_number(route.clearance_m) + " m)", spec.file,
                  route.source.line, field);
    return *c;
  };
  // From the start to the first waypoint, then the loop.
  std::vector<Vec2> stops = route.waypoints;
  stops.push_back(route.waypoints.front());
  path_.push_back(spec.start.translation());
  Cell from = cell_of(spec.start.translation(), 0);
  for (std::size_t i = 0; i < stops.size(); ++i) {
    const Cell to = cell_of(stops[i], i % route.waypoints.size());
    if (i == 1) loop_start_ = path_.size() - 1;  // the first waypoint: where every later lap starts
    if (from == to) continue;
    const PlanResult r = planner->plan(from, to);
    if (!r.found())
      throw Error("no path to it at the route's clearance", spec.file, route.source.line,
                  "route.waypoints_m[" + std::to_string(i % route.waypoints.size()) + "]");
    // Theta*'s vertices (cell centres where a planner gives only cells).
    std::vector<Vec2> leg = r.path_world;
    if (leg.empty())
      for (const Cell& c : r.path_cells) leg.push_back(grid.geometry().cell_center(c));
    if (leg.size() >= 2) path_.insert(path_.end(), leg.begin() + 1, leg.end());
    from = to;
  }
  // The lap: from the first waypoint's arrival onwards (the approach from the start is not repeated).
  for (std::size_t i = loop_start_ + 1; i < path_.size(); ++i) lap_length_m_ += (path_[i] - path_[i - 1]).norm();
  sim.command_source = [this](double t) { return command(t); };
}

void RouteDrive::kidnap_at(double t_s, double min_distance_m, double turn_rad) {
  kidnap_t_s_ = t_s;
  kidnap_distance_m_ = min_distance_m;
  kidnap_turn_rad_ = turn_rad;
}

BodyTwist RouteDrive::command(double t) {
  if (kidnap_t_s_ >= 0.0 && kidnapped_t_s_ < 0.0 && t >= kidnap_t_s_) {
    const Pose2 now = sim_->vehicle().state().pose.to_pose2();
    std::size_t i = target_;
    const auto wrap_index = [&](std::size_t k) { return k + 1 < path_.size() ? k + 1 : loop_start_ + 1; };
    for (std::size_t guard = 0; guard < 2 * path_.size() && (path_[i] - now.translation()).norm() < kidnap_distance_m_; ++guard)
      i = wrap_index(i);
    kidnap_pose_ = Pose2(path_[i].x(), path_[i].y(), wrap_angle(now.yaw + kidnap_turn_rad_));
    sim_->teleport(kidnap_pose_);
    kidnapped_t_s_ = t;
    target_ = wrap_index(i);
  }
  const Pose2 pose = sim_->vehicle().state().pose.to_pose2();
  while ((path_[target_] - pose.translation()).norm() < kReachedM) {
    if (++target_ == path_.size()) {
      if (++laps_done_ >= laps_) {
        sim_->stop();
        return {};
      }
      target_ = loop_start_ + 1;
    }
  }
  const Vec2 d = pose.inverse_transform(path_[target_]);
  const double heading = std::atan2(d.y(), d.x());
  BodyTwist cmd;
  cmd.wz = std::clamp(kHeadingGain * heading, -kMaxTurnRadps, kMaxTurnRadps);
  if (std::abs(heading) < kTurnInPlaceRad) cmd.vx = speed_mps_ * std::cos(heading);
  return cmd;
}

std::unique_ptr<RouteDrive> make_route_drive(Simulation& sim) {
  const ScenarioSpec& spec = sim.spec();
  if (!spec.route || !spec.occupancy_map) throw Error("the scenario has no route on an occupancy map", spec.file, 0, "route");
  LoadedMap loaded = load_map(spec.occupancy_map->resolved_file);
  if (loaded.is_elevation()) throw Error("not an occupancy map", spec.occupancy_map->resolved_file, 0, "world.occupancy_map");
  return std::make_unique<RouteDrive>(sim, loaded.occupancy(), loaded.thresholds());
}

}  // namespace starnav
