#pragma once
// How a scenario section names its components and hands them their parameters; shared by the
// navigation section and the localization section.
#include <string>
#include <vector>

#include "starnav/core/component.hpp"
#include "starnav/core/params.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav {

// The settings of `section` (keys starting "section."), the prefix removed; taken out of `rest`.
std::vector<ParamSetting> settings_under(std::vector<ParamSetting>& rest, const std::string& section);

// The component `key` names in `settings` (`fallback` when absent), with where it was written.
ComponentChoice choice_of(const std::vector<ParamSetting>& settings, const std::string& key, std::string fallback,
                          const std::string& section_field, const ScenarioSpec& spec);

}  // namespace starnav
