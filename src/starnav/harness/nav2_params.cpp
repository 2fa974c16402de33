#include "starnav/harness/nav2_params.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

// A named namespace: the unity build puts this file beside others with helpers of the same names.
namespace nav2_detail {

constexpr std::uint64_t kMaxNav2FileBytes = std::uint64_t{16} << 20;

// One leaf of a node's ros__parameters, its dotted key relative to them.
struct Leaf {
  std::string key;  // "FollowPath.max_vel_x"
  std::string value;
  int line = 0;
  bool scalar = true;
};

// The value under `key` of a map node, or an undefined node (never yaml-cpp's invalid node, which
// throws on use).
YAML::Node child(const YAML::Node& n, const std::string& key) {
  if (!n.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  for (const auto& kv : n)
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.second;
  return YAML::Node(YAML::NodeType::Undefined);
}

void flatten(const YAML::Node& n, const std::string& prefix, std::vector<Leaf>& out, int depth) {
  if (depth > 16) throw Error("nested deeper than 16 maps", {}, n.Mark().line + 1);
  for (const auto& kv : n) {
    if (!kv.first.IsScalar()) throw Error("a key that is not a name", {}, kv.first.Mark().line + 1);
    const std::string key = prefix.empty() ? kv.first.Scalar() : prefix + "." + kv.first.Scalar();
    const YAML::Node& v = kv.second;
    if (v.IsMap()) {
      flatten(v, key, out, depth + 1);
    } else {
      std::string text;
      if (v.IsScalar()) {
        text = v.Scalar();
      } else if (v.IsSequence() && std::all_of(v.begin(), v.end(), [](const YAML::Node& e) { return e.IsScalar(); })) {
        // A list of names or numbers in full ("[a, b]"; MPPI's critics map from it).
        text = "[";
        for (std::size_t i = 0; i < v.size(); ++i) text += (i ? ", " : "") + v[i].Scalar();
        text += "]";
        if (text.size() > 4096) text = one_line(text, 80);
      } else if (v.IsSequence()) {
        std::ostringstream s;
        s << YAML::Dump(v);
        text = one_line(s.str(), 80);
      }
      out.push_back({key, text, v.Mark().line + 1, v.IsScalar()});
    }
  }
}

// The spec of a starnav key, for its range (null: not declared in a table starnav exposes).
std::optional<ParamSpec> spec_of(const std::string& key) {
  const auto find = [](const std::vector<ParamSpec>& specs, const std::string& k) -> std::optional<ParamSpec> {
    for (const ParamSpec& s : specs)
      if (s.key == k) return s;
    return std::nullopt;
  };
  const auto after = [&](const std::string& prefix) { return key.substr(prefix.size()); };
  // A component's key: ROOT.SECTION.KEY (localize's own: SECTION.KEY), found by its section.
  // (Prefixes built by append: g++ 12 warns falsely (-Wrestrict) on a literal + string here.)
  const auto prefixed = [](std::string_view root, const std::string& section) {
    std::string p(root);
    p.append(section).append(".");
    return p;
  };
  for (const ComponentInfo& c : all_components()) {
    const std::string own = prefixed("", c.section), in_localization = prefixed("localization.", c.section),
                      in_navigation = prefixed("navigation.", c.section);
    if (c.role == Role::Localizer && (key.rfind(in_localization, 0) == 0 || key.rfind(own, 0) == 0))
      return find(c.params, key.rfind(own, 0) == 0 ? after(own) : after(in_localization));
    if ((c.role == Role::LocalController || c.role == Role::GoalChecker) && key.rfind(in_navigation, 0) == 0) return find(c.params, after(in_navigation));
  }
  if (key == "navigation.map.barrier_distance_m") {
    ParamSpec s;
    s.key = "map.barrier_distance_m";
    s.range = non_negative();
    s.unit = "m";
    return s;
  }
  if (key.rfind("navigation.", 0) == 0) return find(navigation_params().specs(), after("navigation."));
  return std::nullopt;
}

struct Rule {
  Rule(std::string key = {}, double s = 1.0, std::string n = {}, bool inv = false)
      : starnav(std::move(key)), scale(s), note(std::move(n)), invert(inv) {}
  std::string starnav;  // the key relative to the target's root ("alpha1" for AMCL; the caller prefixes)
  double scale;         // starnav = nav2 * scale
  std::string note;     // "rad -> deg"
  bool invert;          // starnav = 1 / nav2 (Hz -> s)
};

const double kDeg = 180.0 / kPi;

const std::map<std::string, Rule>& amcl_rules() {
  static const std::map<std::string, Rule> r = {
      {"alpha1", {"alpha1"}}, {"alpha2", {"alpha2"}}, {"alpha3", {"alpha3"}}, {"alpha4", {"alpha4"}}, {"alpha5", {"alpha5"}},
      {"z_hit", {"z_hit"}}, {"z_rand", {"z_rand"}}, {"z_short", {"z_short"}}, {"z_max", {"z_max"}},
      {"sigma_hit", {"sigma_hit_m"}}, {"lambda_short", {"lambda_short"}},
      {"laser_likelihood_max_dist", {"laser_likelihood_max_dist_m"}},
      {"laser_max_range", {"laser_max_range_m"}}, {"laser_min_range", {"laser_min_range_m"}},
      {"max_beams", {"max_beams"}}, {"min_particles", {"min_particles"}}, {"max_particles", {"max_particles"}},
      {"pf_err", {"pf_err"}}, {"pf_z", {"pf_z"}},
      {"recovery_alpha_slow", {"recovery_alpha_slow"}}, {"recovery_alpha_fast", {"recovery_alpha_fast"}},
      {"resample_interval", {"resample_interval"}}, {"update_min_d", {"update_min_d_m"}},
      {"update_min_a", {"update_min_a_deg", kDeg, "rad -> deg"}},
  };
  return r;
}

// DWB (dwb_core::DWBLocalPlanner): its keys and its critics' scales.
const std::map<std::string, Rule>& dwb_rules() {
  static const std::map<std::string, Rule> r = {
      {"max_vel_x", {"max_vx_mps"}}, {"min_vel_x", {"min_vx_mps"}}, {"max_vel_y", {"max_vy_mps"}},
      {"max_speed_xy", {"max_speed_xy_mps"}}, {"max_vel_theta", {"max_yaw_rate_degps", kDeg, "rad/s -> deg/s"}},
      {"acc_lim_x", {"acc_x_mps2"}}, {"acc_lim_y", {"acc_y_mps2"}}, {"acc_lim_theta", {"acc_yaw_degps2", kDeg, "rad/s^2 -> deg/s^2"}},
      {"vx_samples", {"vx_samples"}}, {"vy_samples", {"vy_samples"}}, {"vtheta_samples", {"wz_samples"}},
      {"sim_time", {"sim_time_s"}},
      {"PathAlign.scale", {"path_align_weight"}}, {"PathDist.scale", {"path_dist_weight"}},
      {"GoalAlign.scale", {"goal_align_weight"}}, {"GoalDist.scale", {"goal_dist_weight"}},
      {"BaseObstacle.scale", {"obstacle_weight"}}, {"ObstacleFootprint.scale", {"obstacle_weight"}},
      {"Oscillation.scale", {"oscillation_weight"}}, {"RotateToGoal.scale", {"rotate_to_goal_weight"}},
      {"Twirling.scale", {"twirling_weight"}}, {"PreferForward.scale", {"prefer_forward_weight"}},
      {"PathAlign.forward_point_distance", {"forward_point_m"}}, {"GoalAlign.forward_point_distance", {"forward_point_m"}},
      {"Oscillation.oscillation_reset_dist", {"oscillation_reset_m"}},
      {"Oscillation.oscillation_reset_angle", {"oscillation_reset_deg", kDeg, "rad -> deg"}},
  };
  return r;
}

// Nav2's pure pursuit keys under the path follower's names (its pure_pursuit mode).
const std::map<std::string, Rule>& follower_pursuit_rules() {
  static const std::map<std::string, Rule> r = {
      {"desired_linear_vel", {"cruise_speed_mps"}},
      {"lookahead_dist", {"pursuit_look_ahead_m"}},
      {"rotate_to_heading_angular_vel", {"max_yaw_rate_degps", kDeg, "rad/s -> deg/s"}},
  };
  return r;
}

const std::string kPlumbing = "ROS plumbing (frames, topics, transforms, QoS, introspection): the log's or the simulator's own";

bool is_plumbing(const std::string& key) {
  static const char* words[] = {"frame", "topic", "tf_broadcast", "transform_tolerance", "introspection", "use_sim_time",
                                "save_pose_rate", "qos", "service", "timeout", "bond", "plugin"};
  for (const char* w : words)
    if (key.find(w) != std::string::npos) return true;
  return false;
}

// The rule for a Nav2 key of a controller that stands for Nav2's Regulated Pure Pursuit, from the
// keys the controller declares: its key of the same name, bare or with its unit's suffix (an angle
// given in degrees converted from Nav2's radians), else the path follower's name for it when the
// controller declares that. Nothing when the controller has no such key.
std::optional<Rule> pursuit_rule(const std::string& nav2_key, const std::vector<ParamSpec>& specs) {
  for (const ParamSpec& s : specs) {
    if (s.key == nav2_key) return Rule(s.key);
    if (s.key.size() <= nav2_key.size() + 1 || s.key.compare(0, nav2_key.size(), nav2_key) != 0 || s.key[nav2_key.size()] != '_') continue;
    const std::string suffix = s.key.substr(nav2_key.size() + 1);
    if (suffix == "m" || suffix == "mps" || suffix == "mps2" || suffix == "s" || suffix == "radps") return Rule(s.key);
    if (suffix == "deg" && s.unit == "deg") return Rule(s.key, kDeg, "rad -> deg");
    if (suffix == "degps" && s.unit == "deg/s") return Rule(s.key, kDeg, "rad/s -> deg/s");
    if (suffix == "degps2" && s.unit == "deg/s^2") return Rule(s.key, kDeg, "rad/s^2 -> deg/s^2");
  }
  const auto follower = follower_pursuit_rules().find(nav2_key);
  if (follower == follower_pursuit_rules().end()) return std::nullopt;
  for (const ParamSpec& s : specs)
    if (s.key == follower->second.starnav) return follower->second;
  return std::nullopt;
}

// The Nav2 plugins whose keys map onto the starnav component that declares it stands for them.
constexpr std::string_view kNav2Amcl = "nav2_amcl::AmclNode";
constexpr std::string_view kNav2Dwb = "dwb_core::DWBLocalPlanner";
constexpr std::string_view kNav2Rpp = "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController";
constexpr std::string_view kNav2Mppi = "nav2_mppi_controller::MPPIController";
constexpr std::string_view kNav2SimpleGoalChecker = "nav2_controller::SimpleGoalChecker";
constexpr std::string_view kNav2StoppedGoalChecker = "nav2_controller::StoppedGoalChecker";

// A Nav2 MPPI name in starnav's spelling: CamelCase to snake_case, a critic's "Critic" dropped
// (GoalCritic: goal; AckermannConstraints: ackermann_constraints; DiffDrive: diff_drive).
std::string mppi_name(std::string name) {
  if (name.size() > 6 && name.compare(name.size() - 6, 6, "Critic") == 0) name.resize(name.size() - 6);
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (c >= 'A' && c <= 'Z') {
      if (i > 0 && name[i - 1] != '_') out += '_';
      out += static_cast<char>(c - 'A' + 'a');
    } else {
      out += c;
    }
  }
  return out;
}

// The names of a YAML list as flatten() wrote it ("[\"GoalCritic\", ...]" on one line).
std::vector<std::string> list_names(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : text + ",") {
    if (c == ',' || c == '[' || c == ']') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else if (c != ' ' && c != '"' && c != '\'' && c != '-' && c != '\n') {
      cur += c;
    }
  }
  return out;
}

class Mapper {
 public:
  Mapper(std::string file, const Nav2Target& t) : target_(t) { p_.file = std::move(file); }

  void node(const std::string& nav2_node, const std::vector<Leaf>& leaves) {
    if (nav2_node == "amcl") return amcl(leaves);
    if (nav2_node == "controller_server") return controller(leaves);
    if (nav2_node == "local_costmap" || nav2_node == "global_costmap") return costmap(nav2_node, leaves);
    for (const Leaf& l : leaves) ignore(nav2_node, l, nav2_node + " is not a starnav component (starnav's navigation: docs/navigation.md)");
  }

  Nav2Params take() { return std::move(p_); }

 private:
  void ignore(const std::string& node, const Leaf& l, const std::string& why) { p_.ignored.push_back({node + "." + l.key, l.line, l.value, "", "", why}); }

  void map(const std::string& node, const Leaf& l, const std::string& key, const Rule& rule) {
    const std::string nav2 = node + "." + l.key;
    std::optional<ParamSpec> spec = spec_of(key);
    std::string converted = l.value;
    if (!spec || spec->type == ParamType::Real || spec->type == ParamType::Integer) {
      double v = 0;
      try {
        v = std::stod(l.value);
      } catch (const std::exception&) {
        throw Error("expected a number, got '" + printable(l.value, 40) + "'", p_.file, l.line, nav2 + " (" + key + ")");
      }
      if (!std::isfinite(v)) throw Error("not finite", p_.file, l.line, nav2 + " (" + key + ")");
      const double s = rule.invert ? (v != 0 ? 1.0 / v : std::numeric_limits<double>::infinity()) : v * rule.scale;
      if (spec && spec->type == ParamType::Integer) {
        if (s != std::floor(s)) throw Error("expected an integer, got " + l.value, p_.file, l.line, nav2 + " (" + key + ")");
        converted = std::to_string(static_cast<long long>(s));
      } else {
        converted = format_param_real(s);
      }
      if (spec && !spec->range.contains(s))
        throw Error(l.value + (rule.note.empty() ? "" : " (" + converted + " " + spec->unit + ")") + " is outside " + key + "'s range " +
                        spec->range.text() + (spec->unit.empty() ? "" : " " + spec->unit),
                    p_.file, l.line, nav2 + " (" + key + ")");
    }
    if (spec && spec->type == ParamType::Boolean) {
      // YAML's spellings of a ROS 2 bool; starnav's settings write true / false.
      if (l.value == "true" || l.value == "True" || l.value == "TRUE") converted = "true";
      else if (l.value == "false" || l.value == "False" || l.value == "FALSE") converted = "false";
      else throw Error("expected true or false, got '" + printable(l.value, 40) + "'", p_.file, l.line, nav2 + " (" + key + ")");
    }
    p_.mapped.push_back({nav2, l.line, l.value, key, converted, rule.note});
  }

  void map_choice(const std::string& node, const Leaf& l, const std::string& key, const std::string& value) {
    p_.mapped.push_back({node + "." + l.key, l.line, l.value, key, value, "'" + l.value + "' -> " + value});
  }

  // The section of the scenario's component of `role` when it stands for Nav2's `plugin` (its
  // declared counterpart), else nothing: Nav2's keys for that plugin map onto it.
  std::optional<ComponentInfo> component_standing_for(Role role, const std::string& name, std::string_view plugin) const {
    if (name.empty()) return std::nullopt;
    ComponentInfo info = find_component(role, name,
                                        role == Role::Localizer      ? "localization.localizer"
                                        : role == Role::GoalChecker ? "navigation.goal_checker"
                                                                    : "navigation.controller");
    if (info.nav2_counterpart != plugin) return std::nullopt;
    return info;
  }
  std::optional<std::string> section_standing_for(Role role, const std::string& name, std::string_view plugin) const {
    const auto info = component_standing_for(role, name, plugin);
    return info ? std::optional<std::string>(info->section) : std::nullopt;
  }
  std::optional<ComponentInfo> controller_info_standing_for(std::string_view plugin) const {
    if (!target_.navigation) return std::nullopt;
    return component_standing_for(Role::LocalController, target_.controller, plugin);
  }
  std::optional<std::string> controller_standing_for(std::string_view plugin) const {
    const auto info = controller_info_standing_for(plugin);
    return info ? std::optional<std::string>(info->section) : std::nullopt;
  }

  // "amcl." + key for localize (AMCL itself); "localization.SECTION." for a scenario whose
  // localizer stands for Nav2's AMCL.
  std::optional<std::string> amcl_root() const {
    if (target_.kind == Nav2Target::Kind::Localize) return std::string("amcl.");
    if (const auto section = section_standing_for(Role::Localizer, target_.localizer, kNav2Amcl)) return "localization." + *section + ".";
    return std::nullopt;
  }

  void amcl(const std::vector<Leaf>& leaves) {
    const std::optional<std::string> root = amcl_root();
    for (const Leaf& l : leaves) {
      if (!root) {
        ignore("amcl", l, "the scenario's localizer is " + (target_.localizer.empty() ? std::string("none") : target_.localizer) + ", not amcl");
        continue;
      }
      const auto rule = amcl_rules().find(l.key);
      if ((l.key == "laser_max_range" || l.key == "laser_min_range") && l.value.rfind("-1", 0) == 0) {
        ignore("amcl", l, "-1: the laser's own range, which is starnav's default too");
      } else if (rule != amcl_rules().end()) {
        map("amcl", l, *root + rule->second.starnav, rule->second);
      } else if (l.key == "laser_model_type") {
        if (l.value == "likelihood_field" || l.value == "beam") map_choice("amcl", l, *root + "laser_model_type", l.value);
        else ignore("amcl", l, "starnav's AMCL has the likelihood_field and beam models only");
      } else if (l.key == "robot_model_type") {
        if (l.value.find("Differential") != std::string::npos || l.value == "differential")
          map_choice("amcl", l, *root + "robot_model_type", "differential");
        else if (l.value.find("Omni") != std::string::npos || l.value == "omnidirectional")
          map_choice("amcl", l, *root + "robot_model_type", "omnidirectional");
        else ignore("amcl", l, "an unknown motion model");
      } else if (l.key == "random_seed") {
        ignore("amcl", l, "the run's seed is starnav's (--seed)");
      } else if (l.key.rfind("beam_skip", 0) == 0 || l.key == "do_beamskip") {
        ignore("amcl", l, "starnav's AMCL has no beam skipping");
      } else if (l.key.rfind("initial_pose", 0) == 0 || l.key == "set_initial_pose" || l.key == "always_reset_initial_pose" ||
                 l.key == "first_map_only") {
        ignore("amcl", l, "the start is the scenario's (localization.amcl.initial) or localize's --initial");
      } else if (is_plumbing(l.key)) {
        ignore("amcl", l, kPlumbing);
      } else {
        ignore("amcl", l, "no equivalent in starnav's AMCL (starnav params, section amcl)");
      }
    }
  }

  void controller(const std::vector<Leaf>& leaves) {
    // The plugin of each sub-map ("FollowPath.plugin: dwb_core::DWBLocalPlanner").
    std::map<std::string, std::string> plugins;
    for (const Leaf& l : leaves) {
      const std::size_t dot = l.key.find('.');
      if (dot != std::string::npos && l.key.substr(dot + 1) == "plugin") plugins[l.key.substr(0, dot)] = l.value;
    }
    const std::string node = "controller_server";
    for (const Leaf& l : leaves) {
      const std::size_t dot = l.key.find('.');
      const std::string owner = dot == std::string::npos ? "" : l.key.substr(0, dot);
      const std::string rest = dot == std::string::npos ? l.key : l.key.substr(dot + 1);
      const std::string plugin = plugins.count(owner) ? plugins[owner] : "";
      if (owner.empty()) {
        if (const auto dwb = controller_standing_for(kNav2Dwb); l.key == "controller_frequency" && dwb && target_.kind == Nav2Target::Kind::Scenario)
          map(node, l, "navigation." + *dwb + ".control_period_s", {"", 1.0, "Hz -> s", true});
        else if (const auto mppi = controller_standing_for(kNav2Mppi);
                 l.key == "controller_frequency" && mppi && target_.kind == Nav2Target::Kind::Scenario)
          map(node, l, "navigation." + *mppi + ".control_period_s", {"", 1.0, "Hz -> s", true});
        else if (l.key == "controller_frequency")
          ignore(node, l, "the control period is the DWA's (navigation.dwa.control_period_s); the scenario's controller is " + target_.controller);
        else
          ignore(node, l, is_plumbing(l.key) ? kPlumbing : "no starnav equivalent (the controller server's own bookkeeping)");
        continue;
      }
      if (rest == "plugin") {
        ignore(node, l, "the scenario names its controller (navigation.controller; starnav's dwa is Nav2's DWB)");
        continue;
      }
      if (target_.kind == Nav2Target::Kind::Localize || !target_.navigation) {
        ignore(node, l, target_.kind == Nav2Target::Kind::Localize ? "localize runs AMCL only" : "the scenario has no navigation section");
        continue;
      }
      if (plugin.find("DWBLocalPlanner") != std::string::npos) {
        const auto rule = dwb_rules().find(rest);
        if (rule == dwb_rules().end()) ignore(node, l, rest == "critics" ? "starnav's DWA has DWB's critics; their weights are the scales" : "no equivalent in starnav's DWA");
        else if (const auto dwb = controller_standing_for(kNav2Dwb); !dwb)
          ignore(node, l, "the scenario's controller is " + target_.controller + ", not one that stands for Nav2's DWB (dwa)");
        else map(node, l, "navigation." + *dwb + "." + rule->second.starnav, rule->second);
      } else if (plugin.find("RegulatedPurePursuit") != std::string::npos) {
        const auto rpp = controller_info_standing_for(kNav2Rpp);
        if (!rpp) {
          ignore(node, l, "the scenario's controller is " + target_.controller +
                              ", not one that stands for Nav2's pure pursuit (regulated_pure_pursuit, or path_follower's pure_pursuit mode)");
        } else if (const auto rule = pursuit_rule(rest, rpp->params); !rule) {
          ignore(node, l, "no equivalent in starnav's " + rpp->name);
        } else {
          map(node, l, "navigation." + rpp->section + "." + rule->starnav, *rule);
        }
      } else if (plugin.find("MPPI") != std::string::npos) {
        mppi_key(node, l, rest, owner, leaves);
      } else if (plugin.find("GoalChecker") != std::string::npos) {
        goal_checker_key(node, l, rest, plugin);
      } else {
        ignore(node, l, "no starnav equivalent (" + (plugin.empty() ? std::string("no plugin") : printable(plugin, 60)) + ")");
      }
    }
  }

  // One key of a Nav2 goal checker: the tolerances are the navigation's own; the checker's other
  // keys map onto the scenario's goal checker when it stands for that plugin (latching: Simple,
  // stopped: Stopped).
  void goal_checker_key(const std::string& node, const Leaf& l, const std::string& rest, const std::string& plugin) {
    if (rest == "xy_goal_tolerance") return map(node, l, "navigation.goal_tolerance_m", {});
    if (rest == "yaw_goal_tolerance") return map(node, l, "navigation.goal_yaw_tolerance_deg", {"", kDeg, "rad -> deg"});
    const std::string_view counterpart = plugin.find("StoppedGoalChecker") != std::string::npos ? kNav2StoppedGoalChecker
                                         : plugin.find("SimpleGoalChecker") != std::string::npos  ? kNav2SimpleGoalChecker
                                                                                                  : std::string_view();
    const auto section = counterpart.empty() ? std::nullopt : section_standing_for(Role::GoalChecker, target_.goal_checker, counterpart);
    if (!section) {
      ignore(node, l, counterpart.empty() ? "no starnav goal checker stands for " + printable(plugin, 60)
                                          : "the scenario's goal checker is " + target_.goal_checker + ", not one that stands for Nav2's " +
                                                std::string(counterpart.substr(counterpart.find("::") + 2)));
      return;
    }
    const std::string root = "navigation." + *section + ".";
    if (rest == "stateful" && counterpart == kNav2SimpleGoalChecker) map(node, l, root + "stateful", {});
    else if (rest == "trans_stopped_velocity" && counterpart == kNav2StoppedGoalChecker) map(node, l, root + "trans_stopped_velocity_mps", {});
    else if (rest == "rot_stopped_velocity" && counterpart == kNav2StoppedGoalChecker)
      map(node, l, root + "rot_stopped_velocity_degps", {"", kDeg, "rad/s -> deg/s"});
    else ignore(node, l, "no equivalent in starnav's goal checker " + target_.goal_checker);
  }

  // One key of Nav2's MPPI controller: its own keys and its critics' (GoalCritic.cost_weight) under
  // starnav's names (goal.cost_weight, with the unit's suffix); the critics' list with the ones
  // disabled (X.enabled: false) left out; CostCritic stands as starnav's distance-based obstacles.
  void mppi_key(const std::string& node, const Leaf& l, const std::string& rest, const std::string& owner, const std::vector<Leaf>& leaves) {
    const auto mppi = controller_info_standing_for(kNav2Mppi);
    if (!mppi) {
      ignore(node, l, "the scenario's controller is " + target_.controller + ", not one that stands for Nav2's MPPI (mppi)");
      return;
    }
    const std::string root = "navigation." + mppi->section + ".";
    const std::size_t dot = rest.find('.');
    const std::string space = dot == std::string::npos ? "" : rest.substr(0, dot), key = dot == std::string::npos ? rest : rest.substr(dot + 1);
    if (rest == "critics") {
      std::vector<std::string> names;
      std::string dropped;
      for (const std::string& n : list_names(l.value)) {
        bool enabled = true;
        for (const Leaf& e : leaves)
          if (e.key == owner + "." + n + ".enabled" && (e.value == "false" || e.value == "False")) enabled = false;
        std::string s = mppi_name(n);
        if (s == "cost") s = "obstacles";
        bool known = false;
        for (const ParamSpec& spec : mppi->params)
          if (spec.key == "critics") known = std::find(spec.choices.begin(), spec.choices.end(), s) != spec.choices.end();
        if (!enabled || !known || std::find(names.begin(), names.end(), s) != names.end()) {
          dropped += (dropped.empty() ? "" : ", ") + n + (!enabled ? " (disabled)" : (!known ? " (no such critic)" : " (twice)"));
          continue;
        }
        names.push_back(s);
      }
      std::string value = "[";
      for (std::size_t i = 0; i < names.size(); ++i) value += (i ? ", " : "") + names[i];
      value += "]";
      p_.mapped.push_back({node + "." + l.key, l.line, l.value, root + "critics", value,
                           "CostCritic -> obstacles" + (dropped.empty() ? std::string() : "; left out: " + dropped)});
      return;
    }
    if (key == "enabled") {
      ignore(node, l, "applied to the critics' list (a disabled critic is left out of navigation." + mppi->section + ".critics)");
    } else if (space == "CostCritic") {
      ignore(node, l, "starnav's obstacles critic (distance-based: navigation." + mppi->section + ".obstacles.*) stands for the CostCritic");
    } else if (rest == "motion_model") {
      const std::string m = mppi_name(l.value);
      if (m == "diff_drive" || m == "omni" || m == "ackermann") map_choice(node, l, root + "motion_model", m);
      else ignore(node, l, "an unknown motion model");
    } else if (const auto rule = pursuit_rule(space.empty() ? key : mppi_name(space) + "." + key, mppi->params)) {
      map(node, l, root + rule->starnav, *rule);
    } else {
      ignore(node, l, is_plumbing(l.key) || space == "TrajectoryVisualizer" || key == "visualize" || key == "publish_optimal_trajectory"
                          ? kPlumbing
                          : "no equivalent in starnav's " + mppi->name);
    }
  }

  void costmap(const std::string& node, const std::vector<Leaf>& leaves) {
    std::map<std::string, std::string> plugins;
    for (const Leaf& l : leaves) {
      const std::size_t dot = l.key.rfind('.');
      if (dot != std::string::npos && l.key.substr(dot + 1) == "plugin") plugins[l.key.substr(0, dot)] = l.value;
    }
    const bool local = node == "local_costmap";
    for (const Leaf& l : leaves) {
      const std::size_t dot = l.key.rfind('.');
      const std::string owner = dot == std::string::npos ? "" : l.key.substr(0, dot);
      const std::string rest = dot == std::string::npos ? l.key : l.key.substr(dot + 1);
      const bool inflation = plugins.count(owner) && plugins[owner].find("InflationLayer") != std::string::npos;
      if (target_.kind == Nav2Target::Kind::Localize || !target_.navigation) {
        ignore(node, l, target_.kind == Nav2Target::Kind::Localize ? "localize runs AMCL only" : "the scenario has no navigation section");
      } else if (inflation && (rest == "inflation_radius" || rest == "cost_scaling_factor")) {
        if (!local) ignore(node, l, "the global planner plans on the barrier map (navigation.map) with its own costs (navigation.PLANNER.cost_*)");
        else if (const auto dwb = controller_standing_for(kNav2Dwb); !dwb)
          ignore(node, l, "the local costs are the DWA's obstacle critic; the scenario's controller is " + target_.controller);
        else map(node, l, "navigation." + *dwb + (rest == "inflation_radius" ? ".inflation_radius_m" : ".cost_scaling_per_m"), {});
      } else if (rest == "robot_radius" && owner.empty()) {
        if (local) ignore(node, l, "the DWA's footprint is the robot's body (navigation.dwa.footprint=circle with footprint_radius_m takes a radius)");
        else map(node, l, "navigation.map.barrier_distance_m", {});
      } else if (rest == "footprint" && owner.empty()) {
        ignore(node, l, "starnav's footprint is the robot's body (the robot section), not a polygon");
      } else {
        ignore(node, l, is_plumbing(l.key) ? kPlumbing : "no starnav equivalent (starnav's navigation map is built from its LiDAR: docs/navigation.md)");
      }
    }
  }

  Nav2Target target_;
  Nav2Params p_;
};

}  // namespace nav2_detail

std::vector<ParamSetting> Nav2Params::settings() const {
  std::vector<ParamSetting> out;
  for (const Nav2Key& k : mapped) out.push_back({k.starnav, k.converted, file, k.line, k.nav2 + " (" + k.starnav + ")"});
  return out;
}

Nav2Params read_nav2_params(const std::string& path, const Nav2Target& target) {
  const InputFileScope reading(path);
  const std::string text = read_input_file(path, nav2_detail::kMaxNav2FileBytes);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error("not YAML: " + one_line(e.msg, 200), path, e.mark.line + 1);
  }
  if (!root.IsMap()) throw Error("expected a map of Nav2 nodes (NODE: ros__parameters: ...)", path);
  nav2_detail::Mapper mapper(path, target);
  int nodes = 0;
  try {
    for (const auto& kv : root) {
      const std::string name = kv.first.IsScalar() ? kv.first.Scalar() : std::string();
      YAML::Node params = nav2_detail::child(kv.second, "ros__parameters");
      // Costmaps nest their node: local_costmap: local_costmap: ros__parameters.
      if (!params.IsMap()) params = nav2_detail::child(nav2_detail::child(kv.second, name), "ros__parameters");
      if (!params.IsMap()) continue;
      std::vector<nav2_detail::Leaf> leaves;
      try {
        nav2_detail::flatten(params, "", leaves, 0);
      } catch (const Error& e) {
        throw Error(e.message(), path, e.line(), name);
      }
      mapper.node(name, leaves);
      ++nodes;
    }
  } catch (const YAML::Exception& e) {
    throw Error(one_line(e.msg, 200), path, e.mark.line + 1);
  }
  if (nodes == 0) throw Error("has no NODE: ros__parameters: map: not a Nav2 parameter file", path);
  return mapper.take();
}

std::string nav2_params_text(const Nav2Params& p) {
  std::ostringstream out;
  out << p.file << ": " << p.mapped.size() << " keys mapped, " << p.ignored.size() << " ignored\n";
  for (const Nav2Key& k : p.mapped)
    out << "  mapped  " << k.nav2 << " = " << k.value << "  ->  " << k.starnav << " = " << k.converted << (k.note.empty() ? "" : "  (" + k.note + ")")
        << "  [line " << k.line << "]\n";
  for (const Nav2Key& k : p.ignored) out << "  ignored " << k.nav2 << ": " << k.note << "  [line " << k.line << "]\n";
  return out.str();
}

std::string nav2_params_json(const Nav2Params& p) {
  nlohmann::ordered_json j;
  j["file"] = p.file;
  nlohmann::ordered_json mapped = nlohmann::ordered_json::array(), ignored = nlohmann::ordered_json::array();
  for (const Nav2Key& k : p.mapped)
    mapped.push_back({{"nav2", k.nav2}, {"line", k.line}, {"value", k.value}, {"starnav", k.starnav}, {"converted", k.converted}, {"note", k.note}});
  for (const Nav2Key& k : p.ignored) ignored.push_back({{"nav2", k.nav2}, {"line", k.line}, {"value", k.value}, {"reason", k.note}});
  j["mapped"] = mapped;
  j["ignored"] = ignored;
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace starnav
