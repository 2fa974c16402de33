// The scenario document's declared keys: every declared section refuses, in a scenario, an
// unknown key (naming the known ones), a value just outside its declared range and a value of
// the wrong type, each with the file, line and full key; its table accepts a value just inside
// the range. docs/scenarios.md's generated tables match the declarations, and every scenario in
// scenarios/ loads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "support/test_support.hpp"
#include "starnav/core/error.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/scenario_keys.hpp"

namespace starnav {
namespace {

// Where a section's mapping sits in a valid scenario: the text before and after it, the
// mapping's entries (its required keys), and the keys a tested key replaces.
struct Host {
  std::string before;  // ends where the mapping starts ("robot: ")
  std::string after;
  std::string field;   // the mapping's dotted field
  std::vector<std::pair<std::string, std::string>> entries;
  std::map<std::string, std::string> replaces = {};  // tested key -> entry it replaces
  bool components = false;  // keys beyond the declared ones belong to components (checked later)
};

const std::string kWorld = "world: {terrain: {generate: {kind: flat, size_m: [10, 6]}}}\nsim: {duration_s: 1}\n";
const std::string kIndoor = "world: {occupancy_map: m.yaml}\nsim: {duration_s: 1}\n";
const std::string kLidar = kWorld + "sensors: {lidar: {}}\n";

std::map<std::string, Host> hosts() {
  const std::string gen = "world: {terrain: {generate: ";
  const std::string obstacle = "world: {obstacles: [";
  return {
      {"top", {kWorld, "", "", {}}},
      {"sim", {"world: {}\nsim: ", "\n", "sim", {{"duration_s", "1"}}}},
      {"world", {"world: ", "\nsim: {duration_s: 1}\n", "world", {}}},
      {"world.terrain", {"world: {terrain: ", "}\nsim: {duration_s: 1}\n", "world.terrain", {{"file", "ground.asc"}}}},
      {"world.terrain.generate", {gen, "}}\nsim: {duration_s: 1}\n", "world.terrain.generate", {{"kind", "flat"}, {"size_m", "[10, 6]"}}}},
      {"world.terrain.generate.flat", {gen, "}}\nsim: {duration_s: 1}\n", "world.terrain.generate", {{"kind", "flat"}, {"size_m", "[10, 6]"}}}},
      {"world.terrain.generate.hills", {gen, "}}\nsim: {duration_s: 1}\n", "world.terrain.generate", {{"kind", "hills"}, {"size_m", "[10, 6]"}}}},
      {"world.terrain.generate.road", {gen, "}}\nsim: {duration_s: 1}\n", "world.terrain.generate", {{"kind", "road"}, {"size_m", "[10, 6]"}}}},
      {"world.terrain.features",
       {gen + "{kind: flat, size_m: [10, 6], features: [", "]}}}\nsim: {duration_s: 1}\n", "world.terrain.generate.features[0]",
        {{"kind", "pit"}, {"centre_m", "[1, 1]"}, {"radius_m", "1"}, {"depth_m", "0.1"}}}},
      {"world.occupancy_map", {"world: {occupancy_map: ", "}\nsim: {duration_s: 1}\n", "world.occupancy_map", {{"file", "m.yaml"}}}},
      {"world.obstacles",
       {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]", {{"kind", "box"}, {"position_m", "[1, 1]"}, {"size_m", "[1, 1, 1]"}}}},
      {"world.obstacles.box",
       {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]", {{"kind", "box"}, {"position_m", "[1, 1]"}, {"size_m", "[1, 1, 1]"}}}},
      {"world.obstacles.cylinder",
       {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]",
        {{"kind", "cylinder"}, {"position_m", "[1, 1]"}, {"radius_m", "1"}, {"height_m", "1"}}}},
      {"world.obstacles.prism",
       {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]",
        {{"kind", "prism"}, {"position_m", "[1, 1]"}, {"base_width_m", "1"}, {"height_m", "1"}, {"length_m", "1"}}}},
      {"world.obstacles.sphere",
       {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]", {{"kind", "sphere"}, {"position_m", "[1, 1]"}, {"radius_m", "1"}}}},
      {"world.obstacles.slope_step", {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]", {{"kind", "slope_step"}, {"position_m", "[1, 1]"}}}},
      {"world.obstacles.undulating_ground",
       {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]", {{"kind", "undulating_ground"}, {"position_m", "[1, 1]"}}}},
      {"world.obstacles.round_convex",
       {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]", {{"kind", "round_convex"}, {"position_m", "[1, 1]"}}}},
      {"world.obstacles.gravel", {obstacle, "]}\nsim: {duration_s: 1}\n", "world.obstacles[0]", {{"kind", "gravel"}, {"position_m", "[1, 1]"}}}},
      {"world.obstacles.waypoints",
       {obstacle + "{kind: sphere, position_m: [1, 1], radius_m: 0.5, waypoints: [", "]}]}\nsim: {duration_s: 1}\n",
        "world.obstacles[0].waypoints[0]", {{"t_s", "0"}, {"position_m", "[1, 1]"}}}},
      {"robot", {kWorld + "robot: ", "\n", "robot", {}}},
      {"robot.start", {kWorld + "robot: {start: ", "}\n", "robot.start", {}}},
      {"vehicle", {kWorld + "vehicle: ", "\n", "vehicle", {}}},
      {"sensors", {kWorld + "sensors: ", "\n", "sensors", {}}},
      {"sensors.lidar", {kWorld + "sensors: {lidar: ", "}\n", "sensors.lidar", {}}},
      {"sensors.lidar.mount", {kWorld + "sensors: {lidar: {mount: ", "}}\n", "sensors.lidar.mount", {}}},
      {"sensors.imu", {kWorld + "sensors: {imu: ", "}\n", "sensors.imu", {}}},
      {"sensors.encoders", {kWorld + "sensors: {encoders: ", "}\n", "sensors.encoders", {}}},
      {"commands", {kWorld + "commands: [", "]\n", "commands[0]", {{"duration_s", "1"}}, {{"until_s", "duration_s"}}}},
      {"route", {kIndoor + "route: ", "\n", "route", {{"waypoints_m", "[[0, 0], [1, 1]]"}}}},
      {"events", {kWorld + "events: [", "]\n", "events[0]", {{"t_s", "0.5"}, {"teleport", "{x_m: 1}"}}}},
      {"events.teleport", {kWorld + "events: [{t_s: 0.5, teleport: ", "}]\n", "events[0].teleport", {}}},
      {"navigation", {kWorld + "navigation: ", "\n", "navigation", {{"goal", "{x_m: 1, y_m: 1}"}}, {}, true}},
      {"navigation.goal", {kWorld + "navigation: {goal: ", "}\n", "navigation.goal", {{"x_m", "1"}, {"y_m", "1"}}}},
      {"navigation.manual",
       {kWorld + "navigation: {goal: {x_m: 1, y_m: 1}, manual: [", "]}\n", "navigation.manual[0]", {{"t_s", "0"}, {"duration_s", "1"}}}},
      {"metrics", {kWorld + "metrics: ", "\n", "metrics", {}}},
      {"outputs", {kLidar + "outputs: ", "\n", "outputs", {}}},
      {"outputs.point_clouds", {kLidar + "outputs: {point_clouds: ", "}\n", "outputs.point_clouds", {{"format", "ply"}}}},
      {"outputs.lidar_frames", {kLidar + "outputs: {lidar_frames: ", "}\n", "outputs.lidar_frames", {}}},
  };
}

// The scenario with `key: value` in the section's mapping (replacing a host entry of that key),
// and the line the mapping is on.
std::pair<std::string, int> with_value(const Host& h, const std::string& key, const std::string& value) {
  const int line = 1 + static_cast<int>(std::count(h.before.begin(), h.before.end(), '\n'));
  if (h.field.empty()) return {h.before + key + ": " + value + "\n", line};
  std::string map = "{";
  bool placed = false;
  const auto replaced = h.replaces.find(key);
  for (const auto& [k, v] : h.entries) {
    if (replaced != h.replaces.end() && replaced->second == k) continue;
    map += (map.size() > 1 ? ", " : "") + k + ": " + (k == key ? value : v);
    placed = placed || k == key;
  }
  if (!placed) map += (map.size() > 1 ? ", " : "") + key + ": " + value;
  return {h.before + map + "}" + h.after, line};
}

// The error of parsing `yaml`, which must name case.yaml, `line` and `field`.
std::string refused(const std::string& yaml, int line, const std::string& field) {
  try {
    parse_scenario(yaml, "case.yaml");
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "case.yaml") << e.what() << "\n" << yaml;
    EXPECT_EQ(e.line(), line) << e.what() << "\n" << yaml;
    EXPECT_EQ(e.field(), field) << e.what() << "\n" << yaml;
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << yaml;
  return {};
}

std::string text_of(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Values just outside a declared range (both ends where they are finite).
std::vector<std::string> outside(const ParamSpec& p) {
  std::vector<std::string> out;
  const ParamRange& r = p.range;
  const bool integer = p.type == ParamType::Integer;
  if (std::isfinite(r.lo)) {
    const double step = integer ? 1.0 : 1e-6 * std::max(1.0, std::abs(r.lo));
    out.push_back(text_of(r.lo_open ? r.lo : r.lo - step));
  }
  if (std::isfinite(r.hi) && r.hi < 1e15) {
    const double step = integer ? 1.0 : 1e-6 * std::max(1.0, std::abs(r.hi));
    out.push_back(text_of(r.hi_open ? r.hi : r.hi + step));
  }
  return out;
}

std::vector<std::string> inside(const ParamSpec& p) {
  std::vector<std::string> out;
  const ParamRange& r = p.range;
  const bool integer = p.type == ParamType::Integer;
  if (std::isfinite(r.lo)) {
    const double step = integer ? 1.0 : 1e-6 * std::max(1.0, std::abs(r.lo));
    out.push_back(text_of(r.lo_open ? r.lo + step : r.lo));
  }
  if (std::isfinite(r.hi)) {
    const double step = integer ? 1.0 : 1e-6 * std::max(1.0, std::abs(r.hi));
    out.push_back(r.hi >= 1e15 ? "18446744073709551615" : text_of(r.hi_open ? r.hi - step : r.hi));
  }
  return out;
}

TEST(ScenarioKeys, EverySectionHasAHostAndUniqueKeys) {
  const auto h = hosts();
  std::set<std::string> ids;
  for (const ScenarioKeySection& s : scenario_key_sections()) {
    EXPECT_TRUE(ids.insert(s.id).second) << s.id;
    EXPECT_TRUE(h.count(s.id)) << "no host scenario for section " << s.id;
    std::set<std::string> keys;
    for (const ScenarioKeyRow& r : s.rows) EXPECT_TRUE(keys.insert(r.key).second) << s.id << "." << r.key;
    // Each host is a valid scenario as it stands.
    if (h.count(s.id)) {
      const Host& host = h.at(s.id);
      if (!host.field.empty()) {
        std::string map = "{";
        for (const auto& [k, v] : host.entries) map += (map.size() > 1 ? ", " : "") + k + ": " + v;
        EXPECT_NO_THROW(parse_scenario(host.before + map + "}" + host.after, "case.yaml")) << s.id;
      }
    }
  }
  EXPECT_GT(ids.size(), 30u);
}

TEST(ScenarioKeys, UnknownKeysAreOneErrorNamingTheKnownOnes) {
  const auto h = hosts();
  for (const ScenarioKeySection& s : scenario_key_sections()) {
    const Host& host = h.at(s.id);
    if (host.components) continue;  // the navigation stack names them (tests/harness)
    const auto [yaml, line] = with_value(host, "no_such_key", "1");
    const std::string what = refused(yaml, line, host.field.empty() ? "no_such_key" : host.field + ".no_such_key");
    EXPECT_NE(what.find("unknown key 'no_such_key'"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    for (const ScenarioKeyRow& r : s.rows) EXPECT_NE(what.find(r.key), std::string::npos) << s.id << ": " << r.key << " in " << what;
  }
}

TEST(ScenarioKeys, ValuesOutsideTheDeclaredRangeAndOfTheWrongTypeAreRefused) {
  const auto h = hosts();
  int ranges = 0, types = 0;
  for (const ScenarioKeySection& s : scenario_key_sections()) {
    const Host& host = h.at(s.id);
    for (const ParamSpec& p : s.specs) {
      const std::string field = host.field.empty() ? p.key : host.field + "." + p.key;
      if (p.type == ParamType::Real || p.type == ParamType::Integer)
        for (const std::string& v : outside(p)) {
          const auto [yaml, line] = with_value(host, p.key, v);
          refused(yaml, line, field);
          ++ranges;
        }
      // A list where a value belongs (a mapping where a list belongs).
      const bool list = p.type == ParamType::Reals || p.type == ParamType::NameList || p.type == ParamType::Polygons;
      const auto [yaml, line] = with_value(host, p.key, list ? "{a: 1}" : "[1, 2]");
      const std::string what = refused(yaml, line, field);
      EXPECT_NE(what.find("expected"), std::string::npos) << what;
      ++types;
      if (p.type == ParamType::Real || p.type == ParamType::Integer || p.type == ParamType::Boolean ||
          (p.type == ParamType::Choice && p.key != "preset" && p.key != "class")) {
        const auto [bad, bad_line] = with_value(host, p.key, "nonsense");
        refused(bad, bad_line, field);
        ++types;
      }
    }
  }
  EXPECT_GT(ranges, 60);
  EXPECT_GT(types, 100);
}

TEST(ScenarioKeys, TheTablesAcceptValuesJustInsideTheirRanges) {
  int checked = 0;
  for (const ScenarioKeySection& s : scenario_key_sections())
    for (const ParamSpec& p : s.specs) {
      if (p.type != ParamType::Real && p.type != ParamType::Integer) continue;
      for (const std::string& v : inside(p)) {
        EXPECT_NO_THROW(s.apply({p.key, v, "case.yaml", 3, s.id + "." + p.key})) << s.id << "." << p.key << " = " << v;
        ++checked;
      }
      for (const std::string& v : outside(p)) {
        const std::string what = test::error_of([&] { s.apply({p.key, v, "case.yaml", 3, s.id + "." + p.key}); });
        EXPECT_EQ(what.rfind("case.yaml:3: " + s.id + "." + p.key + ": ", 0), 0u) << what;
      }
    }
  EXPECT_GT(checked, 60);
}

TEST(ScenarioKeys, ScenariosPageTablesAreCurrent) {
  const std::string path = (std::filesystem::path(STARNAV_SOURCE_DIR) / "docs" / "scenarios.md").string();
  const std::string page = test::read_text(path);
  EXPECT_TRUE(scenario_page_with_keys(page) == page)
      << "docs/scenarios.md is stale: run `build/bin/starnav scenario-keys --fill docs/scenarios.md > /tmp/s.md && mv /tmp/s.md "
         "docs/scenarios.md`";
  for (const ScenarioKeySection& s : scenario_key_sections())
    EXPECT_NE(page.find("<!-- BEGIN scenario-keys " + s.id + " "), std::string::npos) << "no table for " << s.id;
  EXPECT_NE(test::error_of([] { scenario_page_with_keys("<!-- BEGIN scenario-keys nonesuch (x) -->\n"); }).find("nonesuch"),
            std::string::npos);
  EXPECT_NE(test::error_of([] { scenario_page_with_keys("<!-- BEGIN scenario-keys robot (x) -->\nno end\n"); }).find("END"),
            std::string::npos);
}

TEST(ScenarioKeys, EveryScenarioOfTheRepositoryLoads) {
  int loaded = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(STARNAV_SOURCE_DIR) / "scenarios")) {
    if (e.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(load_scenario(e.path().string())) << e.path();
    ++loaded;
  }
  EXPECT_GE(loaded, 20);
}

}  // namespace
}  // namespace starnav
