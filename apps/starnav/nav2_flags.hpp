#pragma once
// `--params NAV2_PARAMS.yaml` (harness/nav2_params.hpp) on the commands that take it: the target a
// scenario's components make, and the one line each command prints about the mapping.
#include <string>

#include "starnav/harness/nav2_params.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav::cli {

// The scenario's navigation section, localizer and controller (`controller_flag` overrides it).
Nav2Target scenario_nav2_target(const ScenarioSpec& spec, const std::string& controller_flag);
// "starnav: FILE: N Nav2 keys mapped, M ignored (starnav params --nav2 FILE lists them)" on stderr.
void print_nav2_summary(const Nav2Params& p);

}  // namespace starnav::cli
