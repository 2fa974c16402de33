// `starnav plan` end to end: exit codes 0 / 1 / 2, the JSON keys, units on MovingAI and metric
// maps, --out and --force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::run_cli;

// 6 x 4, y counted from the top:
//   ......
//   .@@@@.
//   .@....
//   .@.@@@
const char* kMap = "type octile\nheight 4\nwidth 6\nmap\n......\n.@@@@.\n.@....\n.@.@@@\n";

nlohmann::json parse_json(const std::string& out) {
  try {
    return nlohmann::json::parse(out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not JSON: " << out;
    return {};
  }
}

TEST(CliPlan, FoundPrintsEveryKeyAndExitsZero) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  const auto r = run_cli({"plan", "--map", map, "--start", "0,3", "--goal", "2,3", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse_json(r.out);
  for (const char* key : {"planner", "admissible", "found", "cost", "length", "expanded", "generated", "time_ms",
                          "path", "path_cells"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_FALSE(j.contains("reason"));
  EXPECT_EQ(j["planner"], "astar");
  EXPECT_EQ(j["found"], true);
  // Around the wall: up the left column (3), along the top (5), down the right column (2), left
  // (3), down (1); every corner would need a cut, so no diagonal move helps.
  EXPECT_DOUBLE_EQ(j["cost"].get<double>(), 14.0);
  const auto cells = j["path_cells"];
  ASSERT_GE(cells.size(), 2u);
  EXPECT_EQ(cells.front(), nlohmann::json::array({0, 3}));
  EXPECT_EQ(cells.back(), nlohmann::json::array({2, 3}));
  EXPECT_EQ(j["path"], j["path_cells"]);  // cells on MovingAI maps
  EXPECT_GT(j["expanded"].get<int>(), 0);
  EXPECT_DOUBLE_EQ(j["cost"].get<double>(), j["length"].get<double>());
}

TEST(CliPlan, EveryPlannerAgreesOnTheCost) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  const auto ref = parse_json(run_cli({"plan", "--map", map, "--start", "0,3", "--goal", "2,3", "--json"}).out);
  for (const char* planner : {"dijkstra", "astar", "wastar", "jps", "jpsplus", "dstarlite", "thetastar"}) {
    const auto r = run_cli({"plan", "--map", map, "--start", "0,3", "--goal", "2,3", "--planner", planner, "--json"});
    ASSERT_EQ(r.exit_code, 0) << planner << ": " << r.err;
    const auto j = parse_json(r.out);
    // The old spelling dstarlite runs D* Lite under its registry name, with a warning.
    EXPECT_EQ(j["planner"], std::string(planner) == "dstarlite" ? "dstar_lite" : planner);
    if (std::string(planner) == "dstarlite") {
      EXPECT_NE(r.err.find("deprecated; use 'dstar_lite'"), std::string::npos) << r.err;
    }
    if (std::string(planner) == "thetastar") EXPECT_LE(j["cost"].get<double>(), ref["cost"].get<double>() + 1e-9);
    else EXPECT_NEAR(j["cost"].get<double>(), ref["cost"].get<double>(), 1e-9) << planner;
  }
  const auto w = parse_json(
      run_cli({"plan", "--map", map, "--start", "0,3", "--goal", "2,3", "--planner", "wastar", "--weight", "2", "--json"}).out);
  EXPECT_EQ(w["admissible"], false);
}

TEST(CliPlan, NoAnswerIsAResultWithExitOne) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  struct Case {
    const char* start;
    const char* goal;
    const char* reason;
  };
  for (const Case c : {Case{"9,0", "0,0", "start_outside_map"}, Case{"0,0", "0,-1", "goal_outside_map"},
                       Case{"1,1", "0,0", "start_blocked"}, Case{"0,0", "3,3", "goal_blocked"}}) {
    const auto r = run_cli({"plan", "--map", map, "--start", c.start, "--goal", c.goal, "--json"});
    EXPECT_EQ(r.exit_code, 1) << c.reason;
    const auto j = parse_json(r.out);
    EXPECT_EQ(j["found"], false);
    EXPECT_EQ(j["reason"], c.reason);
    EXPECT_TRUE(j["path"].empty());
  }
  const auto limited = run_cli({"plan", "--map", map, "--start", "0,3", "--goal", "2,3", "--max-expansions", "2", "--json"});
  EXPECT_EQ(limited.exit_code, 1);
  EXPECT_EQ(parse_json(limited.out)["reason"], "expansion_limit");
  const auto text = run_cli({"plan", "--map", map, "--start", "1,1", "--goal", "0,0"});
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_NE(text.out.find("start_blocked"), std::string::npos);
}

TEST(CliPlan, BadInputIsAnErrorWithExitTwo) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  struct Case {
    std::vector<std::string> args;
    const char* mentions;
  };
  const std::vector<Case> cases = {
      {{"plan", "--map", map, "--start", "0", "--goal", "1,1"}, "--start"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1.5,1"}, "--goal"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--planner", "bfs"}, "--planner"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--connectivity", "6"}, "--connectivity"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--planner", "wastar", "--weight", "0.5"}, "--weight"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--weight", "2"}, "--weight"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--unknown", "maybe"}, "--unknown"},
      {{"plan", "--map", dir.file("missing.map"), "--start", "0,0", "--goal", "1,1"}, "missing.map"},
      {{"plan", "--map", map, "--start", "0,0", "--goal", "1,1", "--planner", "jps", "--connectivity", "4"}, "connectivity"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.mentions << ": " << r.out;
    EXPECT_NE(r.err.find("starnav: error:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.mentions), std::string::npos) << r.err;
  }
}

TEST(CliPlan, OutWritesCsvAndNeedsForceToOverwrite) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  const std::string csv = dir.file("path.csv");
  const std::vector<std::string> args = {"plan", "--map", map, "--start", "0,0", "--goal", "5,0", "--out", csv};
  ASSERT_EQ(run_cli(args).exit_code, 0);
  EXPECT_EQ(test::read_text(csv), "x_cell,y_cell\n0,0\n1,0\n2,0\n3,0\n4,0\n5,0\n");
  const auto again = run_cli(args);
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos);
  auto forced = args;
  forced.push_back("--force");
  EXPECT_EQ(run_cli(forced).exit_code, 0);
}

TEST(CliPlan, MetricMapsUseMetres) {
  test::ScratchDir dir;
  // 4 x 3 cells of 0.5 m, origin (1, 2); the image's top row is the map's top row (iy = 2).
  test::write_text(dir.file("m.pgm"), "P2\n4 3\n255\n254 254 254 254\n254 0 0 254\n254 254 254 254\n");
  test::write_text(dir.file("m.yaml"),
                   "image: m.pgm\nresolution: 0.5\norigin: [1.0, 2.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
                   "free_thresh: 0.196\n");
  const auto r = run_cli({"plan", "--map", dir.file("m.yaml"), "--start", "1.2,2.3", "--goal", "2.9,2.1", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse_json(r.out);
  EXPECT_EQ(j["path_cells"].front(), nlohmann::json::array({0, 0}));
  EXPECT_EQ(j["path_cells"].back(), nlohmann::json::array({3, 0}));
  EXPECT_NEAR(j["path"].front()[0].get<double>(), 1.25, 1e-12);
  EXPECT_NEAR(j["path"].front()[1].get<double>(), 2.25, 1e-12);
  EXPECT_NEAR(j["cost"].get<double>(), 1.5, 1e-12);  // three cells of 0.5 m along the bottom row
  // --cells: the same query in cell indices.
  const auto c = run_cli({"plan", "--map", dir.file("m.yaml"), "--cells", "--start", "0,0", "--goal", "3,0", "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_EQ(parse_json(c.out)["path_cells"], j["path_cells"]);
  // A world point outside the map is a result.
  const auto out = run_cli({"plan", "--map", dir.file("m.yaml"), "--start", "0.9,2.1", "--goal", "2.9,2.1", "--json"});
  EXPECT_EQ(out.exit_code, 1);
  EXPECT_EQ(parse_json(out.out)["reason"], "start_outside_map");
  // Through the middle row it is blocked; with the blocked cells, 4-connected is longer.
  const auto four = run_cli({"plan", "--map", dir.file("m.yaml"), "--cells", "--start", "0,0", "--goal", "3,2",
                             "--connectivity", "4", "--json"});
  EXPECT_NEAR(parse_json(four.out)["cost"].get<double>(), 2.5, 1e-12);
}

TEST(CliPlan, ExpandedCellsOnRequest) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  const auto j = parse_json(run_cli({"plan", "--map", map, "--start", "0,3", "--goal", "2,3", "--json", "--expanded"}).out);
  ASSERT_TRUE(j.contains("expanded_cells"));
  EXPECT_EQ(j["expanded_cells"].size(), j["expanded"].get<std::size_t>());
}

TEST(CliPlan, SvgDrawsThePicture) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  const std::string svg = dir.file("p.svg");
  const std::vector<std::string> args = {"plan", "--map", map, "--start", "0,3", "--goal", "2,3", "--svg", svg, "--expanded"};
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = test::read_text(svg);
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("path"), std::string::npos);
  EXPECT_NE(text.find("expanded"), std::string::npos);
  EXPECT_EQ(run_cli(args).exit_code, 2);  // exists: needs --force
  // No path: still a picture (map, start, goal), exit 1.
  const std::string none = dir.file("none.svg");
  EXPECT_EQ(run_cli({"plan", "--map", map, "--start", "0,0", "--goal", "3,3", "--svg", none}).exit_code, 1);
  EXPECT_NE(test::read_text(none).find("<svg"), std::string::npos);
}

// A planner between poses: headings in degrees, its parameters by --set, poses and reversing flags
// in the JSON; the pose flags are refused for the grid planners and the grid flags for it.
TEST(CliPlan, HybridAStarPlansBetweenPoses) {
  test::ScratchDir dir;
  // 60 x 40 cells of 0.1 m, a wall in the middle from the bottom (x 2.9 .. 3.1 m, y 0 .. 2.5 m).
  std::string pgm = "P2\n60 40\n255\n";
  for (int row = 0; row < 40; ++row) {
    const int iy = 39 - row;
    for (int ix = 0; ix < 60; ++ix) pgm += (ix >= 29 && ix <= 30 && iy < 25) ? "0 " : "254 ";
    pgm += "\n";
  }
  test::write_text(dir.file("m.pgm"), pgm);
  test::write_text(dir.file("m.yaml"),
                   "image: m.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
                   "free_thresh: 0.196\n");
  const std::vector<std::string> base = {"plan", "--map", dir.file("m.yaml"), "--planner", "hybrid_astar", "--start",
                                         "1.0,1.0", "--start-yaw-deg", "90", "--goal", "5.0,1.0"};
  auto args = base;
  for (const char* a : {"--goal-yaw-deg", "-90", "--set", "minimum_turning_radius_m=0.8", "--json"}) args.push_back(a);
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse_json(r.out);
  for (const char* key : {"planner", "found", "cost", "length", "units", "expanded", "generated", "cusps",
                          "reverse_length", "path", "reversing", "path_cells", "time_ms"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["planner"], "hybrid_astar");
  ASSERT_EQ(j["path"].size(), j["reversing"].size());
  EXPECT_NEAR(j["path"].front()[2].get<double>(), kPi / 2, 1e-9);
  EXPECT_NEAR(j["path"].back()[0].get<double>(), 5.0, 1e-6);
  EXPECT_NEAR(j["path"].back()[2].get<double>(), -kPi / 2, 1e-6);
  // Over the wall's top (2.5 m) with the default robot radius (0.25 m) to spare.
  double top = 0.0;
  for (const auto& p : j["path"]) top = std::max(top, p[1].get<double>());
  EXPECT_GT(top, 2.75);
  EXPECT_GT(j["length"].get<double>(), 2.0 * std::hypot(2.0, 1.75));
  // Errors, each naming its flag.
  const auto fails_naming = [&](std::vector<std::string> a, const std::string& flag) {
    const auto e = run_cli(a);
    EXPECT_EQ(e.exit_code, 2) << flag;
    EXPECT_NE(e.err.find(flag), std::string::npos) << e.err;
  };
  fails_naming(base, "--goal-yaw-deg");
  auto bad = args;
  bad.push_back("--set");
  bad.push_back("angle_bins=3");
  fails_naming(bad, "--set angle_bins");
  bad = args;
  bad.push_back("--weight");
  bad.push_back("2");
  fails_naming(bad, "--weight");
  fails_naming({"plan", "--map", dir.file("m.yaml"), "--start", "1,1", "--goal", "5,1", "--start-yaw-deg", "10"},
               "--start-yaw-deg");
  fails_naming({"plan", "--map", dir.file("m.yaml"), "--start", "1,1", "--goal", "5,1", "--set", "a=1"}, "--set");
}

}  // namespace
}  // namespace starnav
