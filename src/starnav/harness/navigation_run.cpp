#include "starnav/harness/navigation_run.hpp"
#include "starnav/harness/scenario_settings.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

[[noreturn]] void fail_at(const ScenarioSpec& spec, const ScenarioSource& src, const std::string& message) {
  throw Error(message, spec.file, src.line, src.field);
}

// The map grid: the world's terrain, or the box around start, goal and the obstacles (extent
// world); the paper's 1.5 x |goal - start| per axis around their midpoint (extent paper).
GridGeometry map_geometry(const ScenarioSpec& spec, const WorldDescription& world, const NavigationSettings& n) {
  const Vec2 start = spec.start.translation();
  const Vec2 goal = spec.navigation->goal;
  Vec2 lo, hi;
  if (n.extent == "paper") {
    const Vec2 mid = 0.5 * (start + goal);
    const Vec2 half = (0.75 * (goal - start).cwiseAbs()).cwiseMax(Vec2::Constant(0.5 * n.paper_min_size_m));
    lo = mid - half;
    hi = mid + half;
  } else if (world.terrain) {
    const GridGeometry& g = world.terrain->geometry();
    lo = g.origin.translation();
    hi = lo + Vec2(g.width_m(), g.height_m());
  } else {
    // Everything the robot may need to plan across: the start, every goal, and every obstacle
    // whole (a map_server world's walls are one obstacle) wherever it stands during the run.
    lo = start;
    hi = start;
    const auto extend = [&lo, &hi](const Vec2& p) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    };
    for (const ScenarioGoal& g : spec.navigation->goals) extend(g.position);
    for (const Obstacle& o : world.obstacles) {
      std::vector<Vec3> offsets{o.offset_at(o.appear)};
      for (const Waypoint& w : o.waypoints) offsets.push_back(o.offset_at(w.time));
      if (o.velocity != Vec3::Zero() && std::isfinite(o.disappear)) offsets.push_back(o.offset_at(o.disappear));
      for (const Primitive& part : o.parts) {
        const Aabb b = bounds(part);
        if (b.empty()) continue;
        for (const Vec3& d : offsets) {
          extend((b.lo + d).head<2>());
          extend((b.hi + d).head<2>());
        }
      }
    }
    lo -= Vec2::Constant(2.0);
    hi += Vec2::Constant(2.0);
  }
  GridGeometry g;
  g.resolution = n.resolution_m;
  g.origin = Pose2(lo.x(), lo.y(), 0.0);
  const double w = std::ceil((hi.x() - lo.x()) / n.resolution_m - 1e-9);
  const double h = std::ceil((hi.y() - lo.y()) / n.resolution_m - 1e-9);
  if (!(w >= 1.0 && h >= 1.0) || w * h > static_cast<double>(kMaxNavigationMapCells))
    throw Error("the navigation map's extent " + format_readable(hi.x() - lo.x()) + " x " + format_readable(hi.y() - lo.y()) +
                    " m (navigation.map.extent " + n.extent + ") over navigation.map.resolution_m " + format_readable(n.resolution_m) +
                    " m gives " + format_number(w) + " x " + format_number(h) + " cells, more than " +
                    std::to_string(kMaxNavigationMapCells) + " (about " + std::to_string(kNavigationMapCellBytes) +
                    " bytes each): coarsen map.resolution_m",
                spec.file, 0, "navigation.map.resolution_m");
  g.width = static_cast<int>(w);
  g.height = static_cast<int>(h);
  return g;
}

}  // namespace

// The settings of `section` (keys starting "section."), the prefix removed.
std::vector<ParamSetting> settings_under(std::vector<ParamSetting>& rest, const std::string& section) {
  std::vector<ParamSetting> mine, others;
  const std::string prefix = section + ".";
  for (ParamSetting& v : rest) {
    if (v.key.rfind(prefix, 0) == 0) {
      v.key = v.key.substr(prefix.size());
      mine.push_back(std::move(v));
    } else {
      others.push_back(std::move(v));
    }
  }
  rest = std::move(others);
  return mine;
}

ComponentChoice choice_of(const std::vector<ParamSetting>& settings, const std::string& key, std::string fallback,
                          const std::string& section_field, const ScenarioSpec& spec) {
  ComponentChoice c{std::move(fallback), {}, section_field + "." + key, 0, spec.file};
  for (const ParamSetting& v : settings)
    if (v.key == key) {
      c.name = v.value;
      c.line = v.line;
      c.field = v.field;
    }
  return c;
}


const ParamTable<NavigationSettings>& navigation_params() {
  static const ParamTable<NavigationSettings> table = [] {
    using C = NavigationSettings;
    ParamTable<C> t;
    const auto name_of = [](std::string C::*member) {
      return [member](C& c, const std::string& v) { c.*member = v; };
    };
    const auto get_of = [](std::string C::*member) { return [member](const C& c) { return c.*member; }; };
    std::vector<std::string> occupancy_planners;
    for (const GlobalPlannerDef& d : global_planners())
      if (!d.info.has(Capability::NeedsElevation)) occupancy_planners.push_back(d.info.name);
    t.choice("planner", occupancy_planners, name_of(&C::planner), get_of(&C::planner),
             "the global planner (registry name; it plans on the node map's occupancy)", false);
    t.choice("controller", component_names(Role::LocalController), name_of(&C::controller), get_of(&C::controller),
             "the local controller (registry name)", false);
    t.choice("goal_checker", component_names(Role::GoalChecker), name_of(&C::goal_checker), get_of(&C::goal_checker),
             "the goal checker (registry name)", false);
    t.choice("progress_checker", component_names(Role::ProgressChecker), name_of(&C::progress_checker),
             get_of(&C::progress_checker), "the progress checker (registry name)", false);
    t.name_list("recoveries", component_names(Role::Recovery), [](C& c, const std::vector<std::string>& v) { c.recoveries = v; },
                [](const C& c) { return c.recoveries; },
                "run in this order when the robot is stuck, then a new plan ([] : none, the robot waits)", false);
    t.name_list("layers", component_names(Role::CostmapLayer), [](C& c, const std::vector<std::string>& v) { c.layers = v; },
                [](const C& c) { return c.layers; },
                "the navigation map's layers, in order: each adds its obstacles, then the map expands them by "
                "map.barrier_distance_m",
                false);
    t.real("goal_tolerance_m", &C::goal_tolerance_m, positive(), "m", "arrived within this distance of the goal");
    t.real("goal_yaw_tolerance_deg", &C::goal_yaw_tolerance_rad, open(0.0, 180.0), "deg",
           "with a goal heading (goal.yaw_deg), arrived within this angle of it too", kPi / 180.0);
    t.choice("map.prior", {"(none)", "world", "FILE.yaml"}, [](C& c, const std::string& v) { c.prior_map = v; },
             [](const C& c) { return c.prior_map; },
             "obstacles known before the run: world (the world's occupancy_map) or a map_server YAML, relative to the "
             "scenario (2D map mode); empty: none",
             false);
    t.real("no_path_retry_s", &C::no_path_retry_s, closed(0.0, 3600.0), "s",
           "no path (a blocked start, a cut-off goal): wait and plan again at every cycle this long before giving up "
           "(0: give up at once, the paper's rule)");
    t.real("recovery.blocked_patience_s", [](C& c) -> double& { return c.recovery.blocked_patience_s; }, positive(), "s",
           "the controller blocked this long starts the recoveries (a new plan is asked for at once)");
    t.integer("recovery.max_recoveries", [](C& c) -> int& { return c.recovery.max_recoveries; }, closed(0, 1000), "",
              "recoveries per goal before the navigation gives up (no_path, stuck)");
    t.boolean("bumper.stop", [](C& c) -> bool& { return c.bumper.bumper_stop; },
              "a bumper contact stops the robot (outranks manual and autonomous commands)");
    t.real("bumper.resume_delay_s", [](C& c) -> double& { return c.bumper.resume_delay_s; }, closed(0.0, 60.0), "s",
           "wait this long after a contact ends before moving again");
    t.real("settle_speed_mps", &C::settle_speed_mps, positive(), "m/s",
           "an arrival is measured once the robot is this slow (or after settle_max_s)");
    t.real("settle_max_s", &C::settle_max_s, closed(0.0, 60.0), "s", "longest wait for the robot to come to rest at a goal");
    t.real("map.resolution_m", &C::resolution_m, positive(), "m", "cell size of the navigation map");
    t.choice("map.extent", {"world", "paper"}, name_of(&C::extent), get_of(&C::extent),
             "world: the world's bounds; paper: 1.5 x |goal - start| per axis around their midpoint");
    t.real("map.paper_min_size_m", &C::paper_min_size_m, positive(), "m", "extent paper: the smallest side");
    t.choice("map.mode", {"auto", "nodes_3d", "lidar_2d"}, name_of(&C::map_mode), get_of(&C::map_mode),
             "auto: nodes_3d with a 3D LiDAR, lidar_2d with a 2D one");
    t.real("map.barrier_distance_m", [](C& c) -> double& { return c.map.barrier_distance_m; }, non_negative(), "m",
           "obstacle expansion radius");
    t.default_rule("map.barrier_distance_m",
                   "the body's circumscribed radius; its inscribed radius with a controller that checks the footprint (dwa)");
    t.real("map.max_step_m", [](C& c) -> double& { return c.map.li.max_step_m; }, positive(), "m",
           "largest height spread of a walkable cell");
    t.default_rule("map.max_step_m", "robot.max_step_m");
    t.real("map.max_slope_deg", [](C& c) -> double& { return c.map.li.max_slope_rad; }, open(0.0, 90.0), "deg",
           "steepest walkable slope between neighbouring cells", kPi / 180.0);
    t.real("map.clear_margin_m", [](C& c) -> double& { return c.map.clear_margin_m; }, non_negative(), "m",
           "a beam contradicts a cell only when it passes this far below the cell's max height");
    t.integer("map.hit_gain", [](C& c) -> int& { return c.map.hit_gain; }, closed(1, 255), "",
              "evidence gained by a cell hit in a scan");
    t.integer("map.miss_loss", [](C& c) -> int& { return c.map.miss_loss; }, closed(0, 255), "",
              "evidence lost by a cell a beam contradicts in a scan");
    t.integer("map.evidence_max", [](C& c) -> int& { return c.map.evidence_max; }, closed(1, 255), "",
              "evidence cap: a stale cell clears after evidence_max / miss_loss scans");
    t.real("map.no_return_clear_m", &C::no_return_clear_m, non_negative(), "m",
           "beams without a return clear the cells up to this range (0: off)");
    t.real("map.clearance_range_m", [](C& c) -> double& { return c.map.clearance_range_m; }, open(0.0, 100.0), "m",
           "the map's distance field (what controllers and recoveries check footprints against) is exact out to this");
    return t;
  }();
  return table;
}

namespace {

// The prior map's obstacles on the navigation grid: a navigation cell is an obstacle when the
// map's cell under its centre is occupied (by the map's own threshold).
std::vector<std::uint8_t> prior_mask(const std::string& file, const GridGeometry& g) {
  RosMapMetadata meta;
  const OccupancyGrid prior = read_ros_map(file, &meta);
  OccupancyThresholds th;
  th.occupied_percent = meta.occupied_thresh * 100.0;
  th.free_percent = meta.free_thresh * 100.0;
  std::vector<std::uint8_t> mask(g.cell_count(), 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const auto c = prior.geometry().world_to_cell(g.cell_center(x, y));
      if (c && th.classify(prior(c->x, c->y)) == CellState::Occupied) mask[g.index(x, y)] = 1;
    }
  return mask;
}

}  // namespace

NavigatorConfig navigator_config(const ScenarioSpec& spec, const WorldDescription& world, const NavigationOptions& options,
                                 NavigationSettings* settings_out, NavigationComponents* components_out) {
  if (!spec.navigation)
    throw Error("not a navigation scenario (no navigation section)", spec.file, 0, "navigation");
  const ScenarioNavigation& n = *spec.navigation;
  if (!spec.lidar) throw Error("navigation needs sensors.lidar", spec.file, n.source.line, "sensors.lidar");
  const RobotConfig& rc = spec.vehicle.robot;

  // Defaults that come from the robot, then the scenario's settings.
  NavigationSettings s;
  s.map.li.max_step_m = rc.max_step_m;
  std::vector<ParamSetting> rest = n.settings;
  NavigatorConfig c;
  NavigationComponents parts;
  const NavigationSettings defaults;
  parts.planner = choice_of(rest, "planner", defaults.planner, "navigation", spec);
  parts.controller = choice_of(rest, "controller", defaults.controller, "navigation", spec);
  parts.goal_checker = choice_of(rest, "goal_checker", defaults.goal_checker, "navigation", spec);
  parts.progress_checker = choice_of(rest, "progress_checker", defaults.progress_checker, "navigation", spec);
  if (options.planner) parts.planner = {*options.planner, {}, "--planner", 0, ""};
  if (options.controller) parts.controller = {*options.controller, {}, "--controller", 0, ""};
  // The recoveries and the map's layers, in order: the names of each list, each a choice of its own.
  const auto choices_of = [&](const std::string& key, const std::vector<std::string>& fallback) {
    const ComponentChoice list = choice_of(rest, key, format_param_name_list(fallback), "navigation", spec);
    const ParamSetting as_setting{key, list.name, list.file, list.line, list.field};
    std::vector<ComponentChoice> out;
    for (const std::string& name : parse_param_name_list(as_setting)) out.push_back({name, {}, list.field, list.line, list.file});
    return out;
  };
  parts.recoveries = choices_of("recoveries", defaults.recoveries);
  parts.layers = choices_of("layers", defaults.layers);
  // Each chosen component is found in the registry (errors where its name was given) and takes the
  // settings of its own section.
  std::vector<std::string> chosen_sections;
  const auto resolve = [&](ComponentChoice& choice, Role role) -> ComponentInfo {
    std::string warning;
    ComponentInfo info;
    try {
      info = find_component(role, choice.name, choice.field, &warning);
    } catch (const Error& e) {
      throw Error(e.message(), choice.file, choice.line, choice.field);
    }
    if (!warning.empty()) c.warnings.push_back(choice.field + ": " + warning);
    choice.name = info.name;
    if (std::find(chosen_sections.begin(), chosen_sections.end(), info.section) == chosen_sections.end()) {
      choice.settings = settings_under(rest, info.section);
      chosen_sections.push_back(info.section);
    } else {
      // The same recovery (or layer) twice in its list: both run with the one section's settings.
      for (const std::vector<ComponentChoice>* list : {&parts.recoveries, &parts.layers})
        for (const ComponentChoice& earlier : *list)
          if (earlier.name == info.name && !earlier.settings.empty()) choice.settings = earlier.settings;
    }
    return info;
  };
  const ComponentInfo pinfo = resolve(parts.planner, Role::GlobalPlanner);
  const ComponentInfo cinfo = resolve(parts.controller, Role::LocalController);
  resolve(parts.goal_checker, Role::GoalChecker);
  resolve(parts.progress_checker, Role::ProgressChecker);
  for (ComponentChoice& r : parts.recoveries) resolve(r, Role::Recovery);
  bool prior_map_layer = false;
  for (ComponentChoice& l : parts.layers) prior_map_layer = resolve(l, Role::CostmapLayer).has(Capability::PriorMap) || prior_map_layer;
  // The robot is a point in the expanded map: the body's circumscribed radius by default; a
  // controller that checks the whole footprint needs only the inscribed radius (the planner then
  // finds the doors the body fits through sideways or straight).
  s.map.barrier_distance_m = cinfo.has(Capability::ChecksFootprint) ? 0.5 * std::min(rc.body_length_m, rc.body_width_m)
                                                                   : 0.5 * std::hypot(rc.body_length_m, rc.body_width_m);
  // The top-level motion_mode (and --motion-mode) is the controller's own motion_mode parameter,
  // for a controller that declares one.
  const bool has_motion_mode = std::any_of(cinfo.params.begin(), cinfo.params.end(),
                                           [](const ParamSpec& p) { return p.key == "motion_mode"; });
  if (has_motion_mode) {
    if (options.motion_mode) parts.controller.settings.push_back({"motion_mode", *options.motion_mode, "", 0, "--motion-mode"});
    else if (!spec.motion_mode.empty())
      parts.controller.settings.push_back({"motion_mode", spec.motion_mode, spec.file, spec.motion_mode_source.line, "motion_mode"});
  } else if (options.motion_mode) {
    throw Error("the " + cinfo.name + " controller has no motion_mode", "", 0, "--motion-mode");
  } else if (!spec.motion_mode.empty()) {
    // A scenario written for a controller with motion modes, run with another from the command line.
    if (!options.controller)
      throw Error("the " + cinfo.name + " controller has no motion_mode", spec.file, spec.motion_mode_source.line, "motion_mode");
    c.warnings.push_back("motion_mode: ignored (the " + cinfo.name + " controller has none)");
  }
  // What is left: the navigation section's own settings, or a section of a component that is not
  // running (refused, unless a command-line flag swapped that component out: then the file's
  // section is dropped and said).
  const std::vector<std::pair<Role, const char*>> roles = {{Role::GlobalPlanner, "navigation.planner"},
                                                           {Role::LocalController, "navigation.controller"},
                                                           {Role::GoalChecker, "navigation.goal_checker"},
                                                           {Role::ProgressChecker, "navigation.progress_checker"},
                                                           {Role::Recovery, "navigation.recoveries"},
                                                           {Role::CostmapLayer, "navigation.layers"}};
  const auto chosen_name = [&](Role role) {
    switch (role) {
      case Role::GlobalPlanner: return parts.planner.name;
      case Role::LocalController: return parts.controller.name;
      case Role::GoalChecker: return parts.goal_checker.name;
      case Role::ProgressChecker: return parts.progress_checker.name;
      default: {
        std::vector<std::string> names;
        for (const ComponentChoice& r : role == Role::Recovery ? parts.recoveries : parts.layers) names.push_back(r.name);
        return format_param_name_list(names);
      }
    }
  };
  std::vector<ParamSetting> own;
  std::vector<std::string> dropped_sections;
  for (ParamSetting& v : rest) {
    if (navigation_params().has(v.key)) {
      own.push_back(std::move(v));
      continue;
    }
    const std::string head = v.key.substr(0, v.key.find('.'));
    std::optional<ComponentInfo> owner;
    for (const ComponentInfo& i : all_components())
      if (i.section == head && v.key != head &&
          std::any_of(roles.begin(), roles.end(), [&](const auto& r) { return r.first == i.role; }))
        owner = i;
    if (!owner) param_unknown_key(v, navigation_params().keys());
    const auto role = std::find_if(roles.begin(), roles.end(), [&](const auto& r) { return r.first == owner->role; });
    // The scenario file's section of the component a command-line flag swapped out: the flag
    // outranks the file, so that section is dropped (and said). A --set for it is still refused.
    const bool swapped_on_command_line = (owner->role == Role::GlobalPlanner && options.planner) ||
                                         (owner->role == Role::LocalController && options.controller);
    if (v.line > 0 && swapped_on_command_line) {
      if (std::find(dropped_sections.begin(), dropped_sections.end(), head) == dropped_sections.end()) {
        dropped_sections.push_back(head);
        c.warnings.push_back("navigation." + head + ": ignored (parameters of " + owner->name + "; " +
                             (owner->role == Role::GlobalPlanner ? "--planner chose " : "--controller chose ") +
                             chosen_name(owner->role) + ")");
      }
      continue;
    }
    throw Error("parameters of " + owner->name + ", but " + role->second + " is " + chosen_name(owner->role), v.file, v.line,
                v.field);
  }
  navigation_params().apply(s, own);

  try {
    c.geometry = map_geometry(spec, world, s);
  } catch (const Error& e) {
    rethrow_at_setting(e, own, spec.file);
  }
  NodeMapParams& m = c.map;
  m = s.map;
  const bool lidar2d = spec.lidar->config.lines() <= 1;
  m.mode = s.map_mode == "auto" ? (lidar2d ? NodeMapMode::Lidar2D : NodeMapMode::Nodes3D)
                                : (s.map_mode == "lidar_2d" ? NodeMapMode::Lidar2D : NodeMapMode::Nodes3D);
  c.no_return_clear_m = s.no_return_clear_m;
  c.goal_tolerance_m = s.goal_tolerance_m;
  c.goal_yaw_tolerance_rad = s.goal_yaw_tolerance_rad;
  c.recovery = s.recovery;
  c.no_path_retry_s = s.no_path_retry_s;
  if (!s.prior_map.empty() && !prior_map_layer) {
    const auto at = std::find_if(own.begin(), own.end(), [](const ParamSetting& v) { return v.key == "map.prior"; });
    throw Error("no layer of navigation.layers holds a prior map (add static_map)", spec.file, at != own.end() ? at->line : 0,
                at != own.end() ? at->field : "navigation.map.prior");
  }
  if (!s.prior_map.empty()) {
    const auto at = std::find_if(own.begin(), own.end(), [](const ParamSetting& v) { return v.key == "map.prior"; });
    const std::string field = at != own.end() ? at->field : "navigation.map.prior";
    const int line = at != own.end() ? at->line : 0;
    if (m.mode != NodeMapMode::Lidar2D) throw Error("a prior map needs the 2D map mode (a 2D LiDAR or map.mode lidar_2d)", spec.file, line, field);
    std::string file;
    if (s.prior_map == "world") {
      if (!spec.occupancy_map) throw Error("world: the scenario has no world.occupancy_map", spec.file, line, field);
      file = spec.occupancy_map->resolved_file;
    } else {
      file = (std::filesystem::path(spec.file).parent_path() / s.prior_map).string();
    }
    try {
      c.prior_obstacles = prior_mask(file, c.geometry);
    } catch (const Error& e) {
      const std::string what = e.file().empty() ? file + ": " + e.what() : std::string(e.what());
      throw Error("cannot read the prior map: " + what, spec.file, line, field);
    }
  }
  c.compare_astar = options.compare_astar && pinfo.has(Capability::Incremental);
  if (components_out) *components_out = std::move(parts);
  try {
    c.validate();
  } catch (const Error& e) {
    rethrow_at_setting(e, own, spec.file);
  }
  // Only a terrain's bounds or the paper's extent can leave a goal or the start outside.
  const auto outside = [&](const std::string& what, const Vec2& p) {
    const GridGeometry& g = c.geometry;
    const Vec2 lo = g.origin.translation();
    return what + " (" + format_fixed(p.x(), 2) + ", " + format_fixed(p.y(), 2) + ") m lies outside the navigation map, [" +
           format_fixed(lo.x(), 2) + ", " + format_fixed(lo.x() + g.width_m(), 2) + "] x [" + format_fixed(lo.y(), 2) + ", " +
           format_fixed(lo.y() + g.height_m(), 2) + "] m (navigation.map.extent " + s.extent +
           (s.extent == "paper" ? ": 1.5 x |goal - start| around their midpoint; extent world covers the whole world)"
                                : ": the world's terrain)");
  };
  for (const ScenarioGoal& g : n.goals)
    if (!c.geometry.world_to_cell(g.position)) fail_at(spec, g.source, outside("the goal", g.position));
  if (settings_out) *settings_out = s;
  if (!c.geometry.world_to_cell(spec.start.translation()))
    fail_at(spec, spec.start_source, outside("the start", spec.start.translation()));
  return c;
}

NavigatorParts make_navigator_parts(const NavigationComponents& components, const NavigatorConfig& config,
                                    const RobotConfig& robot, std::uint64_t seed) {
  // Errors of a component's own checks (its parameters, its name) point where it was chosen.
  const auto at_choice = [](const ComponentChoice& choice, auto&& build) {
    try {
      return build();
    } catch (const Error& e) {
      if (!e.file().empty() || e.line() > 0) throw;
      throw Error(e.message(), choice.file, choice.line, e.field().empty() ? choice.field : e.field());
    }
  };
  NavigatorParts parts;
  const ComponentChoice& p = components.planner;
  const GlobalPlannerDef& planner = at_choice(p, [&]() -> const GlobalPlannerDef& { return find_global_planner(p.name, p.field); });
  GridPlannerOptions grid;
  grid.connectivity = 8;
  grid.unknown_is_free = true;  // plan optimistically through unobserved cells (docs/papers/li2019.md)
  parts.planner = planner.make({grid, p.file, body_footprint_model(robot), min_turning_radius_of(robot)}, p.settings);
  parts.planner_capabilities = planner.info.capabilities;
  const ComponentChoice& c = components.controller;
  const LocalControllerDef& controller =
      at_choice(c, [&]() -> const LocalControllerDef& { return find_local_controller(c.name, c.field); });
  parts.controller = controller.make({robot, c.file, config.geometry.resolution, seed}, c.settings);
  parts.controller_capabilities = controller.info.capabilities;
  const ComponentChoice& g = components.goal_checker;
  parts.goal_checker = at_choice(g, [&] { return find_goal_checker(g.name, g.field).make({g.file}, g.settings); });
  const ComponentChoice& pc = components.progress_checker;
  parts.progress_checker = at_choice(pc, [&] { return find_progress_checker(pc.name, pc.field).make({pc.file}, pc.settings); });
  for (const ComponentChoice& r : components.recoveries)
    parts.recoveries.push_back(at_choice(r, [&] { return find_recovery(r.name, r.field).make({robot, r.file}, r.settings); }));
  CostmapLayerContext layer_context;
  layer_context.geometry = config.geometry;
  layer_context.map = config.map;
  layer_context.prior_obstacles = config.prior_obstacles;
  layer_context.robot = robot;
  for (const ComponentChoice& l : components.layers) {
    layer_context.file = l.file;
    parts.layers.push_back(at_choice(l, [&] { return find_costmap_layer(l.name, l.field).make(layer_context, l.settings); }));
  }
  return parts;
}

namespace {

// The navigator of a scenario with its parts from the registry; errors about a goal name the
// goal's line.
std::unique_ptr<Navigator> make_navigator(const ScenarioSpec& spec, const NavigatorConfig& config,
                                          const NavigationComponents& components, const NavigationOptions& options = {}) {
  NavigatorParts parts = make_navigator_parts(components, config, spec.vehicle.robot, spec.seed);
  std::string controller_name = components.controller.name;
  if (options.make_controller) {
    parts.controller = options.make_controller({spec.vehicle.robot, spec.file, config.geometry.resolution, spec.seed});
    if (!parts.controller) throw Error("no controller was made", spec.file, 0, "navigation.controller");
    parts.controller_capabilities = options.controller_capabilities;
    controller_name = std::string(parts.controller->name());
  }
  const ScenarioGoal& first = spec.navigation->goals.front();
  // Every goal's heading must suit the controller, not only the first's (the first goal's is
  // checked by the navigator itself below).
  for (const ScenarioGoal& g : spec.navigation->goals) {
    if (&g == &first || !g.yaw_rad) continue;
    if (!parts.controller_capabilities.has(Capability::GoalHeading))
      throw Error("the " + controller_name + " controller cannot turn to a goal heading (give the goal without yaw_deg)",
                  spec.file, g.source.line, g.source.field + ".yaw_deg");
  }
  std::unique_ptr<Navigator> nav;
  try {
    nav = std::make_unique<Navigator>(config, spec.vehicle.robot, std::move(parts), first.position, first.yaw_rad);
  } catch (const Error& e) {
    if (e.file().empty() && e.field().rfind("navigation.goal", 0) == 0)
      throw Error(e.message(), spec.file, first.source.line, first.source.field + e.field().substr(15));
    if (e.file().empty() && e.field() == "navigation.planner")
      throw Error(e.message(), components.planner.file, components.planner.line, components.planner.field);
    throw;
  }
  return nav;
}

}  // namespace

LidarScan scan_placed_at(const LidarScan& scan, const Pose2& truth, const Pose2& estimate) {
  // The rigid motion taking the true pose to the estimate, applied to everything world-framed.
  const double dyaw = wrap_angle(estimate.yaw - truth.yaw);
  const double c = std::cos(dyaw), s = std::sin(dyaw);
  const auto place = [&](const Vec3& p) {
    const double dx = p.x() - truth.x, dy = p.y() - truth.y;
    return Vec3(estimate.x + c * dx - s * dy, estimate.y + s * dx + c * dy, p.z());
  };
  LidarScan out = scan;
  for (Vec3& p : out.points_world) p = place(p);
  out.sensor_pose.position = place(scan.sensor_pose.position);
  out.sensor_pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(dyaw, Vec3::UnitZ())) * scan.sensor_pose.orientation;
  return out;
}

void check_navigation_scenario(const ScenarioSpec& spec) {
  if (!spec.navigation) return;
  WorldDescription empty;
  NavigationComponents components;
  const NavigatorConfig c = navigator_config(spec, empty, {}, nullptr, &components);
  // Building the components validates their parameters (and the motion mode against the drive).
  make_navigator(spec, c, components);
  const LocalizationConfig l = localization_config(spec);
  const LocalizerContext ctx = localizer_context(spec);
  // Without its map (not loaded here) a map-based localizer still checks its parameters.
  find_localizer(l.localizer.name).make(ctx, l.localizer.settings);
  if (l.odometry_filter) find_localizer(l.odometry_filter->name).make(ctx, l.odometry_filter->settings);
}

NavigationRun::NavigationRun(const ScenarioSpec& spec, const NavigationOptions& options)
    : spec_(spec), options_(options) {
  const auto t0 = Clock::now();
  if (!spec_.navigation)
    throw Error("not a navigation scenario (no navigation section)", spec_.file, 0, "navigation");
  const WorldDescription world = build_world(spec_);
  NavigationComponents components;
  const NavigatorConfig config = navigator_config(spec_, world, options_, &settings_, &components);
  localization_ = localization_config(spec_);
  sim_ = std::make_unique<Simulation>(spec_, world);
  nav_ = make_navigator(spec_, config, components, options_);
  if (options_.record_steps) {
    const std::span<const std::int8_t> cells = nav_->map().occupancy().data();
    initial_occupancy_.assign(cells.begin(), cells.end());
  }
  CommandArbiterConfig arbiter = settings_.bumper;
  arbiter.bumper_stop = arbiter.bumper_stop && spec_.bumper;
  arbiter_ = std::make_unique<CommandArbiter>(arbiter, spec_.navigation->manual);
  // The pose the navigator uses: the localizer's, after it has seen the truth (simulation only).
  const auto localized = [this](double t) { return chain_->pose(t); };

  // More LiDARs (a rear one) feed the map; the first one's scans drive the cycle. Both after the
  // localization chain's estimators (SampleStage::Estimate) have seen the scan.
  for (const ScenarioLidar& other : spec_.other_lidars) {
    sim_->lidar_feed(other.stream).subscribe(SampleStage::Navigate, [this, localized](const LidarScan& truth_scan) {
      const Pose2 pose = localized(sim_->time());
      const Pose2 truth = sim_->vehicle().state().pose.to_pose2();
      if (pose.x != truth.x || pose.y != truth.y || pose.yaw != truth.yaw) nav_->add_scan(scan_placed_at(truth_scan, truth, pose));
      else nav_->add_scan(truth_scan);
    });
  }
  sim_->lidar_feed("lidar").subscribe(SampleStage::Navigate, [this, localized](const LidarScan& truth_scan) {
    const Pose3 pose3 = sim_->vehicle().state().pose;
    const double t = sim_->time();
    const Pose2 pose = localized(t);
    // The robot places its returns with the pose it believes, not the truth.
    const Pose2 truth = pose3.to_pose2();
    std::optional<LidarScan> placed;
    if (pose.x != truth.x || pose.y != truth.y || pose.yaw != truth.yaw) placed = scan_placed_at(truth_scan, truth, pose);
    const LidarScan& scan = placed ? *placed : truth_scan;
    NavCycle cycle = nav_->on_scan(scan, pose, t);
    if (options_.record_steps) {
      NavStepRecord r;
      r.t_s = t;
      r.pose = pose3;
      r.returns = scan.points_world.size();
      const LayeredCostmap& map = nav_->map();
      if (options_.step_all_hits) {
        r.hits = scan.points_world;
      } else {
        // One hit per obstacle cell (its highest return this scan), the paper's "laser lines that
        // have detected obstacles": enough for a viewer at a fraction of the bytes.
        std::vector<std::pair<std::size_t, Vec3>> top;
        for (const Vec3& p : scan.points_world) {
          const auto c = map.geometry().world_to_cell(p.head<2>());
          if (c && map.raw_blocked(c->x, c->y)) top.emplace_back(map.geometry().index(c->x, c->y), p);
        }
        std::stable_sort(top.begin(), top.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (std::size_t i = 0; i < top.size();) {
          std::size_t j = i;
          Vec3 best = top[i].second;
          for (; j < top.size() && top[j].first == top[i].first; ++j)
            if (top[j].second.z() > best.z()) best = top[j].second;
          r.hits.push_back(best);
          i = j;
        }
      }
      const OccupancyGrid& occ = map.occupancy();
      for (const Cell& c : cycle.update.occupancy_changed) r.changed.emplace_back(c, occ.at(c.x, c.y));
      r.path_id = nav_->plans().empty() ? 0 : nav_->plans().back().id;
      r.new_path = cycle.planned;
      if (spec_.localization) {
        r.estimate = pose;
        r.particles = chain_->localizer().belief_samples(options_.step_particles);
      }
      steps_.push_back(std::move(r));
      if (options_.on_step_line) options_.on_step_line(step_json_line(*this, steps_.back()));
    }
    if (nav_->status() == NavStatus::NoPath) sim_->stop();
  });
  // Several goals, laps or a goal heading: each arrival is measured once the robot is at rest.
  const ScenarioNavigation& n = *spec_.navigation;
  const bool measured = n.goals.size() > 1 || n.laps > 1 ||
                        std::any_of(n.goals.begin(), n.goals.end(), [](const ScenarioGoal& g) { return g.yaw_rad.has_value(); });
  const std::size_t total = n.goals.size() * static_cast<std::size_t>(n.laps);
  sim_->command_source = [this, localized, measured, total](double t) {
    const Pose2 pose = localized(t);
    const VehicleState& state = sim_->vehicle().state();
    if (settling_) {
      NavArrival& a = arrivals_.back();
      const bool at_rest = std::hypot(state.twist.vx, state.twist.vy) <= settings_.settle_speed_mps &&
                           std::abs(state.twist.wz) <= 10.0 * settings_.settle_speed_mps;
      if (!at_rest && t - a.t_s < settings_.settle_max_s) return BodyTwist{};
      settling_ = false;
      a.settled_t_s = t;
      a.truth = state.pose.to_pose2();
      a.estimate = pose;
      if (++goal_index_ >= total) {
        sim_->stop();
        return BodyTwist{};
      }
      const ScenarioGoal& g = spec_.navigation->goals[goal_index_ % spec_.navigation->goals.size()];
      nav_->set_goal(g.position, g.yaw_rad);
      return BodyTwist{};
    }
    const CommandArbiter::Decision d = arbiter_->decide(t, sim_->vehicle().bumper_contact());
    if (d.source != CommandSource::Autonomous) {
      nav_->hold(t);
      return d.twist;
    }
    const BodyTwist cmd = nav_->command(pose, t, state.twist);
    if (snapshots_.size() < options_.controller_snapshot_times_s.size() &&
        t >= options_.controller_snapshot_times_s[snapshots_.size()] - 1e-9) {
      // The controller's step of this instant (a controller with a period computes only at its ticks).
      std::optional<ControlDiagnostics> step = nav_->controller().diagnostics();
      if (step && step->t_s == t) {
        ControllerSnapshot snap;
        snap.step = std::move(*step);
        snap.local_map = crop_map(nav_->map().raw_occupancy(), pose.translation(), 4.0);
        snap.path = nav_->controller().path();
        snap.footprint = footprint_of(spec_.vehicle.robot);
        snapshots_.push_back(std::move(snap));
      }
    }
    if (nav_->status() == NavStatus::Arrived) {
      const ScenarioGoal& g = spec_.navigation->goals[goal_index_ % spec_.navigation->goals.size()];
      NavArrival a;
      a.goal = static_cast<int>(goal_index_ % spec_.navigation->goals.size());
      a.lap = static_cast<int>(goal_index_ / spec_.navigation->goals.size());
      a.t_s = a.settled_t_s = t;
      a.goal_pose = Pose2(g.position.x(), g.position.y(), g.yaw_rad.value_or(0.0));
      a.has_yaw = g.yaw_rad.has_value();
      a.truth = state.pose.to_pose2();
      a.estimate = pose;
      arrivals_.push_back(a);
      if (measured) {
        settling_ = true;
        return BodyTwist{};
      }
      sim_->stop();
      return BodyTwist{};
    }
    if (nav_->status() == NavStatus::NoPath) {
      sim_->stop();
      return BodyTwist{};
    }
    if (nav_->status() == NavStatus::Navigating && nav_->controller().has_path()) {
      // Deviation of the robot itself (ground truth) from the path it follows.
      const double dev = nav_->distance_to_path(state.pose.to_pose2().translation());
      deviation_sum_ += dev;
      deviation_max_ = std::max(deviation_max_, dev);
      ++deviation_n_;
    }
    return cmd;
  };
  if (!options_.controller_snapshot_times_s.empty()) {
    nav_->controller().keep_diagnostics(true);
    if (!nav_->controller().diagnostics())
      throw Error("the " + std::string(nav_->controller().name()) + " controller gives no diagnostics to draw", "", 0,
                  "--controller-pictures");
    std::sort(options_.controller_snapshot_times_s.begin(), options_.controller_snapshot_times_s.end());
  }
  // Its estimators see each sample before the navigation does (SampleStage::Estimate).
  chain_ = std::make_unique<LocalizationChain>(*sim_, localization_);
  setup_s_ = seconds_since(t0);
}

NavigationRun::~NavigationRun() = default;

double NavArrival::error_yaw_rad() const { return has_yaw ? wrap_angle(truth.yaw - goal_pose.yaw) : 0.0; }

void NavigationRun::run(const std::function<void(double)>& progress) {
  const auto t0 = Clock::now();
  sim_->run(progress);
  wall_s_ += seconds_since(t0);
}

NavigationMetrics NavigationRun::metrics() const {
  NavigationMetrics m;
  const SimulationMetrics s = sim_->metrics();
  const Navigator& nav = *nav_;
  const ScenarioNavigation& n = *spec_.navigation;
  m.goals_total = static_cast<int>(n.goals.size()) * n.laps;
  m.arrivals = static_cast<int>(arrivals_.size());
  m.success = m.arrivals == m.goals_total && !settling_;
  m.outcome = m.success ? "arrived" : nav.status() == NavStatus::NoPath ? "no_path" : "timeout";
  for (const NavEvent& e : nav.events())
    if (e.kind == "recovery" && (e.detail == "controller_blocked" || e.detail == "no_progress")) ++m.recoveries;
  for (const ArbiterEvent& e : arbiter_->events())
    if (e.kind == "bumper_stop") ++m.bumper_stops;
  m.reason = nav.no_path_reason();
  m.time_to_goal_s = m.success ? arrivals_.back().t_s : -1.0;
  m.duration_s = s.duration_s;
  m.distance_m = s.distance_m;
  m.plans = static_cast<int>(nav.plans().size());
  m.replans = std::max(0, m.plans - 1);
  for (std::size_t i = 0; i < nav.plans().size(); ++i) {
    const NavPlan& p = nav.plans()[i];
    m.expanded_total += p.expanded;
    if (i > 0) {
      m.replan_expanded += p.expanded;
      m.astar_replan_expanded += p.astar_expanded;
      m.astar_backward_replan_expanded += p.astar_backward_expanded;
    }
    const auto differs = [&](const std::string& status, double cost) {
      return status != "found" || std::abs(cost - p.cost_m) > 1e-9 * std::max(1.0, p.cost_m);
    };
    if (p.compared && p.status == "found" &&
        (differs(p.astar_status, p.astar_cost_m) || differs(p.astar_backward_status, p.astar_backward_cost_m)))
      m.costs_match = false;
  }
  m.collisions = s.collisions;
  if (deviation_n_ > 0) {
    m.deviation_mean_m = deviation_sum_ / static_cast<double>(deviation_n_);
    m.deviation_max_m = deviation_max_;
  }
  m.goal_distance_m = (s.final_state.position.head<2>() - nav.goal()).norm();
  m.planner = std::string(nav.planner().name());
  m.controller = std::string(nav.controller().name());
  m.motion_mode = nav.controller().motion_mode().empty() ? "none" : nav.controller().motion_mode();
  return m;
}

std::string navigation_metrics_json(const NavigationRun& run) {
  const NavigationMetrics m = run.metrics();
  nlohmann::ordered_json j;
  j["scenario"] = run.spec().name;
  j["seed"] = run.spec().seed;
  j["planner"] = m.planner;
  j["motion_mode"] = m.motion_mode;
  // Only when it is not the default controller (the paper's follower), so the records of the
  // paper's runs keep their bytes.
  if (m.controller != NavigationSettings{}.controller) j["controller"] = m.controller;
  j["success"] = m.success;
  j["outcome"] = m.outcome;
  if (!m.reason.empty()) j["reason"] = m.reason;
  j["time_to_goal_s"] = m.time_to_goal_s;
  j["duration_s"] = m.duration_s;
  j["distance_m"] = m.distance_m;
  j["goal_distance_m"] = m.goal_distance_m;
  j["plans"] = m.plans;
  j["replans"] = m.replans;
  j["expanded_total"] = m.expanded_total;
  j["replan_expanded"] = m.replan_expanded;
  if (run.navigator().config().compare_astar) {
    j["astar_replan_expanded"] = m.astar_replan_expanded;
    j["astar_backward_replan_expanded"] = m.astar_backward_replan_expanded;
    j["costs_match_astar"] = m.costs_match;
  }
  j["collisions"] = m.collisions;
  // Only where they say something, so the records of the paper's single-goal runs keep their bytes.
  if (m.goals_total > 1 || (!run.arrivals().empty() && run.arrivals().front().has_yaw)) {
    j["goals_total"] = m.goals_total;
    j["arrivals"] = m.arrivals;
  }
  if (m.recoveries > 0) j["recoveries"] = m.recoveries;
  if (m.bumper_stops > 0) j["bumper_stops"] = m.bumper_stops;
  j["deviation_mean_m"] = m.deviation_mean_m;
  j["deviation_max_m"] = m.deviation_max_m;
  const Navigator& nav = run.navigator();
  j["map"] = {{"width", nav.map().width()},
              {"height", nav.map().height()},
              {"resolution_m", nav.map().geometry().resolution},
              {"barrier_distance_m", nav.config().map.barrier_distance_m}};
  nlohmann::ordered_json sim = nlohmann::ordered_json::parse(metrics_json(run.simulation()));
  j["sim"] = sim;
  return j.dump(2) + "\n";
}

std::string paths_csv(const NavigationRun& run) {
  std::string out = "plan_id,t_s,x_m,y_m\n";
  for (const NavPlan& p : run.navigator().plans())
    for (const Vec2& v : p.points)
      out += std::to_string(p.id) + ',' + format_fixed6(p.t_s) + ',' + format_fixed6(v.x()) + ',' + format_fixed6(v.y()) + '\n';
  return out;
}

namespace {

std::string arrivals_csv(const NavigationRun& run) {
  std::string out =
      "goal,lap,t_s,settled_t_s,goal_x_m,goal_y_m,goal_yaw_deg,x_m,y_m,yaw_deg,est_x_m,est_y_m,est_yaw_deg,error_x_m,error_y_m,"
      "error_yaw_deg\n";
  for (const NavArrival& a : run.arrivals()) {
    const auto deg = [](double r) { return format_fixed6(rad_to_deg(r)); };
    out += std::to_string(a.goal) + ',' + std::to_string(a.lap) + ',' + format_fixed6(a.t_s) + ',' + format_fixed6(a.settled_t_s) +
           ',' + format_fixed6(a.goal_pose.x) + ',' + format_fixed6(a.goal_pose.y) + ',' + (a.has_yaw ? deg(a.goal_pose.yaw) : "") +
           ',' + format_fixed6(a.truth.x) + ',' + format_fixed6(a.truth.y) + ',' + deg(a.truth.yaw) + ',' +
           format_fixed6(a.estimate.x) + ',' + format_fixed6(a.estimate.y) + ',' + deg(a.estimate.yaw) + ',' +
           format_fixed6(a.error_x_m()) + ',' + format_fixed6(a.error_y_m()) + ',' + (a.has_yaw ? deg(a.error_yaw_rad()) : "") + '\n';
  }
  return out;
}

// The navigator's events and the command sources' changes, in time order.
std::string nav_events_csv(const NavigationRun& run) {
  std::vector<std::pair<double, std::string>> rows;
  for (const NavEvent& e : run.navigator().events()) rows.emplace_back(e.t_s, e.kind + ',' + e.detail);
  for (const ArbiterEvent& e : run.arbiter().events()) rows.emplace_back(e.t_s, "command_source," + e.kind);
  std::stable_sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string out = "t_s,kind,detail\n";
  for (const auto& [t, rest] : rows) out += format_fixed6(t) + ',' + rest + '\n';
  return out;
}

std::string replans_csv(const NavigationRun& run) {
  const bool compare = run.navigator().config().compare_astar;
  std::string out = "plan_id,t_s,cause,status,expanded,cost_m";
  if (compare) out += ",astar_status,astar_expanded,astar_cost_m,astar_backward_expanded,astar_backward_cost_m";
  out += '\n';
  for (const NavPlan& p : run.navigator().plans()) {
    out += std::to_string(p.id) + ',' + format_fixed6(p.t_s) + ',' + p.cause + ',' + p.status + ',' +
           std::to_string(p.expanded) + ',' + format_fixed6(p.cost_m);
    if (compare)
      out += ',' + p.astar_status + ',' + std::to_string(p.astar_expanded) + ',' + format_fixed6(p.astar_cost_m) + ',' +
             std::to_string(p.astar_backward_expanded) + ',' + format_fixed6(p.astar_backward_cost_m);
    out += '\n';
  }
  return out;
}


std::string steps_jsonl(const NavigationRun& run) {
  std::string out;
  for (const NavStepRecord& r : run.steps()) out += step_json_line(run, r) + '\n';
  return out;
}

}  // namespace

std::string step_json_line(const NavigationRun& run, const NavStepRecord& r) {
  const std::vector<Vec2>* path = nullptr;
  if (r.new_path && r.path_id > 0) path = &run.navigator().plans()[static_cast<std::size_t>(r.path_id - 1)].points;
  return step_record_json(r, path);
}

std::string step_record_json(const NavStepRecord& r, const std::vector<Vec2>* new_path) {
  nlohmann::ordered_json j;
  j["t_s"] = round_mm(r.t_s);
  const Vec3 rpy = r.pose.rpy();
  j["pose"] = {round_mm(r.pose.position.x()), round_mm(r.pose.position.y()), round_mm(r.pose.position.z()),
               round_mm(rpy.x()),             round_mm(rpy.y()),             round_mm(rpy.z())};
  j["returns"] = r.returns;
  nlohmann::ordered_json hits = nlohmann::ordered_json::array();
  for (const Vec3& p : r.hits) hits.push_back({round_cm(p.x()), round_cm(p.y()), round_cm(p.z())});
  j["hits"] = std::move(hits);
  nlohmann::ordered_json changed = nlohmann::ordered_json::array();
  for (const auto& [c, v] : r.changed) changed.push_back({c.x, c.y, static_cast<int>(v)});
  j["changed"] = std::move(changed);
  j["path_id"] = r.path_id;
  if (new_path) {
    nlohmann::ordered_json path = nlohmann::ordered_json::array();
    for (const Vec2& v : *new_path) path.push_back({round_mm(v.x()), round_mm(v.y())});
    j["path"] = std::move(path);
  }
  if (r.estimate) j["estimate"] = {round_mm(r.estimate->x), round_mm(r.estimate->y), round_mm(wrap_angle(r.estimate->yaw))};
  if (!r.particles.empty()) {
    nlohmann::ordered_json particles = nlohmann::ordered_json::array();
    for (const Pose2& p : r.particles) particles.push_back({round_cm(p.x), round_cm(p.y), round_cm(wrap_angle(p.yaw))});
    j["particles"] = std::move(particles);
  }
  if (r.reference) j["reference"] = {round_mm(r.reference->x), round_mm(r.reference->y), round_mm(wrap_angle(r.reference->yaw))};
  return j.dump();
}

void write_navigation_records(const NavigationRun& run, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path d(dir);
  write_simulation_records(run.simulation(), dir);  // trajectory.csv, events.csv, sensors; metrics.json replaced below
  write_file_bytes((d / "metrics.json").string(), navigation_metrics_json(run));
  write_file_bytes((d / "paths.csv").string(), paths_csv(run));
  write_file_bytes((d / "replans.csv").string(), replans_csv(run));
  if (run.spec().localization) write_file_bytes((d / "estimate.csv").string(), estimate_csv(run.localization_chain().records()));
  if (run.options().record_steps) write_file_bytes((d / "steps.jsonl").string(), steps_jsonl(run));
  const ScenarioNavigation& n = *run.spec().navigation;
  if (n.goals.size() > 1 || n.laps > 1 || std::any_of(n.goals.begin(), n.goals.end(), [](const ScenarioGoal& g) { return g.yaw_rad.has_value(); }))
    write_file_bytes((d / "arrivals.csv").string(), arrivals_csv(run));
  if (!run.navigator().events().empty() || !run.arbiter().events().empty())
    write_file_bytes((d / "nav_events.csv").string(), nav_events_csv(run));
  write_ros_map(run.navigator().map().occupancy(), (d / "map.yaml").string());

  const SimulationMetrics s = run.simulation().metrics();
  nlohmann::ordered_json t;
  t["wall_s"] = run.wall_s();
  t["setup_s"] = run.setup_s();
  t["sim_s"] = s.duration_s;
  t["real_time_factor"] = run.wall_s() > 0.0 ? s.duration_s / run.wall_s() : 0.0;
  t["steps"] = s.steps;
  t["lidar_rays"] = s.lidar_rays;
  double plan_ms = 0.0;
  nlohmann::ordered_json per_plan = nlohmann::ordered_json::array();
  for (const NavPlan& p : run.navigator().plans()) {
    plan_ms += p.time_ms;
    per_plan.push_back(p.time_ms);
  }
  t["planning_ms"] = plan_ms;
  t["plan_ms"] = std::move(per_plan);  // wall time of each plan's search, by plan_id (replans.csv)
  write_file_bytes((d / "timing.json").string(), t.dump(2) + "\n");
}

}  // namespace starnav
