#pragma once
// The one registry of starnav's components, by role and name (the list is components.cpp, one line
// per component). Front ends find components here: a scenario names its planner, controller and
// localizer; `starnav plan` its planner; `starnav params` and docs/parameters.md list every
// component with its parameters; `--help` texts list the names.
#include <string>
#include <vector>

#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/control/goal_checker.hpp"
#include "starnav/control/local_controller.hpp"
#include "starnav/control/progress_checker.hpp"
#include "starnav/control/recovery.hpp"
#include "starnav/costmap/costmap_layer.hpp"
#include "starnav/core/component.hpp"
#include "starnav/estimate/localizer.hpp"
#include "starnav/plan/global_planner.hpp"
#include "starnav/slam/scan_matcher.hpp"
#include "starnav/slam/slam.hpp"

namespace starnav {

const std::vector<GlobalPlannerDef>& global_planners();
const std::vector<LocalControllerDef>& local_controllers();
const std::vector<GoalCheckerDef>& goal_checkers();
const std::vector<ProgressCheckerDef>& progress_checkers();
const std::vector<RecoveryDef>& recoveries();
const std::vector<CostmapLayerDef>& costmap_layers();
const std::vector<LocalizerDef>& localizers();
const std::vector<SlamDef>& slam_components();
const std::vector<ScanMatcherDef>& scan_matchers();
const std::vector<ScanMatcher3dDef>& scan_matchers_3d();

// By name or deprecated alias. `warning` (when given) gets "'old' is deprecated; use 'new'" for an
// alias, "" otherwise. An unknown name is an Error naming `field` and listing the known names.
const GlobalPlannerDef& find_global_planner(const std::string& name, const std::string& field = "planner",
                                            std::string* warning = nullptr);
const LocalControllerDef& find_local_controller(const std::string& name, const std::string& field = "controller",
                                                std::string* warning = nullptr);
const GoalCheckerDef& find_goal_checker(const std::string& name, const std::string& field = "goal_checker",
                                        std::string* warning = nullptr);
const ProgressCheckerDef& find_progress_checker(const std::string& name, const std::string& field = "progress_checker",
                                                std::string* warning = nullptr);
const RecoveryDef& find_recovery(const std::string& name, const std::string& field = "recoveries",
                                 std::string* warning = nullptr);
const CostmapLayerDef& find_costmap_layer(const std::string& name, const std::string& field = "layers",
                                          std::string* warning = nullptr);
const LocalizerDef& find_localizer(const std::string& name, const std::string& field = "localizer",
                                   std::string* warning = nullptr);
const ScanMatcherDef& find_scan_matcher(const std::string& name, const std::string& field = "scan_matcher",
                                        std::string* warning = nullptr);
const ScanMatcher3dDef& find_scan_matcher_3d(const std::string& name, const std::string& field = "matcher",
                                            std::string* warning = nullptr);
const SlamDef& find_slam(const std::string& name, const std::string& field = "slam", std::string* warning = nullptr);

// The description of the component of `role` named `name` (or a deprecated alias); Errors as the
// find_* functions.
ComponentInfo find_component(Role role, const std::string& name, const std::string& field, std::string* warning = nullptr);

// The names of a role, in registry order.
std::vector<std::string> component_names(Role role);
// Every component's description, in registry order (roles in enum order).
std::vector<ComponentInfo> all_components();

}  // namespace starnav
