// starnav plan on elevation maps and starnav bench terrain (docs/terrain.md): the CLI's numbers equal the
// library's on the same map, JSON keys, exit codes, flags named in errors, report files.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "starnav/io/elevation_io.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/terrain/terrain_path_metrics.hpp"
#include "starnav/terrain/rough_terrain_planners.hpp"
#include "starnav/terrain/terrain_generator.hpp"
#include "support/test_support.hpp"

namespace {

using namespace starnav;
using test::run_cli;
using test::ScratchDir;
using json = nlohmann::json;

// A 4 m x 3 m hills terrain (gentle, so that every planner finds a path), written as ASC (every
// digit kept) and read back: the CLI and the test plan on the same heights.
struct TerrainFile {
  ScratchDir dir;
  std::string path;
  ElevationMap map;
  explicit TerrainFile(double amplitude = 0.15, bool hole_at_goal = false) {
    HillsOptions h;
    h.width_m = 4.0;
    h.height_m = 3.0;
    h.seed = 11;
    h.amplitude = amplitude;
    ElevationMap m = generate_hills(h);
    if (hole_at_goal) m.clear_cell(35, 25);
    path = dir.file("terrain.asc");
    write_asc(m, path);
    map = load_map(path).elevation();
  }
};

const std::vector<std::string> kMetricKeys = {"lv_m",          "av_rad",         "hv_m",          "sv_m2",
                                              "roll_mean_deg", "roll_max_deg",   "pitch_mean_deg", "pitch_max_deg",
                                              "tilt_mean_deg", "tilt_max_deg"};

TEST(CliPlanTerrain, JsonEqualsTheLibraryForEveryPlanner) {
  TerrainFile t;
  for (const std::string name : {"oa", "aoea", "ia"}) {
    std::vector<std::string> args = {"plan", "--map", t.path, "--start", "0.25,0.25", "--goal", "3.55,2.55",
                                     "--planner", name, "--json"};
    const auto r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    const json j = json::parse(r.out);
    for (const char* k : {"planner", "admissible", "found", "cost", "length", "units", "expanded", "generated", "path",
                          "path_cells", "time_ms"})
      EXPECT_TRUE(j.contains(k)) << name << ": " << k;
    for (const std::string& k : kMetricKeys) ASSERT_TRUE(j.contains(k) && j[k].is_number()) << name << ": " << k;
    EXPECT_EQ(j["planner"], name);
    EXPECT_TRUE(j["found"].get<bool>());

    // The library on the same map with the CLI's defaults (IA*: the paper's H, reopening).
    RoughTerrainPlannerOptions o;
    o.heuristic = LiuHeuristic::Paper;
    RoughTerrainPlanner planner(parse_rough_terrain_planner(name), t.map, o);
    EXPECT_EQ(j["admissible"].get<bool>(), planner.admissible());
    const Cell s{2, 2}, g{35, 25};  // the cells of (0.25, 0.25) and (3.55, 2.55) at 0.1 m
    const PlanResult want = planner.plan(s, g);
    ASSERT_TRUE(want.found());
    ASSERT_EQ(j["path_cells"].size(), want.path_cells.size()) << name;
    for (std::size_t i = 0; i < want.path_cells.size(); ++i) {
      EXPECT_EQ(j["path_cells"][i][0].get<int>(), want.path_cells[i].x);
      EXPECT_EQ(j["path_cells"][i][1].get<int>(), want.path_cells[i].y);
    }
    EXPECT_DOUBLE_EQ(j["cost"].get<double>(), want.cost);
    EXPECT_EQ(j["expanded"].get<std::uint64_t>(), want.expanded);
    const TerrainPathMetrics m = terrain_path_metrics(planner.analysis(), want.path_cells);
    EXPECT_DOUBLE_EQ(j["lv_m"].get<double>(), m.lv_m);
    EXPECT_DOUBLE_EQ(j["av_rad"].get<double>(), m.av_rad);
    EXPECT_DOUBLE_EQ(j["hv_m"].get<double>(), m.hv_m);
    EXPECT_DOUBLE_EQ(j["sv_m2"].get<double>(), m.sv_m2);
    EXPECT_DOUBLE_EQ(j["tilt_max_deg"].get<double>(), m.tilt_max_deg);
    EXPECT_DOUBLE_EQ(j["pitch_mean_deg"].get<double>(), m.pitch_mean_deg);
    // Invariants: the 3D length is at least the horizontal one; a tilt bounds roll and pitch.
    EXPECT_GE(j["lv_m"].get<double>(), j["length"].get<double>());
    EXPECT_GE(j["tilt_max_deg"].get<double>() + 1e-9, j["roll_max_deg"].get<double>());
    EXPECT_GE(j["tilt_max_deg"].get<double>() + 1e-9, j["pitch_max_deg"].get<double>());
  }
}

TEST(CliPlanTerrain, IaOptionsReachTheLibrary) {
  TerrainFile t;
  const auto r = run_cli({"plan", "--map", t.path, "--start", "0.25,0.25", "--goal", "3.55,2.55", "--planner", "ia",
                          "--admissible", "--cost-per-metre", "--weights", "0.2,0.3,0.5,0.7,0.3", "--hy-m", "0.08",
                          "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_TRUE(j["admissible"].get<bool>());
  EXPECT_EQ(j["heuristic"], "admissible");
  EXPECT_EQ(j["options"]["cost_per_metre"], true);
  EXPECT_DOUBLE_EQ(j["options"]["w1"].get<double>(), 0.7);
  RoughTerrainPlannerOptions o;
  o.heuristic = LiuHeuristic::Admissible;
  o.cost.cost_per_metre = true;
  o.cost.w_s = 0.2, o.cost.w_e = 0.3, o.cost.w_r = 0.5, o.cost.w1 = 0.7, o.cost.w2 = 0.3;
  o.cost.h_y = 0.08;
  RoughTerrainPlanner planner(RoughTerrainPlannerKind::IA, t.map, o);
  const PlanResult want = planner.plan({2, 2}, {35, 25});
  ASSERT_TRUE(want.found());
  EXPECT_DOUBLE_EQ(j["cost"].get<double>(), want.cost);
  // The reported cost is the path's cost under those options.
  std::vector<Cell> cells;
  for (const auto& c : j["path_cells"]) cells.push_back({c[0].get<int>(), c[1].get<int>()});
  EXPECT_NEAR(j["cost"].get<double>(), ia_path_cost(planner.analysis(), cells, o.cost), 1e-9);
}

TEST(CliPlanTerrain, NoAnswerIsExitOneWithReason) {
  TerrainFile t(0.15, true);
  const auto outside = run_cli({"plan", "--map", t.path, "--start", "-1,0.5", "--goal", "3.55,2.55", "--json"});
  EXPECT_EQ(outside.exit_code, 1) << outside.err;
  json j = json::parse(outside.out);
  EXPECT_FALSE(j["found"].get<bool>());
  EXPECT_EQ(j["reason"], "start_outside_map");
  for (const std::string& k : kMetricKeys) EXPECT_TRUE(j[k].is_null()) << k;
  // The goal cell is unobserved (a hole in the ASC): blocked for every planner.
  for (const std::string name : {"oa", "aoea", "ia"}) {
    const auto blocked =
        run_cli({"plan", "--map", t.path, "--start", "0.25,0.25", "--goal", "3.55,2.55", "--planner", name, "--json"});
    EXPECT_EQ(blocked.exit_code, 1) << name << ": " << blocked.err;
    j = json::parse(blocked.out);
    EXPECT_EQ(j["reason"], "goal_blocked") << name;
  }
}

using test::BadFlagCase;

TEST(CliPlanTerrain, BadFlagsNameTheFlag) {
  TerrainFile t;  // its scratch folder (one per test: a second ScratchDir would share the path)
  const std::string occupancy = t.dir.file("grid.map");
  test::write_text(occupancy, "type octile\nheight 3\nwidth 3\nmap\n...\n...\n...\n");
  const std::vector<std::string> on_elevation = {"plan", "--map", t.path, "--start", "0.25,0.25", "--goal", "3.5,2.5"};
  const std::vector<BadFlagCase> cases = {
      {{"--hy-m", "-1"}, "--hy-m"},
      {{"--ay-rad", "2"}, "--ay-rad"},
      {{"--sy-m2", "0"}, "--sy-m2"},
      {{"--weights", "1,2"}, "--weights"},
      {{"--weights", "0.5,0.5,0.5,0.5,0.5"}, "--weights"},
      {{"--weights", "0.3,0.3,0.4,x,0.5"}, "--weights"},
      {{"--planner", "astar"}, "--planner"},
      {{"--planner", "dstar"}, "--planner"},
      {{"--planner", "oa", "--weights", "0.33,0.33,0.34,0.5,0.5"}, "--weights"},
      {{"--planner", "oa", "--hy-m", "0.1"}, "--hy-m"},
      {{"--planner", "ia", "--robot-radius-m", "0.2"}, "--robot-radius-m"},
      {{"--planner", "aoea", "--admissible"}, "--admissible"},
      {{"--unobserved", "maybe"}, "--unobserved"},
      {{"--inflate", "0.3"}, "--inflate"},
      {{"--connectivity", "4"}, "--connectivity"},
      {{"--turn-cost", "2"}, "--turn-cost"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = on_elevation;
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << c.flag << ": " << r.err;
    EXPECT_NE(r.err.find(c.flag), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << r.err;
  }
  // The Liu flags and planners on an occupancy map.
  for (const BadFlagCase& c : std::vector<BadFlagCase>{{{"--hy-m", "0.1"}, "--hy-m"},
                                               {{"--admissible"}, "--admissible"},
                                               {{"--planner", "ia"}, "--planner"}}) {
    std::vector<std::string> args = {"plan", "--map", occupancy, "--start", "0,0", "--goal", "2,2"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << c.flag << ": " << r.err;
    EXPECT_NE(r.err.find(c.flag), std::string::npos) << r.err;
  }
}

TEST(CliPlanTerrain, SvgAndCsv) {
  TerrainFile t;
  const auto r = run_cli({"plan", "--map", t.path, "--start", "0.25,0.25", "--goal", "3.55,2.55", "--planner", "aoea",
                          "--svg", t.dir.file("p.svg"), "--out", t.dir.file("p.csv")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_text(t.dir.file("p.svg")).find("<svg"), std::string::npos);
  const std::string csv = test::read_text(t.dir.file("p.csv"));
  EXPECT_EQ(csv.rfind("x_m,y_m,z_m,ix,iy\n", 0), 0u);
}

TEST(CliBenchTerrain, TwoGeneratedTerrainsWriteTheReport) {
  ScratchDir dir;
  const std::string out = dir.file("bench");
  const std::vector<std::string> args = {"bench", "terrain", "--generate", "2", "--seed", "5", "--amplitude", "0.5",
                                         "--out", out, "--svg-limit", "1", "--quiet"};
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("| IA* |"), std::string::npos) << r.out;
  for (const char* f : {"terrain.md", "terrain.json", "timing.json", "svg/hills_seed5_paths.svg",
                        "svg/hills_seed5_roll.svg", "svg/hills_seed5_pitch.svg", "svg/hills_seed5_tilt.svg"})
    EXPECT_TRUE(test::fs::exists(test::fs::path(out) / f)) << f;
  EXPECT_FALSE(test::fs::exists(test::fs::path(out) / "svg/hills_seed6_paths.svg"));
  const std::string text = test::read_text((test::fs::path(out) / "terrain.json").string());
  const json j = json::parse(text);
  EXPECT_EQ(j["benchmark"], "terrain");
  EXPECT_EQ(j["terrains"], 2);
  ASSERT_EQ(j["planners"].size(), 3u);
  ASSERT_EQ(j["per_terrain"].size(), 2u);
  ASSERT_EQ(j["comparisons"].size(), 2u);
  for (const char* k : {"terrains", "ia_lower_av", "ia_shorter", "lv_change_pct", "tilt_mean_change_pct"})
    EXPECT_TRUE(j["comparisons"][1].contains(k)) << k;

  // Every per-terrain result equals the library's run on the same generated terrain.
  for (int i = 0; i < 2; ++i) {
    HillsOptions h;
    h.seed = 5 + static_cast<std::uint64_t>(i);
    h.amplitude = 0.5;
    const ElevationMap m = generate_hills(h);
    const json& pt = j["per_terrain"][i];
    EXPECT_EQ(pt["seed"], h.seed);
    EXPECT_EQ(pt["start_cell"], json::array({5, 5}));
    EXPECT_EQ(pt["goal_cell"], json::array({95, 95}));
    for (const std::string name : {"oa", "aoea", "ia"}) {
      RoughTerrainPlannerOptions o;
      o.heuristic = LiuHeuristic::Paper;
      RoughTerrainPlanner planner(parse_rough_terrain_planner(name), m, o);
      const PlanResult want = planner.plan({5, 5}, {95, 95});
      ASSERT_EQ(pt[name]["found"].get<bool>(), want.found()) << name;
      for (const std::string& k : kMetricKeys) EXPECT_TRUE(pt[name].contains(k)) << k;
      if (!want.found()) continue;
      const TerrainPathMetrics mm = terrain_path_metrics(planner.analysis(), want.path_cells);
      EXPECT_DOUBLE_EQ(pt[name]["lv_m"].get<double>(), mm.lv_m) << name;
      EXPECT_DOUBLE_EQ(pt[name]["sv_m2"].get<double>(), mm.sv_m2) << name;
      EXPECT_DOUBLE_EQ(pt[name]["tilt_mean_deg"].get<double>(), mm.tilt_mean_deg) << name;
    }
  }
  // The summaries are the statistics of the per-terrain values.
  for (int p = 0; p < 3; ++p) {
    const std::string name = j["planners"][p]["planner"];
    std::vector<double> lv;
    for (const auto& pt : j["per_terrain"])
      if (pt[name]["found"].get<bool>()) lv.push_back(pt[name]["lv_m"].get<double>());
    const json& s = j["planners"][p]["own_found"]["lv_m"];
    ASSERT_EQ(s["n"].get<std::size_t>(), lv.size());
    if (lv.empty()) continue;
    double mean = 0;
    for (double v : lv) mean += v / static_cast<double>(lv.size());
    EXPECT_NEAR(s["mean"].get<double>(), mean, 1e-12);
    if (lv.size() == 2) {
      EXPECT_NEAR(s["sd"].get<double>(), std::abs(lv[0] - lv[1]) / std::sqrt(2.0), 1e-12);
    }
  }

  // Same inputs, same bytes; an existing report needs --force.
  const auto again = run_cli(args);
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos);
  std::vector<std::string> forced = args;
  forced.push_back("--force");
  ASSERT_EQ(run_cli(forced).exit_code, 0);
  EXPECT_EQ(test::read_text((test::fs::path(out) / "terrain.json").string()), text);
}

TEST(CliBenchTerrain, MapWithAutomaticEndpointsAndBadFlags) {
  TerrainFile t;
  const auto r = run_cli({"bench", "terrain", "--map", t.path, "--json", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["endpoints"], "auto");
  EXPECT_EQ(j["terrains"], 1);
  // The automatic endpoints are free of AOEA* obstacles.
  RoughTerrainPlanner aoea(RoughTerrainPlannerKind::AOEA, t.map, {});
  for (const char* k : {"start_cell", "goal_cell"}) {
    const Cell c{j["per_terrain"][0][k][0].get<int>(), j["per_terrain"][0][k][1].get<int>()};
    ASSERT_TRUE(t.map.contains(c.x, c.y));
    EXPECT_EQ(aoea.blocked_mask()[t.map.geometry().index(c.x, c.y)], 0) << k;
  }
  for (const BadFlagCase& c : std::vector<BadFlagCase>{{{"--generate", "0"}, "--generate"},
                                               {{"--generate", "2", "--map", t.path}, "--map"},
                                               {{"--generate", "1", "--model-resolution", "0.1"}, "--model-resolution"},
                                               {{"--map", t.path, "--seed", "3"}, "--seed"},
                                               {{"--generate", "1", "--start", "1,1"}, "--goal"},
                                               {{"--generate", "1", "--weights", "1"}, "--weights"}}) {
    std::vector<std::string> args = {"bench", "terrain", "--quiet"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto bad = run_cli(args);
    EXPECT_EQ(bad.exit_code, 2) << c.flag << ": " << bad.err;
    EXPECT_NE(bad.err.find(c.flag), std::string::npos) << bad.err;
  }
}

}  // namespace
