// The registry: one line per component. A component is defined in its own file as a function
// returning its ComponentDef; its line here names that function (declared and listed by the
// X-macro below, so a new component touches nothing else).
#include "starnav/registry/components.hpp"

#include <algorithm>

#include "starnav/core/error.hpp"
#include "starnav/plan/hybrid_astar.hpp"
#include "starnav/slam/graph_slam_3d.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"

namespace starnav {

#define STARNAV_LOCAL_CONTROLLERS(X)                          \
  X(path_follower_controller)    /* control/path_follower.cpp */ \
  X(straight_to_goal_controller) /* control/straight_to_goal.cpp */ \
  X(dwa_controller)              /* control/dwa_controller.cpp */ \
  X(regulated_pure_pursuit_controller) /* control/regulated_pure_pursuit.cpp */ \
  X(mppi_controller)             /* control/mppi_controller.cpp */

#define STARNAV_LOCALIZERS(X) \
  X(ground_truth_localizer) /* estimate/ground_truth_localizer.cpp */ \
  X(odometry_localizer)     /* estimate/odometry_localizer.cpp */ \
  X(ekf_localizer)          /* estimate/ekf_localizer.cpp */ \
  X(amcl_localizer)         /* estimate/amcl_localizer.cpp */

#define STARNAV_SCAN_MATCHERS(X) \
  X(correlative_scan_matcher) /* slam/correlative_scan_matcher.cpp */

#define STARNAV_SCAN_MATCHERS_3D(X) \
  X(icp_scan_matcher)    /* cloud/icp.cpp */ \
  X(gicp_scan_matcher)   /* cloud/gicp.cpp */ \
  X(vgicp_scan_matcher)  /* cloud/vgicp.cpp */ \
  X(ndt_scan_matcher)    /* cloud/ndt.cpp */ \
  X(ndt_mt_scan_matcher) /* cloud/ndt.cpp */ \
  X(pcl_icp_scan_matcher)  /* cloud/pcl_matchers.cpp (PCL plugin) */ \
  X(pcl_gicp_scan_matcher) /* cloud/pcl_matchers.cpp (PCL plugin) */ \
  X(pcl_ndt_scan_matcher)  /* cloud/pcl_matchers.cpp (PCL plugin) */

#define STARNAV_SLAM(X) \
  X(graph_slam)    /* slam/graph_slam.cpp */ \
  X(graph_slam_3d) /* slam/graph_slam_3d.cpp */

#define STARNAV_GOAL_CHECKERS(X) \
  X(latching_goal_checker) /* control/latching_goal_checker.cpp */ \
  X(stopped_goal_checker)  /* control/stopped_goal_checker.cpp */

#define STARNAV_PROGRESS_CHECKERS(X) \
  X(simple_progress_checker) /* control/simple_progress_checker.cpp */

#define STARNAV_RECOVERIES(X)                       \
  X(rotate_recovery)  /* control/recoveries.cpp */ \
  X(back_up_recovery) /* control/recoveries.cpp */ \
  X(drive_arc_recovery) /* control/recoveries.cpp */ \
  X(wait_recovery)    /* control/recoveries.cpp */

#define STARNAV_COSTMAP_LAYERS(X)                                \
  X(static_map_layer)  /* costmap/static_map_layer.cpp */       \
  X(node_height_layer) /* costmap/node_height_layer.cpp */ \
  X(keepout_layer)     /* costmap/keepout_layer.cpp */ \
  X(speed_limit_layer) /* costmap/speed_limit_layer.cpp */

#define STARNAV_DECLARE_CONTROLLER(f) LocalControllerDef f();
#define STARNAV_DECLARE_COSTMAP_LAYER(f) CostmapLayerDef f();
#define STARNAV_DECLARE_GOAL_CHECKER(f) GoalCheckerDef f();
#define STARNAV_DECLARE_PROGRESS_CHECKER(f) ProgressCheckerDef f();
#define STARNAV_DECLARE_RECOVERY(f) RecoveryDef f();
#define STARNAV_DECLARE_LOCALIZER(f) LocalizerDef f();
#define STARNAV_DECLARE_SCAN_MATCHER(f) ScanMatcherDef f();
#define STARNAV_DECLARE_SCAN_MATCHER_3D(f) ScanMatcher3dDef f();
#define STARNAV_DECLARE_SLAM(f) SlamDef f();
#define STARNAV_LIST(f) f(),
STARNAV_LOCAL_CONTROLLERS(STARNAV_DECLARE_CONTROLLER)
STARNAV_GOAL_CHECKERS(STARNAV_DECLARE_GOAL_CHECKER)
STARNAV_PROGRESS_CHECKERS(STARNAV_DECLARE_PROGRESS_CHECKER)
STARNAV_RECOVERIES(STARNAV_DECLARE_RECOVERY)
STARNAV_COSTMAP_LAYERS(STARNAV_DECLARE_COSTMAP_LAYER)
STARNAV_LOCALIZERS(STARNAV_DECLARE_LOCALIZER)
STARNAV_SCAN_MATCHERS(STARNAV_DECLARE_SCAN_MATCHER)
STARNAV_SCAN_MATCHERS_3D(STARNAV_DECLARE_SCAN_MATCHER_3D)
STARNAV_SLAM(STARNAV_DECLARE_SLAM)

const std::vector<GlobalPlannerDef>& global_planners() {
  static const std::vector<GlobalPlannerDef> all = {
      grid_global_planner("dijkstra", "Uniform-cost search on the occupancy grid"),
      grid_global_planner("astar", "A* with the octile heuristic (8-connected, no corner cutting)"),
      grid_global_planner("wastar", "Weighted A*: f = g + w h"),
      grid_global_planner("jps", "Jump point search (Harabor and Grastien 2011)"),
      grid_global_planner("jpsplus", "JPS+ with precomputed jump tables"),
      grid_global_planner("thetastar", "Theta*: any-angle paths by line of sight"),
      grid_global_planner("dstar_lite", "D* Lite (Koenig and Likhachev 2002): repairs its search as cells change",
                          {"dstarlite"}),
      grid_global_planner("ou2022", "The improved A* of Ou et al. 2022 with the paper's defaults"),
      hybrid_astar_global_planner(),
      rough_terrain_global_planner(RoughTerrainPlannerKind::OA),
      rough_terrain_global_planner(RoughTerrainPlannerKind::AOEA),
      rough_terrain_global_planner(RoughTerrainPlannerKind::IA),
  };
  return all;
}

const std::vector<LocalControllerDef>& local_controllers() {
  static const std::vector<LocalControllerDef> all = {STARNAV_LOCAL_CONTROLLERS(STARNAV_LIST)};
  return all;
}

const std::vector<GoalCheckerDef>& goal_checkers() {
  static const std::vector<GoalCheckerDef> all = {STARNAV_GOAL_CHECKERS(STARNAV_LIST)};
  return all;
}

const std::vector<ProgressCheckerDef>& progress_checkers() {
  static const std::vector<ProgressCheckerDef> all = {STARNAV_PROGRESS_CHECKERS(STARNAV_LIST)};
  return all;
}

const std::vector<RecoveryDef>& recoveries() {
  static const std::vector<RecoveryDef> all = {STARNAV_RECOVERIES(STARNAV_LIST)};
  return all;
}

const std::vector<CostmapLayerDef>& costmap_layers() {
  static const std::vector<CostmapLayerDef> all = {STARNAV_COSTMAP_LAYERS(STARNAV_LIST)};
  return all;
}

const std::vector<LocalizerDef>& localizers() {
  static const std::vector<LocalizerDef> all = {STARNAV_LOCALIZERS(STARNAV_LIST)};
  return all;
}

namespace {

// A SLAM method is composed with a scan matcher: its factory gets the registry's matchers (by
// name, with their settings) unless the caller gave factories of its own.
SlamDef composed_with_registry_matchers(SlamDef d) {
  d.make = [make = std::move(d.make)](const SlamContext& ctx, std::span<const ParamSetting> settings) {
    SlamContext c = ctx;
    if (!c.make_scan_matcher)
      c.make_scan_matcher = [file = ctx.file](const SlamMatcherChoice& m) {
        return find_scan_matcher(m.name, m.field).make(ScanMatcherContext{file}, m.settings);
      };
    if (!c.make_scan_matcher_3d)
      c.make_scan_matcher_3d = [](const SlamMatcherChoice& m) { return find_scan_matcher_3d(m.name, m.field).make({}, m.settings); };
    return make(c, settings);
  };
  return d;
}

}  // namespace

const std::vector<SlamDef>& slam_components() {
  static const std::vector<SlamDef> all = [] {
    std::vector<SlamDef> defs = {STARNAV_SLAM(STARNAV_LIST)};
    for (SlamDef& d : defs) d = composed_with_registry_matchers(std::move(d));
    return defs;
  }();
  return all;
}

const std::vector<ScanMatcherDef>& scan_matchers() {
  static const std::vector<ScanMatcherDef> all = {STARNAV_SCAN_MATCHERS(STARNAV_LIST)};
  return all;
}

const std::vector<ScanMatcher3dDef>& scan_matchers_3d() {
  static const std::vector<ScanMatcher3dDef> all = {STARNAV_SCAN_MATCHERS_3D(STARNAV_LIST)};
  return all;
}

namespace {

template <class Def>
const Def& find_in(const std::vector<Def>& all, const std::string& name, const std::string& field, std::string* warning,
                   const char* what) {
  if (warning) warning->clear();
  for (const Def& d : all) {
    if (d.info.name == name) return d;
    const auto& aliases = d.info.deprecated_aliases;
    if (std::find(aliases.begin(), aliases.end(), name) != aliases.end()) {
      if (warning) *warning = "'" + name + "' is deprecated; use '" + d.info.name + "'";
      return d;
    }
  }
  std::string known;
  for (const Def& d : all) known += (known.empty() ? "" : ", ") + d.info.name;
  throw Error("unknown " + std::string(what) + " '" + one_line(name, 60) + "' (" + known + ")", {}, 0, field);
}

template <class Def>
void append_infos(const std::vector<Def>& all, std::vector<ComponentInfo>& out) {
  for (const Def& d : all) out.push_back(d.info);
}

}  // namespace

const GlobalPlannerDef& find_global_planner(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(global_planners(), name, field, warning, "planner");
}
const LocalControllerDef& find_local_controller(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(local_controllers(), name, field, warning, "controller");
}
const GoalCheckerDef& find_goal_checker(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(goal_checkers(), name, field, warning, "goal checker");
}
const ProgressCheckerDef& find_progress_checker(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(progress_checkers(), name, field, warning, "progress checker");
}
const RecoveryDef& find_recovery(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(recoveries(), name, field, warning, "recovery");
}
const CostmapLayerDef& find_costmap_layer(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(costmap_layers(), name, field, warning, "costmap layer");
}
const LocalizerDef& find_localizer(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(localizers(), name, field, warning, "localizer");
}

const ScanMatcherDef& find_scan_matcher(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(scan_matchers(), name, field, warning, "scan matcher");
}

const ScanMatcher3dDef& find_scan_matcher_3d(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(scan_matchers_3d(), name, field, warning, "3D scan matcher");
}

const SlamDef& find_slam(const std::string& name, const std::string& field, std::string* warning) {
  return find_in(slam_components(), name, field, warning, "SLAM method");
}

ComponentInfo find_component(Role role, const std::string& name, const std::string& field, std::string* warning) {
  switch (role) {
    case Role::GlobalPlanner: return find_global_planner(name, field, warning).info;
    case Role::LocalController: return find_local_controller(name, field, warning).info;
    case Role::GoalChecker: return find_goal_checker(name, field, warning).info;
    case Role::ProgressChecker: return find_progress_checker(name, field, warning).info;
    case Role::Recovery: return find_recovery(name, field, warning).info;
    case Role::CostmapLayer: return find_costmap_layer(name, field, warning).info;
    case Role::Localizer: return find_localizer(name, field, warning).info;
    case Role::Slam: return find_slam(name, field, warning).info;
    case Role::ScanMatcher: return find_scan_matcher(name, field, warning).info;
    case Role::ScanMatcher3d: return find_scan_matcher_3d(name, field, warning).info;
  }
  throw Error("unknown role", {}, 0, field);
}

std::vector<ComponentInfo> all_components() {
  std::vector<ComponentInfo> out;
  append_infos(global_planners(), out);
  append_infos(local_controllers(), out);
  append_infos(goal_checkers(), out);
  append_infos(progress_checkers(), out);
  append_infos(recoveries(), out);
  append_infos(costmap_layers(), out);
  append_infos(localizers(), out);
  append_infos(slam_components(), out);
  append_infos(scan_matchers(), out);
  append_infos(scan_matchers_3d(), out);
  return out;
}

std::vector<std::string> component_names(Role role) {
  std::vector<std::string> names;
  for (const ComponentInfo& c : all_components())
    if (c.role == role) names.push_back(c.name);
  return names;
}

}  // namespace starnav
