#pragma once
// What every component of the navigation stack is to the rest of starnav: a role, a name, its
// capabilities, its declared parameters (params.hpp) and a factory. The role interfaces live with
// their modules (plan/global_planner.hpp, control/local_controller.hpp, estimate/localizer.hpp,
// slam/slam.hpp, slam/scan_matcher.hpp); the one list of components is registry/components.cpp.
// Adding a component is one new file defining its ComponentDef and one line there
// (docs/architecture.md, "Adding a component").
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/params.hpp"

namespace starnav {

enum class Role : std::uint8_t { GlobalPlanner, LocalController, Localizer, Slam, ScanMatcher, ScanMatcher3d };
// "global_planner", "local_controller", "localizer", "slam", "scan_matcher", "scan_matcher_3d"
const char* role_name(Role r);
inline constexpr Role kAllRoles[] = {Role::GlobalPlanner, Role::LocalController, Role::Localizer,
                                     Role::Slam,          Role::ScanMatcher,     Role::ScanMatcher3d};
// The role named as role_name() spells it; nullopt for anything else.
std::optional<Role> role_from_name(std::string_view name);

struct ComponentInfo {
  Role role = Role::GlobalPlanner;
  std::string name;                             // one spelling: lower_snake_case
  std::vector<std::string> deprecated_aliases;  // accepted with a warning
  std::string section;                          // where its parameters live in a scenario ("follower": navigation.follower)
  std::string summary;                          // one line
  std::vector<std::string> capabilities;        // admissible, incremental, needs_elevation, holonomic_only, ...
  std::vector<ParamSpec> params;
  bool has(const std::string& capability) const;
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
