// Every command that reads YAML reads it one way (io/yaml_document.hpp): nine nested levels of ten
// aliases (10^9 nodes once expanded, a few hundred bytes) are refused at once with one line naming
// the file, whichever reader meets them: map_server maps, elevation and RAW sidecars, scenarios and
// the maps they name, --set values, slam3d's sensor.yaml, localize's --map.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace starnav {
namespace {

struct YamlInputCase {
  std::vector<std::string> args;
  std::string blamed;  // the start of the error line after "starnav: error: "
};

// `[&a [x x 10], &b [*a x 10], ...]`: seven levels, 10^7 nodes expanded.
std::string alias_bomb_value() {
  std::string v = "[&l0 [x, x, x, x, x, x, x, x, x, x]";
  for (int i = 1; i < 7; ++i) {
    v += ", &l" + std::to_string(i) + " [";
    for (int j = 0; j < 10; ++j) v += (j ? ", *l" : "*l") + std::to_string(i - 1);
    v += "]";
  }
  return v + "]";
}

TEST(YamlInputsCli, NestedAliasesAreRefusedByEveryReader) {
  test::ScratchDir dir;
  const std::string bad = test::test_data("bad");
  const std::string map = bad + "/ros_alias_bomb.yaml";
  test::write_text(dir.file("tiny.clf"), "ODOM 0 0 0 0 0 0 1.0 h 1.0\nFLASER 3 1 1 1 0 0 0 0 0 0 1.0 h 1.0\n");
  const std::string expanded = "holds more than 200000 YAML nodes once its aliases are expanded";
  const std::vector<YamlInputCase> cases = {
      {{"map", "info", map}, map + ":13: "},
      {{"map", "info", bad + "/elev_alias_bomb.yaml"}, bad + "/elev_alias_bomb.yaml:12: "},
      {{"map", "info", bad + "/raw_alias_bomb.raw"}, bad + "/raw_alias_bomb.raw.yaml:15: "},
      {{"map", "convert", map, dir.file("m.map")}, map + ":13: "},
      {{"sim", bad + "/scenario_alias_bomb.yaml", "--out", dir.file("s1")}, bad + "/scenario_alias_bomb.yaml:8: "},
      {{"sim", test::scenario_path("amcl_indoor.yaml"), "--out", dir.file("s2"), "--set", "world.occupancy_map.file=" + map},
       test::scenario_path("amcl_indoor.yaml")},
      {{"sim", test::kE1, "--out", dir.file("s3"), "--set", "world.obstacles=" + alias_bomb_value()}, "--set world.obstacles: "},
      {{"slam3d", bad + "/frames_alias_bomb", "--out", dir.file("d")}, bad + "/frames_alias_bomb/sensor.yaml:14: "},
      {{"localize", dir.file("tiny.clf"), "--map", map, "--out", dir.file("l"), "--initial", "0,0,0"}, map + ":13: "},
  };
  for (const YamlInputCase& c : cases) {
    std::string line;
    for (const std::string& a : c.args) line += a + " ";
    SCOPED_TRACE(line);
    const test::CliResult r = test::run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("starnav: error: " + c.blamed, 0), 0u) << r.err;
    EXPECT_NE(r.err.find(expanded), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace starnav
