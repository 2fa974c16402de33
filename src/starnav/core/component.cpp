#include "starnav/core/component.hpp"

#include <algorithm>

namespace starnav {

const char* role_name(Role r) {
  switch (r) {
    case Role::GlobalPlanner: return "global_planner";
    case Role::LocalController: return "local_controller";
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

bool ComponentInfo::has(const std::string& capability) const {
  return std::find(capabilities.begin(), capabilities.end(), capability) != capabilities.end();
}

}  // namespace starnav
