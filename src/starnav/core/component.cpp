#include "starnav/core/component.hpp"

#include <algorithm>

namespace starnav {

const char* role_name(Role r) {
  switch (r) {
    case Role::GlobalPlanner: return "global_planner";
    case Role::LocalController: return "local_controller";
    case Role::GoalChecker: return "goal_checker";
    case Role::ProgressChecker: return "progress_checker";
    case Role::Recovery: return "recovery";
    case Role::CostmapLayer: return "costmap_layer";
    case Role::Localizer: return "localizer";
    case Role::Slam: return "slam";
    case Role::ScanMatcher: return "scan_matcher";
    case Role::ScanMatcher3d: return "scan_matcher_3d";
  }
  return "unknown";
}

std::optional<Role> role_from_name(std::string_view name) {
  for (Role r : kAllRoles)
    if (name == role_name(r)) return r;
  return std::nullopt;
}

const char* capability_name(Capability c) {
  switch (c) {
    case Capability::Admissible: return "admissible";
    case Capability::Incremental: return "incremental";
    case Capability::Occupancy: return "occupancy";
    case Capability::NeedsElevation: return "needs_elevation";
    case Capability::NeedsMap: return "needs_map";
    case Capability::GoalHeading: return "goal_heading";
    case Capability::ChecksFootprint: return "checks_footprint";
    case Capability::VelocitySpace: return "velocity_space";
    case Capability::Plugin: return "plugin";
    case Capability::Planar: return "planar";
    case Capability::ThreeD: return "3d";
    case Capability::PriorMap: return "prior_map";
    case Capability::FiltersOdometry: return "filters_odometry";
    case Capability::HeuristicWeight: return "heuristic_weight";
    case Capability::NeedsHeadings: return "needs_headings";
  }
  return "unknown";
}

std::vector<std::string> Capabilities::names() const {
  std::vector<std::string> out;
  for (int i = 0; i < kCapabilityCount; ++i)
    if (has(static_cast<Capability>(i))) out.emplace_back(capability_name(static_cast<Capability>(i)));
  return out;
}

}  // namespace starnav
