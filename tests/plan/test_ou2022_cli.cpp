// Ou et al. 2022 (docs/papers/ou2022.md) on the command line: `starnav plan` with the new flags and its
// `metrics`, the errors for JPS with search features, and `starnav bench ablation` end to end on
// a small map (files, keys, determinism of everything but the times).
// GCC 12 reports a false -Wrestrict in std::string concatenation inlined from run_cli (GCC bug
// 105329); the code is fine.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::run_cli;

// 16 x 10, y counted from the top: a wall with a door of 3 cells.
const char* kMap =
    "type octile\nheight 10\nwidth 16\nmap\n"
    "................\n"
    "................\n"
    "................\n"
    ".......@........\n"
    ".......@........\n"
    ".......@........\n"
    "................\n"
    "................\n"
    "................\n"
    "................\n";

const char* kWallMap =
    "type octile\nheight 10\nwidth 16\nmap\n"
    "................\n"
    ".......@........\n"
    ".......@........\n"
    ".......@........\n"
    ".......@........\n"
    ".......@........\n"
    ".......@........\n"
    "................\n"
    "................\n"
    "................\n";

nlohmann::json parse_json(const std::string& out) {
  try {
    return nlohmann::json::parse(out);
  } catch (const std::exception&) {
    ADD_FAILURE() << "not JSON: " << out;
    return {};
  }
}

TEST(Ou2022Cli, PlanReportsMetrics) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kWallMap);
  const auto r = run_cli({"plan", "--map", map, "--start", "2,4", "--goal", "13,4", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse_json(r.out);
  ASSERT_TRUE(j.contains("metrics"));
  const auto& m = j["metrics"];
  for (const char* key : {"length", "vertices", "turning_points", "turn_total_rad", "turn_max_rad", "clearance_min",
                          "clearance_mean", "smoothness"})
    EXPECT_TRUE(m.contains(key)) << key;
  EXPECT_FALSE(j.contains("metrics_before_smoothing"));
  EXPECT_DOUBLE_EQ(m["length"].get<double>(), j["length"].get<double>());
  EXPECT_EQ(m["vertices"].get<std::size_t>(), j["path_cells"].size());
  // Around the wall's end at row 0 or row 7: the path passes next to the wall (clearance 1 cell).
  EXPECT_DOUBLE_EQ(m["clearance_min"].get<double>(), 1.0);
  EXPECT_GE(m["turning_points"].get<int>(), 2);
}

TEST(Ou2022Cli, Ou2022SmoothsAndChargesTurns) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kWallMap);
  const auto plain = parse_json(run_cli({"plan", "--map", map, "--start", "2,4", "--goal", "13,4", "--json"}).out);
  const auto r = run_cli({"plan", "--map", map, "--start", "2,4", "--goal", "13,4", "--planner", "ou2022", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse_json(r.out);
  EXPECT_EQ(j["planner"], "ou2022");
  EXPECT_EQ(j["admissible"], false);
  ASSERT_TRUE(j.contains("metrics_before_smoothing"));
  EXPECT_LT(j["metrics"]["vertices"].get<int>(), j["metrics_before_smoothing"]["vertices"].get<int>());
  EXPECT_LE(j["metrics"]["turning_points"].get<int>(), j["metrics_before_smoothing"]["turning_points"].get<int>());
  EXPECT_LE(j["length"].get<double>(), j["metrics_before_smoothing"]["length"].get<double>() + 1e-9);
  EXPECT_LE(j["length"].get<double>(), plain["length"].get<double>() + 1e-9);
  // The objective includes the turns, so it exceeds the grid path's length.
  EXPECT_GT(j["cost"].get<double>(), j["metrics_before_smoothing"]["length"].get<double>());

  // Every feature alone on astar.
  const std::vector<std::vector<std::string>> features = {{"--turn-cost", "2"},
                                                          {"--turn-cost", "1", "--turn-exact"},
                                                          {"--adaptive-weight"},
                                                          {"--heuristic", "manhattan"},
                                                          {"--heuristic", "euclidean"},
                                                          {"--inflate", "1"},
                                                          {"--inflate-cost-radius", "3", "--inflate-cost", "1"},
                                                          {"--smooth", "los"},
                                                          {"--turn-cost", "1", "--start-heading-deg", "180"}};
  for (const auto& f : features) {
    std::vector<std::string> args = {"plan", "--map", map, "--start", "2,4", "--goal", "13,4", "--json"};
    args.insert(args.end(), f.begin(), f.end());
    const auto a = run_cli(args);
    ASSERT_EQ(a.exit_code, 0) << f[0] << ": " << a.err;
    const auto ja = parse_json(a.out);
    EXPECT_EQ(ja["planner"], "astar") << f[0];
  }
  // ou2022 with its paper defaults switched off one by one.
  const auto off = parse_json(run_cli({"plan", "--map", map, "--start", "2,4", "--goal", "13,4", "--planner", "ou2022",
                                       "--turn-cost", "0", "--no-adaptive-weight", "--smooth", "none",
                                       "--heuristic", "octile", "--json"})
                                  .out);
  EXPECT_DOUBLE_EQ(off["cost"].get<double>(), plain["cost"].get<double>());
  EXPECT_EQ(off["admissible"], true);
  EXPECT_FALSE(off.contains("metrics_before_smoothing"));
}

TEST(Ou2022Cli, InflationKeepsThePathAway) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  const auto r = parse_json(
      run_cli({"plan", "--map", map, "--start", "3,4", "--goal", "12,4", "--inflate", "2", "--json"}).out);
  ASSERT_EQ(r["found"], true);
  EXPECT_GE(r["metrics"]["clearance_min"].get<double>(), 2.0);  // R = 2 cells: every cell at distance > 2
  // Start inside the inflated zone: no answer, exit 1.
  const auto blocked = run_cli({"plan", "--map", map, "--start", "6,4", "--goal", "12,4", "--inflate", "2", "--json"});
  EXPECT_EQ(blocked.exit_code, 1);
  EXPECT_EQ(parse_json(blocked.out)["reason"], "start_blocked");
  // JPS with inflation and smoothing.
  const auto jps = run_cli({"plan", "--map", map, "--start", "3,4", "--goal", "12,4", "--planner", "jps", "--inflate",
                            "2", "--smooth", "los", "--json"});
  ASSERT_EQ(jps.exit_code, 0) << jps.err;
  EXPECT_GE(parse_json(jps.out)["metrics"]["clearance_min"].get<double>(), 2.0);
  // SVG with the inflation layer and the path before smoothing.
  const std::string svg = dir.file("p.svg");
  ASSERT_EQ(run_cli({"plan", "--map", map, "--start", "3,4", "--goal", "12,4", "--planner", "ou2022", "--inflate", "2",
                     "--svg", svg})
                .exit_code,
            0);
  const std::string text = test::read_text(svg);
  EXPECT_NE(text.find("inflation"), std::string::npos);
  EXPECT_NE(text.find("before smoothing"), std::string::npos);
}

TEST(Ou2022Cli, BadCombinationsAreErrors) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  auto expect_error = [&](std::vector<std::string> extra, const std::string& flag) {
    std::vector<std::string> args = {"plan", "--map", map, "--start", "0,0", "--goal", "15,9"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << extra[0];
    EXPECT_NE(r.err.find("starnav: error: " + flag), std::string::npos) << r.err;
  };
  expect_error({"--planner", "jps", "--turn-cost", "1"}, "--turn-cost");
  expect_error({"--planner", "jps", "--inflate-cost-radius", "2"}, "--inflate-cost-radius");
  expect_error({"--planner", "jps", "--adaptive-weight"}, "--adaptive-weight");
  expect_error({"--planner", "jpsplus", "--turn-exact"}, "--turn-exact");
  expect_error({"--turn-cost", "-1"}, "--turn-cost");
  expect_error({"--inflate", "-1"}, "--inflate");
  expect_error({"--inflate", "2", "--inflate-cost-radius", "1"}, "--inflate-cost-radius");
  expect_error({"--smooth", "spline"}, "--smooth");
  expect_error({"--heuristic", "chebyshev"}, "--heuristic");
  expect_error({"--smooth-clearance", "1"}, "--smooth-clearance");  // only with --smooth gradient
  expect_error({"--smooth", "gradient", "--smooth-clearance", "-1"}, "--smooth-clearance");
}

// --smooth gradient (beyond the paper): the line-of-sight path round the wall's end, smoothed.
TEST(Ou2022Cli, GradientSmoothingRoundsTheTurnsAndStaysClear) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kWallMap);
  const std::vector<std::string> base = {"plan", "--map", map, "--start", "3,4", "--goal", "12,4", "--inflate", "1",
                                         "--json"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return parse_json(r.out);
  };
  const auto los = with({"--smooth", "los"});
  const auto g = with({"--smooth", "gradient", "--out", dir.file("p.csv"), "--svg", dir.file("p.svg")});
  ASSERT_TRUE(g.contains("smoothed_path"));
  const auto& pts = g["smoothed_path"];
  ASSERT_GT(pts.size(), los["path"].size());
  // Same ends as the line-of-sight path (cells, centre at the indices), a gentler largest turn,
  // and the clearance of the inflated planner kept (every cell at distance > 1).
  EXPECT_EQ(pts.front(), los["path"].front());
  EXPECT_EQ(pts.back(), los["path"].back());
  EXPECT_EQ(g["path"], los["path"]);
  EXPECT_LT(g["metrics"]["turn_max_rad"].get<double>(), 0.8 * los["metrics"]["turn_max_rad"].get<double>());
  EXPECT_GT(g["metrics"]["clearance_min"].get<double>(), 1.0);
  EXPECT_LE(g["smoothing"]["energy_output"].get<double>(), g["smoothing"]["energy_input"].get<double>());
  // No point in the closed square of a blocked cell of the inflated map: the wall (column 7, rows
  // 1-6) and its one-cell band (column 7 rows 0-7, columns 6 and 8 rows 1-6).
  auto in_square = [](double x, double y, int cx, int cy) { return x >= cx && x <= cx + 1 && y >= cy && y <= cy + 1; };
  for (const auto& p : pts) {
    const double x = p[0].get<double>() + 0.5, y = p[1].get<double>() + 0.5;  // continuous cell coordinates
    for (int row = 0; row <= 7; ++row) EXPECT_FALSE(in_square(x, y, 7, row)) << x << "," << y;
    for (int row = 1; row <= 6; ++row) EXPECT_FALSE(in_square(x, y, 6, row) || in_square(x, y, 8, row)) << x << "," << y;
  }
  const std::string csv = test::read_text(dir.file("p.csv"));
  EXPECT_EQ(csv.rfind("x_cell,y_cell\n", 0), 0u);
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), pts.size() + 1);
  EXPECT_NE(test::read_text(dir.file("p.svg")).find("gradient smoothing"), std::string::npos);
  // A clearance floor of 2 cells: no sample ends nearer the wall than 2 cells where it was not.
  const auto far = with({"--smooth", "gradient", "--smooth-clearance", "2"});
  EXPECT_GT(far["metrics"]["clearance_min"].get<double>(), 1.0);
}

TEST(Ou2022Cli, BenchAblationWritesTheReport) {
  test::ScratchDir dir;
  const std::string map = dir.file("m.map");
  test::write_text(map, kMap);
  const std::string out = dir.file("ablation");
  const std::vector<std::string> args = {"bench",      "ablation", "--map",    map,   "--random", "6",
                                         "--seed",     "3",        "--min-dist", "5", "--max-dist", "12",
                                         "--inflate",  "1",        "--repeat", "2",   "--quiet"};
  std::vector<std::string> first = args;
  first.insert(first.end(), {"--out", out});
  const auto r = run_cli(first);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("| A* + turn_w + W |"), std::string::npos);
  EXPECT_NE(r.out.find("Tir (%)"), std::string::npos);
  for (const char* f : {"ablation.md", "ablation.json", "queries.csv", "svg/query_000.svg", "svg/query_005.svg"})
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(out) / f)) << f;
  const auto j = parse_json(test::read_text(out + "/ablation.json"));
  EXPECT_EQ(j["queries"].size(), 6u);
  ASSERT_EQ(j["tables"].size(), 4u);  // manhattan / octile x original / inflated
  std::vector<std::string> names;
  for (const auto& v : j["tables"][1]["mean"]) names.push_back(v["variant"]);
  EXPECT_EQ(names, (std::vector<std::string>{"A*", "A* + turn_w", "A* + turn_w + W", "A* + turn_w + W + LOS",
                                             "A* + turn_w (exact)", "JPS", "JPS + LOS"}));
  for (const auto& t : j["tables"]) {
    EXPECT_EQ(t["mean"][0]["tir_percent"].get<double>(), 0.0);
    EXPECT_EQ(t["mean"][0]["enr_percent"].get<double>(), 0.0);
    for (const auto& v : t["mean"]) {
      EXPECT_EQ(v["solved"].get<int>(), 6) << v["variant"];
      for (const char* key : {"time_ms", "expanded", "tir_percent", "enr_percent", "length", "turning_points",
                              "vertices", "vertices_los", "clearance_min", "smoothness"})
        EXPECT_TRUE(v.contains(key)) << key;
    }
    EXPECT_EQ(t["per_query"].size(), 6u * 7u);
  }
  // The LOS rows never have more vertices than their grid rows; the exact variant's objective is
  // never above the paper variant's.
  for (const auto& t : j["tables"]) {
    EXPECT_LE(t["mean"][3]["vertices"].get<double>(), t["mean"][2]["vertices"].get<double>());
    EXPECT_LE(t["mean"][4]["cost"].get<double>(), t["mean"][1]["cost"].get<double>() + 1e-9);
  }
  // Existing results are kept unless --force; the same seed gives the same queries and counts.
  EXPECT_EQ(run_cli(first).exit_code, 2);
  first.push_back("--force");
  ASSERT_EQ(run_cli(first).exit_code, 0);
  const auto j2 = parse_json(test::read_text(out + "/ablation.json"));
  EXPECT_EQ(j2["queries"], j["queries"]);
  for (std::size_t t = 0; t < j["tables"].size(); ++t)
    for (std::size_t i = 0; i < j["tables"][t]["per_query"].size(); ++i) {
      EXPECT_EQ(j2["tables"][t]["per_query"][i]["expanded"], j["tables"][t]["per_query"][i]["expanded"]);
      EXPECT_EQ(j2["tables"][t]["per_query"][i]["length"], j["tables"][t]["per_query"][i]["length"]);
    }
  // The queries file reproduces the run.
  std::vector<std::string> again = {"bench", "ablation", "--map", map, "--queries", out + "/queries.csv",
                                    "--inflate", "1", "--repeat", "1", "--quiet"};
  const auto q = run_cli(again);
  ASSERT_EQ(q.exit_code, 0) << q.err;
  EXPECT_NE(q.out.find("6 queries (from"), std::string::npos);
  // Bad input.
  EXPECT_EQ(run_cli({"bench", "ablation", "--map", map}).exit_code, 2);
  EXPECT_EQ(run_cli({"bench", "ablation", "--map", map, "--random", "3", "--queries", out + "/queries.csv"}).exit_code,
            2);
  EXPECT_EQ(run_cli({"bench", "ablation", "--map", map, "--random", "3", "--min-dist", "500", "--max-dist", "600",
                     "--quiet"})
                .exit_code,
            2);
}

}  // namespace
}  // namespace starnav
