// Error-line discipline and consistent acceptance across commands: each row is one member found
// while hardening, answered with exit 2 and one line that names the right flag, file or field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace starnav {
namespace {

struct ErrorLineCase {
  std::vector<std::string> args;
  std::string expected;  // a part of the one error line
  std::string not_expected = {};
};

void expect_one_error_line(const ErrorLineCase& c) {
  std::string line;
  for (const std::string& a : c.args) line += a + " ";
  SCOPED_TRACE(line);
  const test::CliResult r = test::run_cli(c.args);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  if (!c.not_expected.empty()) {
    EXPECT_EQ(r.err.find(c.not_expected), std::string::npos) << r.err;
  }
}

TEST(ErrorLinesCli, UsageMistakesAreNamedForWhatTheyAre) {
  test::ScratchDir dir;
  const std::string map = test::test_data("movingai_tiny.map");
  test::write_text(dir.file("generated_with_features.yaml"),
                   "world:\n  terrain:\n    generate: {kind: flat, size_m: [10, 10], resolution_m: 0.5}\n    features: []\n");
  const std::vector<ErrorLineCase> cases = {
      // A misspelt option is the mistake, not the required option it hides.
      {{"plan", "--bogus"}, "unknown option --bogus", "--map is required"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--bogus", "3"}, "unknown option --bogus"},
      // An option given twice, in plain words.
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--goal", "2,2"}, "--goal: given 2 times; give it once"},
      // Which planners take a weight is their capability (the registry's word, not the CLI's).
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--planner", "astar", "--weight", "2"},
       "--weight: 'astar' takes no weight (planners that do: wastar)"},
      {{"sim", ".", "--out", dir.file("o")}, "is a directory"},
      // A misspelt command is named, with the commands it may have meant.
      {{"simulate", "scenarios/e1_terrain_platform.yaml"}, "unknown command 'simulate' for starnav (did you mean 'sim'?)"},
      {{"bench", "navv"}, "unknown command 'navv' for starnav bench (did you mean 'nav'?)"},
      {{"frobnicate"}, "unknown command 'frobnicate' for starnav (commands: map plan"},
      {{"params", "--role", "planner"}, "--role: unknown role 'planner' (roles: global_planner, local_controller"},
      {{"sim", dir.file("generated_with_features.yaml"), "--out", dir.file("o2")},
       "world.terrain.features: with 'generate', put 'features' inside 'generate:'"},
  };
  for (const ErrorLineCase& c : cases) expect_one_error_line(c);
}

TEST(ErrorLinesCli, EveryCountSeedAndCoordinateIsReadOneWay) {
  test::ScratchDir dir;
  const std::string map = test::test_data("movingai_tiny.map");
  const std::vector<std::string> road = {"terrain", "generate", "--kind", "road", "--size-m", "2,2", "--resolution", "0.1",
                                         "--out", dir.file("road.asc")};
  auto with = [](std::vector<std::string> base, std::initializer_list<std::string> more) {
    base.insert(base.end(), more);
    return base;
  };
  const std::vector<ErrorLineCase> cases = {
      // Negative counts and seeds are refused, never wrapped to 2^64 - 1.
      {{"bench", "movingai", "--map", map, "--limit", "-1"}, "--limit: expected a non-negative whole number, got '-1'"},
      {{"bench", "ablation", "--map", map, "--random", "2", "--seed", "-1", "--out", dir.file("a1")}, "--seed:"},
      {{"localize", "log", "--map", "m.yaml", "--out", dir.file("l1"), "--initial", "global", "--seed", "-1"}, "--seed:"},
      // Digits too many for 64 bits are out of range; anything else is not a number at all.
      {{"sim", test::kE1, "--out", dir.file("s1"), "--quiet", "--seed", "99999999999999999999999"},
       "--seed: out of range (at most 2^64 - 1)"},
      {{"sim", test::kE1, "--out", dir.file("s2"), "--quiet", "--seed", "1+2"}, "--seed: expected a non-negative integer, got '1+2'"},
      // Hex and octal are not numbers here (CLI11 alone would read "010" as eight).
      {{"bench", "movingai", "--map", map, "--limit", "0x3"}, "--limit: expected a non-negative whole number, got '0x3'"},
      {{"plan", "--map", map, "--start", "0x1,1", "--goal", "2,2"}, "--start"},
      {with(road, {"--resolution", "0x1p-3"}), "--resolution"},
      // Empty strings are not values.
      {with(road, {"--class", ""}), "--class: empty value"},
      {with(road, {"--seed", ""}), "--seed: empty value"},
      // Each road method's own knob is refused with the other method, not ignored.
      {with(road, {"--blur-cells", "3"}), "--blur-cells: only for --method paper"},
      {with(road, {"--method", "paper", "--directions", "8"}), "--directions: only for --method directional"},
      // Queries for another map, and endpoints off the map, are the user's mistake.
      {{"bench", "terrain", "--generate", "1", "--start", "50,50", "--goal", "1,1", "--out", dir.file("t1")},
       "--start: (50, 50) m is outside the map"},
  };
  for (const ErrorLineCase& c : cases) expect_one_error_line(c);
}

// One rule per kind of number and name, whatever command reads it: a count, a size or a seed
// takes no sign (not "-3" for "all" on one command, not "+16"), and a planner is named as the
// registry names it (an old spelling warns everywhere `plan` accepts it).
TEST(ErrorLinesCli, CountsTakeNoSignAndPlannersAreTheRegistrysEverywhere) {
  test::ScratchDir dir;
  const std::string map = test::test_data("movingai_tiny.map");
  const std::string no_sign = "expected a non-negative whole number, got ";
  const std::vector<ErrorLineCase> cases = {
      {{"bench", "ablation", "--map", map, "--random", "2", "--svg-limit", "-3", "--out", dir.file("a1")}, "--svg-limit: " + no_sign + "'-3'"},
      {{"bench", "terrain", "--generate", "1", "--svg-limit", "-3", "--out", dir.file("t1")}, "--svg-limit: " + no_sign + "'-3'"},
      {{"bench", "ablation", "--map", map, "--random", "2", "--seed", "+16", "--out", dir.file("a2")}, "--seed: " + no_sign + "'+16'"},
      {{"bench", "ablation", "--map", map, "--random", "+2", "--out", dir.file("a3")}, "--random: " + no_sign + "'+2'"},
      {{"bench", "movingai", "--map", map, "--repeat", "-1"}, "--repeat: " + no_sign + "'-1'"},
      {{"sim", test::kE1, "--out", dir.file("s1"), "--quiet", "--seed", "+16"}, "--seed: expected a non-negative integer, got '+16'"},
      {{"sim", test::kE1, "--out", dir.file("s2"), "--quiet", "--set", "sim.seed=+16"}, "sim.seed"},
      {{"bench", "movingai", "--map", map, "--planner", "oa"}, "--planner: 'oa' plans on elevation maps"},
      {{"bench", "movingai", "--map", map, "--planner", "nosuch"}, "--planner: unknown planner 'nosuch' (dijkstra, astar"},
  };
  for (const ErrorLineCase& c : cases) expect_one_error_line(c);
  // The old spelling runs under its registry name, with plan's warning, not "unknown planner".
  test::write_text(dir.file("tiny.scen"), "version 1\n0\tmovingai_tiny.map\t5\t3\t0\t0\t1\t0\t1\n");
  const test::CliResult old =
      test::run_cli({"bench", "movingai", "--map", map, "--scen", dir.file("tiny.scen"), "--planner", "dstarlite", "--json"});
  EXPECT_EQ(old.exit_code, 0) << old.err;
  EXPECT_NE(old.err.find("starnav: warning: --planner: 'dstarlite' is deprecated; use 'dstar_lite'\n"), std::string::npos) << old.err;
  EXPECT_NE(old.out.find("\"dstar_lite\""), std::string::npos) << old.out;
}

TEST(ErrorLinesCli, AblationQueriesMustBeForTheMapTheyRunOn) {
  test::ScratchDir dir;
  const std::string map = test::test_data("movingai_tiny.map");  // 5 x 3
  test::write_text(dir.file("q.map.scen"), "version 1\n0\tother.map\t49\t49\t1\t1\t2\t2\t1.41421356\n");
  test::write_text(dir.file("q.csv"), "start_x,start_y,goal_x,goal_y\n0,0,7,1\n");
  expect_one_error_line({{"bench", "ablation", "--map", map, "--queries", dir.file("q.map.scen"), "--out", dir.file("a")},
                         "problem 1 is for a 49 x 49 map"});
  expect_one_error_line({{"bench", "ablation", "--map", map, "--queries", dir.file("q.csv"), "--out", dir.file("b")},
                         "q.csv:2: a cell outside the 5 x 3 map"});
}

TEST(ErrorLinesCli, AByteOrderMarkReadsTheSameInEveryTextFormat) {
  test::ScratchDir dir;
  const std::string bom = "\xEF\xBB\xBF";
  const std::string map_text = test::read_text(test::test_data("movingai_tiny.map"));
  test::write_text(dir.file("bom.map"), bom + map_text);
  const test::CliResult plain = test::run_cli({"map", "info", test::test_data("movingai_tiny.map"), "--json"});
  const test::CliResult marked = test::run_cli({"map", "info", dir.file("bom.map"), "--json"});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(marked.exit_code, 0) << marked.err;
  // The same cells, so the same counts (the file name differs).
  for (const char* key : {"\"free\"", "\"occupied\"", "\"width\"", "\"height\""}) {
    const auto a = plain.out.find(key), b = marked.out.find(key);
    ASSERT_NE(a, std::string::npos) << plain.out;
    ASSERT_NE(b, std::string::npos) << marked.out;
    EXPECT_EQ(plain.out.substr(a, plain.out.find(',', a) - a), marked.out.substr(b, marked.out.find(',', b) - b));
  }
}

TEST(ErrorLinesCli, ConvertingToAFormatThatLosesInformationWarns) {
  test::ScratchDir dir;
  const test::CliResult r = test::run_cli({"map", "convert", test::test_data("ros_modes.yaml"), dir.file("x.map")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("starnav: warning: "), std::string::npos);
  EXPECT_NE(r.err.find("origin"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("unknown cells become obstacles"), std::string::npos) << r.err;
  // A lossless conversion says nothing.
  const test::CliResult back = test::run_cli({"map", "convert", dir.file("x.map"), dir.file("y.map")});
  ASSERT_EQ(back.exit_code, 0) << back.err;
  EXPECT_EQ(back.err, "");
}

TEST(ErrorLinesCli, RunningOutOfMemoryNamesTheFileBeingRead) {
  if (test::kUnderAddressSanitizer) GTEST_SKIP() << "AddressSanitizer reserves more address space than a memory limit allows";
  test::ScratchDir dir;
  // 8000 x 8000 cells: 64 MB of text, which with its cells is more than a 100 MB address space.
  {
    std::string text = "type octile\nheight 8000\nwidth 8000\nmap\n";
    const std::string row = std::string(8000, '.') + "\n";
    text.reserve(text.size() + row.size() * 8000);
    for (int i = 0; i < 8000; ++i) text += row;
    test::write_text(dir.file("big.map"), text);
  }
  const std::string cmd = "ulimit -v 100000; " + test::shell_quote(STARNAV_CLI_PATH) + " map info " +
                          test::shell_quote(dir.file("big.map")) + " >/dev/null 2>" + test::shell_quote(dir.file("err"));
  const int status = std::system(("sh -c " + test::shell_quote(cmd)).c_str());
  const std::string err = test::read_text(dir.file("err"));
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) GTEST_SKIP() << "the map fitted under the limit here";
  EXPECT_EQ(WEXITSTATUS(status), 2) << err;
  EXPECT_EQ(err, "starnav: error: " + dir.file("big.map") + ": out of memory while reading it\n");
}

// A --set that the command would override, or a key given twice, is refused: no setting is
// silently ignored.
TEST(ErrorLinesCli, ASetTheCommandWouldOverrideIsRefused) {
  test::ScratchDir dir;
  const std::string scenarios = std::string(STARNAV_SOURCE_DIR) + "/scenarios/";
  const std::string e1 = scenarios + "e1_terrain_platform.yaml";
  const std::string e2 = scenarios + "e2_stochastic_pit_mound.yaml";
  const std::string e3 = scenarios + "e3_three_obstacles.yaml";
  const std::vector<ErrorLineCase> cases = {
      {{"bench", "nav", "--scenario", e2, "--seeds", "1", "--set", "navigation.planner=jps"},
       "navigation.planner (--set): the command sets navigation.planner itself (bench nav runs dstar_lite and astar"},
      {{"bench", "nav", "--scenario", e2, "--seeds", "1", "--set", "sim.seed=3"}, "sim.seed (--set): the command sets sim.seed"},
      {{"bench", "nav", "--scenario", e2, "--seeds", "1", "--motion-mode", "holonomic", "--set", "motion_mode=turn_then_drive"},
       "motion_mode (--set): the command sets motion_mode itself (--motion-mode gives it)"},
      {{"sim", e1, "--out", dir.file("a"), "--seed", "3", "--set", "sim.seed=4"}, "sim.seed (--set): the command sets sim.seed"},
      {{"sim", e1, "--out", dir.file("b"), "--duration", "3", "--set", "sim.duration_s=4"}, "sim.duration_s (--set)"},
      {{"sim", e3, "--out", dir.file("c"), "--planner", "jps", "--set", "navigation.planner=astar"}, "navigation.planner (--set)"},
      {{"sim", e3, "--out", dir.file("d"), "--controller", "dwa", "--set", "navigation.controller=path_follower"},
       "navigation.controller (--set)"},
      {{"sim", e1, "--out", dir.file("e"), "--set", "sim.seed=4", "--set", "sim.seed=5"}, "sim.seed (--set): given twice"},
      {{"bench", "mapping3d", "--seeds", "1", "--scenario", scenarios + "ou2022_mapping3d.yaml", "--set", "sim.seed=2"},
       "sim.seed (--set): the command sets sim.seed"},
      {{"bench", "ekf-square", "--seeds", "1", "--set", "localization.ekf.bias_state=false"},
       "localization.ekf.bias_state (--set): the command sets"},
      {{"slam", "run", e1, "--out", dir.file("f"), "--set", "submap_nodes=3", "--set", "submap_nodes=4"},
       "--set submap_nodes: given twice"},
  };
  for (const ErrorLineCase& c : cases) expect_one_error_line(c);
}

TEST(ErrorLinesCli, WildCoordinatesAreOneLineAtTheirLineNeverAnInternalError) {
  // Poses of 1e19..1e300 m made map build loop (a cast beyond int64), a three-line log printed
  // the standard library's "cannot create std::vector larger than max_size()", and a reference
  // pose of 1e300 hung slam3d's picture.
  test::ScratchDir dir;
  std::string ranges;
  for (int i = 0; i < 180; ++i) ranges += " " + std::to_string(1.0 + 0.01 * i);
  const auto flaser = [&](const std::string& pose, const std::string& t) { return "FLASER 180" + ranges + " " + pose + " " + t + " h " + t + "\n"; };
  test::write_text(dir.file("wild.clf"), flaser("0 0 0 0 0 0", "1.0") + flaser("1e19 0 0 1e19 0 0", "2.0") + flaser("1e19 1e19 0 0 0 0", "3.0"));
  test::write_text(dir.file("far.clf"), flaser("0 0 0 0 0 0", "1.0") + flaser("9e8 0 0 9e8 0 0", "2.0"));
  const std::string frames = dir.file("frames");
  std::filesystem::create_directories(frames);
  test::write_text(frames + "/sensor.yaml",
                   "model: custom\nlines: 1\nbeams: 8\nrate_hz: 10\nrange_min_m: 0.1\nrange_max_m: 10\n"
                   "mount: {x_m: 0, y_m: 0, z_m: 0, roll_deg: 0, pitch_deg: 0, yaw_deg: 0}\n");
  test::write_text(frames + "/frames.csv",
                   "frame,t_s,cloud,odom_x_m,odom_y_m,odom_yaw_rad,imu_yaw_rate_radps,true_x_m,true_y_m,true_z_m,true_roll_rad,"
                   "true_pitch_rad,true_yaw_rad\n0,0.0,0.pcd,0,0,0,,1e300,-1e300,0,0,0,0\n");
  const std::vector<ErrorLineCase> cases = {
      {{"map", "build", dir.file("wild.clf"), "--out", dir.file("m1.yaml")}, "wild.clf:2: FLASER x: 1e+19 m lies farther than", "std::"},
      {{"slam", "run", dir.file("wild.clf"), "--out", dir.file("s1"), "--quiet"}, "wild.clf:2: FLASER x:", "std::"},
      {{"log", "info", dir.file("wild.clf")}, "wild.clf:2: FLASER x:", "std::"},
      {{"map", "build", dir.file("far.clf"), "--out", dir.file("m2.yaml")}, "far.clf:2: resolution_m: a pose or reading at (900000000, -1) m lies far outside the mapped area", "std::"},
      {{"slam", "run", dir.file("far.clf"), "--out", dir.file("s2"), "--quiet"}, "far.clf:2: resolution_m: a pose or reading at", "std::"},
      {{"slam3d", frames, "--out", dir.file("d")}, "frames.csv:2: true_x_m: 1e+300 m lies farther than", "std::"},
  };
  for (const ErrorLineCase& c : cases) expect_one_error_line(c);
}

}  // namespace
}  // namespace starnav
