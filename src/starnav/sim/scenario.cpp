// The scenario document: its top level, the sim, metrics and outputs sections, values set from
// the command line, and building the world. The other sections are read beside their
// declarations (scenario_world.cpp, scenario_robot.cpp, scenario_navigation.cpp).
#include "starnav/sim/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/io/yaml_document.hpp"
#include "starnav/sim/occupancy_world.hpp"
#include "starnav/sim/scenario_document.hpp"
#include "starnav/sim/terrain_surface.hpp"

namespace starnav {

namespace scenario_detail {

const SectionDecl<ScenarioSpec>& top_decl() {
  static const SectionDecl<ScenarioSpec> d = [] {
    SectionDecl<ScenarioSpec> s;
    s.id = "top";
    s.title = "the top level";
    s.table.text("name", &ScenarioSpec::name, "used in pictures and metrics.json")
        .text("description", &ScenarioSpec::description, "free text");
    s.table.default_rule("name", "the file name without extension");
    s.structural = {
        {"world", "mapping", "required", "", "", "terrain and obstacles"},
        {"robot", "mapping", "the paper's Mecanum robot", "", "", "kinematics, body, limits, start pose"},
        {"vehicle", "mapping", "", "", "", "friction and slip"},
        {"sensors", "mapping", "none (bumper only)", "", "", "LiDARs, IMU, encoders, bumper"},
        {"sim", "mapping", "", "", "", "clock and seed"},
        {"commands", "list of mappings", "[] (stand still)", "", "", "scripted body-velocity segments"},
        {"route", "mapping", "none", "", "",
         "a fixed loop through waypoints, planned on world.occupancy_map and driven on the true pose; instead of commands"},
        {"events", "list of mappings", "[]", "", "", "timed events: teleport (the kidnapped robot)"},
    };
    s.table.choice(
        "motion_mode", {"auto", "turn_then_drive", "holonomic", "pure_pursuit"},
        [](ScenarioSpec& spec, const std::string& m) { spec.motion_mode = m; },
        [](const ScenarioSpec& spec) { return spec.motion_mode.empty() ? std::string("auto") : spec.motion_mode; },
        "how the path follower follows its paths (docs/navigation.md); checked against the drive when a navigation run "
        "starts; starnav sim --motion-mode overrides");
    s.structural.push_back({"navigation", "mapping", "none", "", "",
                            "makes the scenario a navigation run: the navigation stack drives to a goal; no commands then"});
    s.structural.push_back({"localization", "mapping", "none", "", "",
                            "the localization chain (docs/parameters.md): a navigation run navigates on it, a scripted run "
                            "records it beside its script"});
    s.structural.push_back({"metrics", "mapping", "none", "", "", "reference line for deviation metrics"});
    s.structural.push_back({"outputs", "mapping", "", "", "", "trajectory decimation, point clouds, LiDAR frames"});
    return s;
  }();
  return d;
}

namespace {

struct SimKeys {
  double dt_s = 0.01;
  double duration_s = 0.0;
  std::uint64_t seed = 0;
};

const SectionDecl<SimKeys>& sim_keys_decl() {
  static const SectionDecl<SimKeys> d = [] {
    SectionDecl<SimKeys> s;
    s.id = "sim";
    s.title = "sim";
    s.table.real("dt_s", &SimKeys::dt_s, ParamRange{0.0, 1.0, true, false}, "s", "the fixed step")
        .real("duration_s", &SimKeys::duration_s, positive(), "s",
              "required when there are no commands; --duration overrides");
    s.table.default_rule("duration_s", "the end of the command script");
    declare_seed(s.table, "seed", &SimKeys::seed,
                 "every random draw (sensor noise, slip, and generated terrain / gravel without their own seed); --seed overrides");
    return s;
  }();
  return d;
}

struct MetricsKeys {};

const SectionDecl<MetricsKeys>& metrics_decl() {
  static const SectionDecl<MetricsKeys> d = [] {
    SectionDecl<MetricsKeys> s;
    s.id = "metrics";
    s.title = "metrics";
    s.structural = {{"reference_line_m", "list of [x, y]", "none", "at least 2 points", "m",
                     "metrics.json reports the robot's mean and largest distance from this polyline; track.svg draws it"}};
    return s;
  }();
  return d;
}

const SectionDecl<ScenarioOutputs>& outputs_decl() {
  static const SectionDecl<ScenarioOutputs> d = [] {
    SectionDecl<ScenarioOutputs> s;
    s.id = "outputs";
    s.title = "outputs";
    s.table.integer("trajectory_every_n_steps", &ScenarioOutputs::trajectory_every_n_steps, closed(1, 1000000), "",
                    "a trajectory.csv row every N steps (and the last)");
    s.structural = {
        {"point_clouds", "mapping", "none", "", "",
         "LiDAR point clouds in the world frame to OUT/clouds/ (outputs.point_clouds); needs sensors.lidar"},
        {"lidar_frames", "mapping", "none", "", "",
         "what a robot records for 3D mapping, into OUT/lidar/ (outputs.lidar_frames; docs/mapping3d.md); needs sensors.lidar"},
    };
    return s;
  }();
  return d;
}

const SectionDecl<ScenarioOutputs>& point_clouds_decl() {
  static const SectionDecl<ScenarioOutputs> d = [] {
    SectionDecl<ScenarioOutputs> s;
    s.id = "outputs.point_clouds";
    s.title = "outputs.point_clouds";
    s.table
        .choice(
            "format", {"ply", "pcd", "none"},
            [](ScenarioOutputs& o, const std::string& f) { o.point_clouds = parse_cloud_format(f, "format"); },
            [](const ScenarioOutputs& o) { return std::string(cloud_format_name(o.point_clouds)); },
            "file format (scan_NNNNNN.EXT); --point-clouds overrides")
        .integer("every_n_scans", &ScenarioOutputs::clouds_every_n_scans, closed(1, 1000000), "", "a cloud every N scans");
    s.required = {"format"};
    return s;
  }();
  return d;
}

const SectionDecl<ScenarioOutputs>& lidar_frames_decl() {
  static const SectionDecl<ScenarioOutputs> d = [] {
    SectionDecl<ScenarioOutputs> s;
    s.id = "outputs.lidar_frames";
    s.title = "outputs.lidar_frames";
    s.table.integer("every_n_scans", &ScenarioOutputs::lidar_frames_every_n_scans, closed(1, 1000000), "",
                    "a frame every N scans");
    s.table.default_rule("every_n_scans", "1");
    return s;
  }();
  return d;
}

void parse_sim(const Value& v, ScenarioSpec& s, std::optional<double>& duration) {
  Fields f(v, v.doc());
  SimKeys k;
  apply_section(f, sim_keys_decl(), k);
  s.dt_s = k.dt_s;
  if (f.has("duration_s")) duration = k.duration_s;
  s.seed = k.seed;
}

}  // namespace

void parse_metrics(const Value& v, ScenarioSpec& s) {
  Fields f(v, v.doc());
  if (auto r = f.take("reference_line_m")) {
    if (!r->node().IsSequence() || r->node().size() < 2)
      r->fail("expected a list of at least 2 points [x, y], found " + node_kind(r->node()));
    for (std::size_t i = 0; i < r->node().size(); ++i) {
      const auto p = r->element(i).numbers(2, 2);
      s.reference_line.emplace_back(p[0], p[1]);
    }
  }
  MetricsKeys none;
  apply_section(f, metrics_decl(), none);
}

void parse_outputs(const Value& v, ScenarioSpec& s) {
  const Doc& doc = v.doc();
  Fields f(v, doc);
  if (auto pc = f.take("point_clouds")) {
    Fields g(*pc, doc);
    g.require("format");
    apply_section(g, point_clouds_decl(), s.outputs);
    if (s.outputs.point_clouds != ScenarioOutputs::CloudFormat::None && !s.lidar)
      throw Error("point clouds need sensors.lidar", doc.file, pc->line(), pc->field());
  }
  if (auto lf = f.take("lidar_frames")) {
    Fields g(*lf, doc);
    s.outputs.lidar_frames_every_n_scans = 1;
    apply_section(g, lidar_frames_decl(), s.outputs);
    if (!s.lidar) throw Error("LiDAR frames need sensors.lidar", doc.file, lf->line(), lf->field());
  }
  apply_section(f, outputs_decl(), s.outputs);
}

std::vector<ScenarioKeySection> top_sections() {
  return {top_decl().describe(), sim_keys_decl().describe()};
}

std::vector<ScenarioKeySection> output_sections() {
  return {metrics_decl().describe(), outputs_decl().describe(), point_clouds_decl().describe(), lidar_frames_decl().describe()};
}

}  // namespace scenario_detail

namespace scenario_detail {

ScenarioSpec parse_document(const YAML::Node& root, const std::string& file) {
  const Doc doc{file, std::filesystem::path(file).parent_path()};
  ScenarioSpec s;
  s.file = file;
  if (!root.IsDefined() || root.IsNull()) throw Error("empty scenario (expected a mapping with world, robot, ...)", file, 1);
  const Value rv(root, "", mark_line(root) > 0 ? mark_line(root) : 1, doc);
  if (!root.IsMap()) rv.fail("a scenario is a mapping (key: value lines), found " + node_kind(root));
  Fields top(rv, doc);

  // sim first: the script's length may set the duration.
  std::optional<double> duration;
  if (auto v = top.take("sim")) parse_sim(*v, s, duration);
  parse_world(top.required("world"), s);
  parse_robot_and_vehicle(top.take("robot"), top.take("vehicle"), s);
  if (auto v = top.take("sensors")) parse_sensors(*v, s);
  if (auto v = top.take("commands")) parse_commands(*v, s);
  if (auto v = top.take("route")) parse_route(*v, s);
  if (duration) s.duration_s = *duration;
  else if (!s.commands.empty()) s.duration_s = s.commands.back().end_s;
  else throw Error("required when there are no commands", file, top.line_of("sim"), "sim.duration_s");

  if (auto v = top.take("navigation")) {
    s.navigation = parse_navigation(*v);
    if (s.route) throw Error("a navigation scenario has no route (the navigation stack drives)", file, s.route->source.line, "route");
    if (!s.commands.empty())
      throw Error("a navigation scenario has no command script (the navigation stack drives)", file,
                  top.line_of("commands"), "commands");
  }
  // A scripted run may carry a chain too: it runs beside the script and records its estimate.
  if (auto v = top.take("localization")) s.localization = parse_settings_section(*v);
  if (auto v = top.take("events")) parse_events(*v, s);
  if (auto v = top.take("metrics")) parse_metrics(*v, s);
  if (auto v = top.take("outputs")) parse_outputs(*v, s);

  apply_section(top, top_decl(), s);
  if (top.has("motion_mode")) s.motion_mode_source = {top.line_of("motion_mode"), "motion_mode"};
  if (s.name.empty()) s.name = std::filesystem::path(file).stem().string();

  // A sensor samples at most once per simulation step: a faster rate would only repeat the
  // same state, and an absurd one (1e300 Hz) would never finish a step.
  const double max_rate_hz = 1.0 / s.dt_s * (1.0 + 1e-9);
  const auto check_rate = [&](double rate_hz, const ScenarioSource& src, const std::string& field) {
    if (rate_hz > max_rate_hz)
      throw Error("is " + format_number(rate_hz) + " Hz, more than one sample per simulation step (1 / sim.dt_s = " +
                      format_number(1.0 / s.dt_s) + " Hz)",
                  file, src.line, field);
  };
  if (s.lidar) check_rate(s.lidar->config.rate_hz, s.lidar->source, "sensors.lidar.rate_hz");
  for (const ScenarioLidar& l : s.other_lidars) check_rate(l.config.rate_hz, l.source, l.source.field + ".rate_hz");
  if (s.imu) check_rate(s.imu->config.rate_hz, s.imu->source, "sensors.imu.rate_hz");
  if (s.encoders) check_rate(s.encoders->rate_hz, s.encoders->source, "sensors.encoders.rate_hz");
  check_simulation_steps(s, "sim.duration_s");
  return s;
}

}  // namespace scenario_detail

BodyTwist ScenarioSpec::command_at(double t) const {
  const int i = segment_at(t);
  return i < 0 ? BodyTwist{} : commands[static_cast<std::size_t>(i)].twist;
}

int ScenarioSpec::segment_at(double t) const {
  // Segments are consecutive from 0: the first whose end lies beyond t.
  const auto it = std::upper_bound(commands.begin(), commands.end(), t,
                                   [](double v, const CommandSegment& c) { return v < c.end_s; });
  if (it == commands.end() || t < 0.0) return -1;
  return static_cast<int>(it - commands.begin());
}

namespace {

// A copy of `n` without marks: values set on the command line have no line in the file.
YAML::Node unmarked(const YAML::Node& n) {
  if (n.IsScalar()) return YAML::Node(n.Scalar());
  if (n.IsSequence()) {
    YAML::Node out(YAML::NodeType::Sequence);
    for (const auto& e : n) out.push_back(unmarked(e));
    return out;
  }
  if (n.IsMap()) {
    YAML::Node out(YAML::NodeType::Map);
    for (auto it = n.begin(); it != n.end(); ++it) out[it->first.Scalar()] = unmarked(it->second);
    return out;
  }
  return YAML::Node();
}

void apply_override(YAML::Node& root, const ScenarioOverride& o, const std::string& file) {
  const std::string field = "--set " + o.key;
  std::vector<std::string> parts;
  for (std::size_t b = 0;;) {
    const std::size_t e = o.key.find('.', b);
    parts.push_back(o.key.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  for (const std::string& p : parts)
    if (p.empty() || p.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
      throw Error("a key is dotted lower_snake_case names (navigation.follower.look_ahead_m)", "", 0, field);
  if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw Error("the scenario is not a mapping", file, 0, field);
  YAML::Node node = root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = node[parts[i]];
    if (!child.IsDefined() || child.IsNull()) {
      node[parts[i]] = YAML::Node(YAML::NodeType::Map);
      child.reset(node[parts[i]]);
    } else if (!child.IsMap()) {
      throw Error("'" + parts[i] + "' is not a section of the scenario", file, 0, field);
    }
    node.reset(child);
  }
  YAML::Node value;
  try {
    value = load_yaml_document(o.value, "");
  } catch (const Error& e) {
    throw Error("not a YAML value: " + e.message(), "", 0, field);
  }
  // A fresh key (no mark): the value has no line in the file.
  node.remove(parts.back());
  node[parts.back()] = value.IsNull() && !o.value.empty() ? YAML::Node(o.value) : unmarked(value);
}

}  // namespace

ScenarioOverride parse_scenario_override(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw Error("expected KEY=VALUE, found '" + one_line(text, 60) + "'", "", 0, "--set");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

void check_user_overrides(std::span<const ScenarioOverride> overrides, std::span<const CommandOwnedKey> owned) {
  const auto under = [](const std::string& key, const std::string& prefix) {
    return key == prefix || key.rfind(prefix + ".", 0) == 0 || key.rfind(prefix + "[", 0) == 0;
  };
  for (std::size_t i = 0; i < overrides.size(); ++i) {
    const std::string& key = overrides[i].key;
    for (std::size_t j = 0; j < i; ++j)
      if (overrides[j].key == key) throw Error("given twice; give each key once", "", 0, key + " (--set)");
    for (const CommandOwnedKey& o : owned)
      if (under(key, o.key)) throw Error("the command sets " + o.key + " itself (" + o.why + ")", "", 0, key + " (--set)");
  }
}

ScenarioSpec parse_scenario(std::string_view yaml_text, const std::string& file, std::span<const ScenarioOverride> overrides) {
  YAML::Node root = load_yaml_document(yaml_text, file);
  for (const ScenarioOverride& o : overrides) apply_override(root, o, file);
  try {
    return scenario_detail::parse_document(root, file);
  } catch (const YAML::Exception& e) {
    throw Error("invalid YAML: " + one_line(e.msg, 60), file, e.mark.is_null() ? 0 : e.mark.line + 1);
  } catch (const Error& e) {
    // A value from --set has no line: say where it came from.
    if (e.line() == 0 && !e.field().empty() && e.field().find("(--set)") == std::string::npos)
      for (const ScenarioOverride& o : overrides)
        if (e.field() == o.key || e.field().rfind(o.key + ".", 0) == 0 || e.field().rfind(o.key + "[", 0) == 0)
          throw Error(e.message(), e.file(), 0, e.field() + " (--set)");
    throw;
  }
}

void check_simulation_steps(const ScenarioSpec& spec, const std::string& field) {
  const double steps = spec.duration_s / spec.dt_s;
  if (!(steps <= kMaxSimulationSteps))
    throw Error(format_number(spec.duration_s) + " s at sim.dt_s " + format_number(spec.dt_s) + " s is " + format_number(steps) +
                    " steps, more than the " + format_number(kMaxSimulationSteps) + " a run may take",
                spec.file, 0, field);
  double rays = 0.0;
  std::vector<const ScenarioLidar*> lidars;
  if (spec.lidar) lidars.push_back(&*spec.lidar);
  for (const ScenarioLidar& l : spec.other_lidars) lidars.push_back(&l);
  for (const ScenarioLidar* lidar : lidars) {
    const LidarConfig& l = lidar->config;
    const double scans = std::floor(spec.duration_s * l.rate_hz) + 1.0;
    rays += scans * static_cast<double>(l.ray_count());
    if (!(rays <= kMaxSimulationLidarRays))
      throw Error(format_number(spec.duration_s) + " s of " + format_number(l.rate_hz) + " Hz scans of " +
                      std::to_string(l.ray_count()) + " rays is " + format_number(rays) + " rays, more than the " +
                      format_number(kMaxSimulationLidarRays) + " a run may cast",
                  spec.file, 0, field);
  }
}

ScenarioSpec load_scenario(const std::string& path, std::span<const ScenarioOverride> overrides) {
  const InputFileScope reading_path(path);
  return parse_scenario(read_yaml_file(path), path, overrides);
}

WorldDescription build_world(const ScenarioSpec& spec) {
  WorldDescription d;
  const ScenarioTerrain& t = spec.terrain;
  const auto fail = [&](const Error& e) -> void {
    throw Error(e.message() + (e.file().empty() || e.file() == t.resolved_file ? "" : " (" + e.file() + ")"), spec.file,
                t.source.line, t.source.field);
  };
  try {
    switch (t.kind) {
      case ScenarioTerrain::Kind::None:
        break;
      case ScenarioTerrain::Kind::File: {
        LoadedMap m;
        try {
          m = load_map(t.resolved_file);
        } catch (const Error& e) {
          // e.what() starts with the terrain file's own path (and line) where it has them.
          const std::string what = e.file().empty() ? t.resolved_file + ": " + e.what() : std::string(e.what());
          throw Error("cannot load the terrain: " + what, spec.file, t.source.line, t.source.field);
        }
        if (!m.is_elevation())
          throw Error("terrain file " + t.resolved_file + " is an occupancy map, not an elevation map", spec.file,
                      t.source.line, t.source.field);
        d.terrain = m.elevation();
        break;
      }
      case ScenarioTerrain::Kind::Flat: {
        ElevationMap m(terrain_geometry(t.hills.width_m, t.hills.height_m, t.hills.resolution, t.hills.origin));
        for (int iy = 0; iy < m.height(); ++iy)
          for (int ix = 0; ix < m.width(); ++ix) m.set_height(ix, iy, t.flat_z_m);
        d.terrain = std::move(m);
        break;
      }
      case ScenarioTerrain::Kind::Hills: {
        HillsOptions h = t.hills;
        if (!t.seed_given) h.seed = spec.seed;
        d.terrain = generate_hills(h);
        break;
      }
      case ScenarioTerrain::Kind::Road: {
        RoadOptions r = t.road;
        if (!t.seed_given) r.seed = spec.seed;
        d.terrain = generate_road(r).map;
        break;
      }
    }
    if (d.terrain)
      for (const TerrainFeature& f : t.features) add_terrain_feature(*d.terrain, f);
  } catch (const Error& e) {
    if (e.file() == spec.file) throw;
    fail(e);
  }

  std::optional<TerrainSurface> ground;
  if (d.terrain) {
    try {
      ground.emplace(*d.terrain);
    } catch (const Error& e) {
      fail(e);
    }
  }
  if (spec.occupancy_map) {
    const ScenarioOccupancyWorld& m = *spec.occupancy_map;
    try {
      RosMapMetadata meta;
      const OccupancyGrid grid = read_ros_map(m.resolved_file, &meta);
      Obstacle walls = occupancy_walls(grid, meta.occupied_thresh * 100.0, m.wall_height_m, "occupancy_map");
      if (!walls.parts.empty()) d.obstacles.push_back(std::move(walls));
    } catch (const Error& e) {
      const std::string what = e.file().empty() ? m.resolved_file + ": " + e.what() : std::string(e.what());
      throw Error("cannot make the world from the occupancy map: " + what, spec.file, m.source.line, m.source.field);
    }
  }
  for (const ScenarioObstacle& s : spec.obstacles) {
    double gz = 0.0;
    if (ground) {
      const double h = ground->height(s.position.x(), s.position.y());
      if (std::isfinite(h)) gz = h;
    }
    try {
      Obstacle o = scenario_detail::place_obstacle(s, gz, ground ? &*ground : nullptr, spec.seed);
      validate(o);
      d.obstacles.push_back(std::move(o));
    } catch (const Error& e) {
      throw Error(e.message(), spec.file, s.source.line, s.source.field + (e.field().empty() ? "" : "." + e.field()));
    }
  }
  return d;
}

const char* cloud_format_name(ScenarioOutputs::CloudFormat f) {
  switch (f) {
    case ScenarioOutputs::CloudFormat::None:
      return "none";
    case ScenarioOutputs::CloudFormat::Ply:
      return "ply";
    case ScenarioOutputs::CloudFormat::Pcd:
      return "pcd";
  }
  return "none";
}

ScenarioOutputs::CloudFormat parse_cloud_format(const std::string& s, const std::string& field) {
  if (s == "none") return ScenarioOutputs::CloudFormat::None;
  if (s == "ply") return ScenarioOutputs::CloudFormat::Ply;
  if (s == "pcd") return ScenarioOutputs::CloudFormat::Pcd;
  throw Error("unknown point cloud format '" + s + "' (ply, pcd, none)", {}, 0, field);
}

}  // namespace starnav
