#include "nav2_flags.hpp"

#include <cstdio>

#include "starnav/harness/navigation_run.hpp"

namespace starnav::cli {

namespace {

std::string setting(const std::vector<ParamSetting>& settings, const std::string& key, const std::string& fallback) {
  std::string value = fallback;
  for (const ParamSetting& s : settings)
    if (s.key == key) value = s.value;
  return value;
}

}  // namespace

Nav2Target scenario_nav2_target(const ScenarioSpec& spec, const std::string& controller_flag) {
  Nav2Target t;
  t.kind = Nav2Target::Kind::Scenario;
  t.navigation = spec.navigation.has_value();
  if (spec.navigation) {
    // The navigation section's own defaults when the scenario names no component.
    const NavigationSettings defaults;
    t.controller = controller_flag.empty() ? setting(spec.navigation->settings, "controller", defaults.controller) : controller_flag;
    t.goal_checker = setting(spec.navigation->settings, "goal_checker", defaults.goal_checker);
  }
  if (spec.localization) t.localizer = setting(spec.localization->settings, "localizer", "ground_truth");
  return t;
}

void print_nav2_summary(const Nav2Params& p) {
  std::fprintf(stderr, "starnav: %s: %zu Nav2 keys mapped, %zu ignored (starnav params --nav2 %s lists them)\n", p.file.c_str(),
               p.mapped.size(), p.ignored.size(), p.file.c_str());
}

}  // namespace starnav::cli
