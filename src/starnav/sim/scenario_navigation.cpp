// The scenario's driving sections: the command script, the route, events, the navigation and
// localization sections (whose component parameters the navigation harness checks).
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/sim/scenario_document.hpp"

namespace starnav::scenario_detail {

namespace {

struct CommandKeys {
  double duration_s = 0.0, until_s = 0.0;
  BodyTwist twist;
};

const SectionDecl<CommandKeys>& command_decl() {
  static const SectionDecl<CommandKeys> d = [] {
    SectionDecl<CommandKeys> s;
    s.id = "commands";
    s.title = "commands[i]";
    const auto t = [](double BodyTwist::*member) { return [member](CommandKeys& k) -> double& { return k.twist.*member; }; };
    s.table.real("duration_s", &CommandKeys::duration_s, positive(), "s", "the segment lasts this long after the previous one's end")
        .real("until_s", &CommandKeys::until_s, any_value(), "s",
              "instead of duration_s: the segment ends at this time (later than the previous end)")
        .real("vx_mps", t(&BodyTwist::vx), any_value(), "m/s", "forward speed (base_link)")
        .real("vy_mps", t(&BodyTwist::vy), any_value(), "m/s", "leftward speed")
        .real("wz_radps", t(&BodyTwist::wz), any_value(), "rad/s", "turn rate, counter-clockwise");
    s.table.default_rule("duration_s", "one of the two").default_rule("until_s", "one of the two");
    return s;
  }();
  return d;
}

const SectionDecl<ScenarioRoute>& route_decl() {
  static const SectionDecl<ScenarioRoute> d = [] {
    SectionDecl<ScenarioRoute> s;
    s.id = "route";
    s.title = "route";
    s.structural = {{"waypoints_m", "list of [x, y]", "required", "at least 2 points", "m", "the loop's waypoints", true}};
    s.table.real("speed_mps", &ScenarioRoute::speed_mps, positive(), "m/s", "driving speed")
        .integer("laps", &ScenarioRoute::laps, closed(1, 1000), "", "closed loops through the waypoints")
        .real("clearance_m", &ScenarioRoute::clearance_m, non_negative(), "m", "obstacle inflation of the planned paths");
    return s;
  }();
  return d;
}

struct EventKeys {
  double t_s = 0.0;
};

const SectionDecl<EventKeys>& event_decl() {
  static const SectionDecl<EventKeys> d = [] {
    SectionDecl<EventKeys> s;
    s.id = "events";
    s.title = "events[i]";
    s.table.real("t_s", &EventKeys::t_s, non_negative(), "s", "when (events in time order)");
    s.required = {"t_s"};
    s.structural = {{"teleport", "mapping", "required", "", "", "the pose the robot is carried to (events[i].teleport)"}};
    return s;
  }();
  return d;
}

struct PoseKeys {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
};

SectionDecl<PoseKeys> pose_decl(const std::string& id, const std::string& yaw_doc) {
  SectionDecl<PoseKeys> s;
  s.id = id;
  s.title = id;
  s.table.real("x_m", &PoseKeys::x_m, any_value(), "m", "x in the world frame")
      .real("y_m", &PoseKeys::y_m, any_value(), "m", "y in the world frame")
      .real("yaw_deg", &PoseKeys::yaw_rad, any_value(), "deg", yaw_doc, kDeg);
  return s;
}

const SectionDecl<PoseKeys>& teleport_decl() {
  static const SectionDecl<PoseKeys> d = pose_decl("events.teleport", "heading, counter-clockwise from +x");
  return d;
}

const SectionDecl<PoseKeys>& goal_decl() {
  static const SectionDecl<PoseKeys> d = [] {
    SectionDecl<PoseKeys> s = pose_decl("navigation.goal",
                                        "the heading to arrive with, for a controller that can turn to it (dwa); none by default");
    s.title = "navigation.goal (and each of navigation.goals)";
    s.required = {"x_m", "y_m"};
    s.table.default_rule("yaw_deg", "none");
    return s;
  }();
  return d;
}

struct NavigationKeys {
  int laps = 1;
};

const SectionDecl<NavigationKeys>& navigation_decl() {
  static const SectionDecl<NavigationKeys> d = [] {
    SectionDecl<NavigationKeys> s;
    s.id = "navigation";
    s.title = "navigation (its own keys; the components' are in docs/parameters.md)";
    s.structural = {
        {"goal", "mapping", "required (or goals)", "", "", "where to go (navigation.goal)", true},
        {"goals", "list of mappings", "", "1 to 1,000", "", "instead of goal: goals visited in order", true},
    };
    s.table.integer("laps", &NavigationKeys::laps, closed(1, 1000), "", "the goals are visited this many times over");
    s.structural.push_back({"manual", "list of mappings", "none", "", "",
                            "timed manual commands (a joystick), in time order (navigation.manual[i])"});
    return s;
  }();
  return d;
}

struct ManualKeys {
  double t_s = 0.0, duration_s = 0.0, vx = 0.0, vy = 0.0, wz_rad = 0.0;
};

const SectionDecl<ManualKeys>& manual_decl() {
  static const SectionDecl<ManualKeys> d = [] {
    SectionDecl<ManualKeys> s;
    s.id = "navigation.manual";
    s.title = "navigation.manual[i]";
    s.table.real("t_s", &ManualKeys::t_s, closed(0.0, 1e6), "s", "start")
        .real("duration_s", &ManualKeys::duration_s, ParamRange{0.0, 1e6, true, false}, "s", "length")
        .real("vx_mps", &ManualKeys::vx, closed(-10.0, 10.0), "m/s", "forward speed (base_link)")
        .real("vy_mps", &ManualKeys::vy, closed(-10.0, 10.0), "m/s", "leftward speed")
        .real("wz_degps", &ManualKeys::wz_rad, closed(-20.0 / kDeg, 20.0 / kDeg), "deg/s", "turn rate, counter-clockwise", kDeg);
    s.required = {"t_s", "duration_s"};
    return s;
  }();
  return d;
}

// A sequence of lower_snake_case names (component names), perhaps empty.
bool is_name_list(const YAML::Node& node) {
  for (const YAML::Node& item : node) {
    if (!item.IsScalar()) return false;
    const std::string& name = item.Scalar();
    if (name.empty() || !(name[0] >= 'a' && name[0] <= 'z')) return false;
    for (const char ch : name)
      if (!((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_')) return false;
  }
  return true;
}

// Every value of `f` not taken yet, as a setting with its dotted key (relative to `prefix`) and
// line, sections recursively; the navigation stack checks them against its components' declared
// parameters.
void collect_settings(Fields& f, const std::string& prefix, std::vector<ParamSetting>& out) {
  for (const std::string& k : f.keys()) {
    if (f.taken(k)) continue;
    const Value e = *f.take(k.c_str());
    const std::string key = prefix.empty() ? k : prefix + "." + k;
    if (e.node().IsMap()) {
      Fields section(e, f.doc());
      collect_settings(section, key, out);
    } else if (e.node().IsScalar()) {
      out.push_back(setting_of(e, key));
    } else if (e.node().IsSequence() && is_name_list(e.node())) {
      // A list of names (navigation.recoveries: [rotate, back_up]) as one setting "rotate, back_up".
      ParamSetting s = setting_of(e, key);
      s.value.clear();
      for (std::size_t i = 0; i < e.node().size(); ++i) s.value += (i ? ", " : "") + e.node()[i].Scalar();
      out.push_back(std::move(s));
    } else if (e.node().IsSequence() && is_value_list(e.node())) {
      // Nested lists of values (polygons: [[[0, 0], [1, 0], [1, 1]]]) in flow form; the
      // parameter's own parser reads the shape.
      ParamSetting s = setting_of(e, key);
      s.value = flow_text(e.node());
      out.push_back(std::move(s));
    } else {
      e.fail("expected a value, a section of values or a list (of names or of lists of numbers), found " + node_kind(e.node()));
    }
  }
}

ScenarioGoal parse_goal(const Value& g) {
  ScenarioGoal goal;
  goal.source = {g.line(), g.field()};
  Fields gf(g, g.doc());
  require_all(gf, goal_decl());
  PoseKeys p;
  apply_section(gf, goal_decl(), p);
  goal.position = Vec2(p.x_m, p.y_m);
  if (gf.has("yaw_deg")) goal.yaw_rad = p.yaw_rad;
  return goal;
}

}  // namespace

void parse_commands(const Value& v, ScenarioSpec& s) {
  if (!v.node().IsSequence()) v.fail("expected a list of command segments, found " + node_kind(v.node()));
  double t = 0.0;
  for (std::size_t i = 0; i < v.node().size(); ++i) {
    const Value e = v.element(i);
    if (e.node().IsNull()) e.fail("expected a segment {duration_s or until_s, vx_mps, vy_mps, wz_radps}");
    Fields f(e, v.doc());
    CommandSegment c;
    c.line = e.line();
    c.start_s = t;
    const bool has_d = f.has("duration_s"), has_u = f.has("until_s");
    if (has_d == has_u) e.fail("give exactly one of duration_s or until_s");
    CommandKeys k;
    apply_section(f, command_decl(), k);
    if (has_d) {
      c.end_s = t + k.duration_s;
      // The sum can overflow to infinity, or a tiny duration can vanish beside a large t.
      if (!std::isfinite(c.end_s))
        f.fail_at("duration_s", "the script's end overflows (" + Value::fmt(t) + " s + " + Value::fmt(k.duration_s) + " s)");
      if (!(c.end_s > t)) f.fail_at("duration_s", "too short to end after the previous segment's end (" + Value::fmt(t) + " s)");
    } else {
      c.end_s = k.until_s;
      if (!(c.end_s > t)) f.fail_at("until_s", "must be later than the previous segment's end (" + Value::fmt(t) + " s)");
    }
    c.twist = k.twist;
    t = c.end_s;
    s.commands.push_back(c);
  }
}

void parse_route(const Value& v, ScenarioSpec& s) {
  if (!s.commands.empty()) v.fail("a route and a command script: give one of them");
  Fields f(v, v.doc());
  ScenarioRoute r;
  r.source = {v.line(), v.field()};
  const Value w = f.required("waypoints_m");
  if (!w.node().IsSequence() || w.node().size() < 2) w.fail("expected a list of at least 2 points [x, y], found " + node_kind(w.node()));
  for (std::size_t i = 0; i < w.node().size(); ++i) {
    const auto p = w.element(i).numbers(2, 2);
    r.waypoints.emplace_back(p[0], p[1]);
  }
  apply_section(f, route_decl(), r);
  if (!s.occupancy_map) v.fail("a route is planned on world.occupancy_map, which the scenario lacks");
  s.route = r;
}

void parse_events(const Value& v, ScenarioSpec& s) {
  const std::size_t n = v.list("events");
  for (std::size_t i = 0; i < n; ++i) {
    const Value e = v.element(i);
    Fields f(e, v.doc());
    ScenarioTeleport t;
    t.source = {e.line(), e.field()};
    require_all(f, event_decl());
    EventKeys k;
    apply_section(f, event_decl(), k, {"t_s"});
    t.t_s = k.t_s;
    if (!s.teleports.empty() && t.t_s < s.teleports.back().t_s) e.fail("events must be in time order");
    const Value to = f.required("teleport");
    Fields g(to, v.doc());
    PoseKeys p;
    apply_section(g, teleport_decl(), p);
    t.to = Pose2(p.x_m, p.y_m, p.yaw_rad);
    apply_section(f, event_decl(), k);
    s.teleports.push_back(t);
  }
}

ScenarioNavigation parse_navigation(const Value& v) {
  ScenarioNavigation n;
  n.source = {v.line(), v.field()};
  Fields f(v, v.doc());
  auto one = f.take("goal");
  auto many = f.take("goals");
  if (one && many) many->fail("give either goal or goals, not both");
  if (one) {
    n.goals.push_back(parse_goal(*one));
  } else if (many) {
    if (!many->node().IsSequence() || many->node().size() < 1 || many->node().size() > 1000)
      many->fail("expected a list of 1 to 1,000 goals {x_m, y_m, yaw_deg}, found " + node_kind(many->node()));
    for (std::size_t i = 0; i < many->node().size(); ++i) n.goals.push_back(parse_goal(many->element(i)));
  } else {
    f.required("goal");  // the error names the missing field
  }
  n.goal = n.goals.front().position;
  n.goal_source = n.goals.front().source;
  NavigationKeys k;
  apply_section(f, navigation_decl(), k, {"laps"});
  n.laps = k.laps;
  if (auto m = f.take("manual")) {
    if (!m->node().IsSequence()) m->fail("expected a list of manual commands {t_s, duration_s, vx_mps, vy_mps, wz_degps}");
    for (std::size_t i = 0; i < m->node().size(); ++i) {
      const Value e = m->element(i);
      Fields mf(e, v.doc());
      ScenarioManualCommand c;
      c.source = {e.line(), e.field()};
      require_all(mf, manual_decl());
      ManualKeys mk;
      apply_section(mf, manual_decl(), mk);
      c.t_s = mk.t_s;
      c.duration_s = mk.duration_s;
      c.twist = {mk.vx, mk.vy, mk.wz_rad};
      if (!n.manual.empty() && c.t_s < n.manual.back().t_s + n.manual.back().duration_s)
        e.fail("manual commands must be in time order and must not overlap");
      n.manual.push_back(c);
    }
  }
  collect_settings(f, "", n.settings);  // everything else: the navigation's and its components' parameters
  return n;
}

ScenarioSettings parse_settings_section(const Value& v) {
  ScenarioSettings out;
  out.source = {v.line(), v.field()};
  if (!v.node().IsMap()) v.fail("expected a section (key: value lines), found " + node_kind(v.node()));
  Fields f(v, v.doc());
  collect_settings(f, "", out.settings);
  return out;
}

std::vector<ScenarioKeySection> navigation_sections() {
  return {command_decl().describe(),    route_decl().describe(), event_decl().describe(), teleport_decl().describe(),
          navigation_decl().describe(), goal_decl().describe(),  manual_decl().describe()};
}

}  // namespace starnav::scenario_detail
