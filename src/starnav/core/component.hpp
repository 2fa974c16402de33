#pragma once
// What every component of the navigation stack is to the rest of starnav: a role, a name, its
// capabilities, its declared parameters (params.hpp) and a factory. The role interfaces live with
// their modules (plan/global_planner.hpp, control/local_controller.hpp, estimate/localizer.hpp,
// slam/slam.hpp, slam/scan_matcher.hpp); the one list of components is registry/components.cpp.
// Adding a component is one new file defining its ComponentDef and one line there
// (docs/architecture.md, "Adding a component").
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/params.hpp"

namespace starnav {

enum class Role : std::uint8_t {
  GlobalPlanner,
  LocalController,
  GoalChecker,
  ProgressChecker,
  Recovery,
  CostmapLayer,
  Localizer,
  Slam,
  ScanMatcher,
  ScanMatcher3d,
};
// "global_planner", "local_controller", "goal_checker", "progress_checker", "recovery",
// "costmap_layer", "localizer", "slam", "scan_matcher", "scan_matcher_3d"
const char* role_name(Role r);
inline constexpr Role kAllRoles[] = {Role::GlobalPlanner, Role::LocalController, Role::GoalChecker, Role::ProgressChecker,
                                     Role::Recovery,      Role::CostmapLayer,    Role::Localizer,   Role::Slam,
                                     Role::ScanMatcher,   Role::ScanMatcher3d};
// The role named as role_name() spells it; nullopt for anything else.
std::optional<Role> role_from_name(std::string_view name);

// What a component can do or needs, as callers query it instead of testing names (OMPL's
// PlannerSpecs idea). Written in docs and `starnav params` by capability_name().
enum class Capability : std::uint8_t {
  Admissible,        // a planner whose paths are optimal on its graph
  Incremental,       // a planner that repairs one search between calls (given the changed cells)
  Occupancy,         // a planner that plans on an occupancy layer
  NeedsElevation,    // a planner that plans on an elevation layer
  NeedsMap,          // a localizer that needs a known map
  GoalHeading,       // a controller that turns to a goal heading
  ChecksFootprint,   // a controller or planner that checks the whole footprint against the obstacles (not the expanded map)
  VelocitySpace,     // a controller that commands velocities under acceleration limits (a speed profile)
  Plugin,            // loaded from a plugin library at run time
  Planar,            // SLAM, scan matchers: 2D scans
  ThreeD,            // SLAM, scan matchers: 3D clouds
  PriorMap,          // a costmap layer that holds the obstacles of navigation.map.prior
  FiltersOdometry,   // a localizer that fuses wheel odometry with the IMU and can stand in as the odometry
  HeuristicWeight,   // a planner whose heuristic takes a weight (plan --weight)
  NeedsHeadings,     // a planner between poses: it needs the start and goal headings (plan_poses)
};
inline constexpr int kCapabilityCount = 15;
// "admissible", "incremental", "occupancy", "needs_elevation", "needs_map", "goal_heading",
// "checks_footprint", "velocity_space", "plugin", "planar", "3d", "prior_map", "filters_odometry",
// "heuristic_weight", "needs_headings"
const char* capability_name(Capability c);

// A set of capabilities, in declaration order when listed.
class Capabilities {
 public:
  Capabilities() = default;
  Capabilities(std::initializer_list<Capability> list) {
    for (Capability c : list) add(c);
  }
  void add(Capability c) { bits_ |= 1u << static_cast<unsigned>(c); }
  bool has(Capability c) const { return (bits_ >> static_cast<unsigned>(c)) & 1u; }
  bool empty() const { return bits_ == 0; }
  std::vector<std::string> names() const;

 private:
  std::uint32_t bits_ = 0;
};

struct ComponentInfo {
  Role role = Role::GlobalPlanner;
  std::string name;                             // one spelling: lower_snake_case
  std::vector<std::string> deprecated_aliases;  // accepted with a warning
  std::string section;                          // where its parameters live in a scenario ("follower": navigation.follower)
  std::string summary;                          // one line
  Capabilities capabilities;
  std::vector<ParamSpec> params;
  // The Nav2 plugin this component stands for ("dwb_core::DWBLocalPlanner"; empty: none): a Nav2
  // parameter file's keys for that plugin map onto this component's section (docs/ros2.md).
  std::string nav2_counterpart;
  bool has(Capability c) const { return capabilities.has(c); }
};

// A component of role `Interface`, built from a context (what the caller knows: the robot, the
// map, the seed) and the user's settings for its section.
template <class Interface, class Context>
struct ComponentDef {
  ComponentInfo info;
  std::function<std::unique_ptr<Interface>(const Context&, std::span<const ParamSetting>)> make;
};

// A component chosen by name, with the user's settings for its section (a scenario's or --set's).
struct ComponentChoice {
  std::string name;
  std::vector<ParamSetting> settings;
  std::string field;  // where the name was given ("navigation.planner", "--planner"), for errors
  int line = 0;       // its line in `file`, 0 when not from a file
  std::string file;
};

}  // namespace starnav
