// `starnav bench movingai` on small maps written here, with optimal lengths computed by a
// Dijkstra of this file: exact counts, JSON keys, --dir, --csv, --limit, exit codes and errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <queue>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using starnav::test::run_cli;
using starnav::test::ScratchDir;
using starnav::test::write_text;

// '@' blocked. The pocket at the bottom right is closed off: problems into it are unsolvable.
const std::vector<std::string> kRows = {
    "..........@....",
    "..@@@.....@....",
    "....@..........",
    "....@...@@@@...",
    "..........@....",
    "@@@.@@....@@@@@",
    "..........@....",
    "..........@..T.",
    "......@...@....",
};

double root2() { return std::sqrt(2.0); }

bool free_cell(int x, int y) {
  return y >= 0 && y < static_cast<int>(kRows.size()) && x >= 0 && x < static_cast<int>(kRows[0].size()) &&
         kRows[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)] == '.';
}

double shortest(int sx, int sy, int gx, int gy) {
  const int w = static_cast<int>(kRows[0].size()), h = static_cast<int>(kRows.size());
  std::vector<double> d(static_cast<std::size_t>(w * h), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> pq;
  d[static_cast<std::size_t>(sy * w + sx)] = 0;
  pq.push({0, sy * w + sx});
  while (!pq.empty()) {
    const auto [c, i] = pq.top();
    pq.pop();
    if (c > d[static_cast<std::size_t>(i)]) continue;
    const int x = i % w, y = i / w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((!dx && !dy) || !free_cell(x + dx, y + dy)) continue;
        if (dx && dy && (!free_cell(x + dx, y) || !free_cell(x, y + dy))) continue;
        const double nc = c + ((dx && dy) ? root2() : 1.0);
        const std::size_t ni = static_cast<std::size_t>((y + dy) * w + x + dx);
        if (nc < d[ni]) {
          d[ni] = nc;
          pq.push({nc, (y + dy) * w + x + dx});
        }
      }
  }
  return d[static_cast<std::size_t>(gy * w + gx)];
}

std::string map_text() {
  std::string t = "type octile\nheight " + std::to_string(kRows.size()) + "\nwidth " + std::to_string(kRows[0].size()) +
                  "\nmap\n";
  for (const auto& r : kRows) t += r + "\n";
  return t;
}

struct Problem {
  int sx, sy, gx, gy;
};
// Six solvable problems, one start == goal, one unsolvable (into the closed pocket).
const std::vector<Problem> kProblems = {{0, 0, 14, 0}, {0, 8, 9, 0},  {3, 2, 12, 4},   {14, 4, 0, 6},
                                        {5, 3, 5, 3},  {0, 0, 13, 8}, {1, 4, 9, 8},    {7, 0, 6, 7}};

// `bad_line` >= 0 gets a wrong optimal length (+1).
std::string scen_text(const std::string& map_name, int bad_line = -1, int width_override = -1) {
  std::ostringstream s;
  s << "version 1\n";
  for (std::size_t k = 0; k < kProblems.size(); ++k) {
    const Problem& p = kProblems[k];
    double len = shortest(p.sx, p.sy, p.gx, p.gy);
    if (std::isinf(len)) len = 0.0;
    if (static_cast<int>(k) == bad_line) len += 1.0;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.8f", len);
    s << static_cast<int>(len / 4) << '\t' << map_name << '\t'
      << (width_override > 0 && k == 2 ? width_override : static_cast<int>(kRows[0].size())) << '\t' << kRows.size()
      << '\t' << p.sx << '\t' << p.sy << '\t' << p.gx << '\t' << p.gy << '\t' << buf << '\n';
  }
  return s.str();
}

const char* const kKeys[] = {"planner",       "instances",          "solved",         "exact",
                             "max_abs_error", "max_suboptimality",  "mean_suboptimality", "median_time_us",
                             "mean_time_us",  "total_expanded",     "expansions_per_s", "preprocess_ms"};

TEST(BenchMovingAiCli, ExactCountsAndJsonKeys) {
  ScratchDir dir;
  // The problems must include one unsolvable and one start == goal line.
  ASSERT_TRUE(std::isinf(shortest(0, 0, 13, 8)));
  ASSERT_FALSE(std::isinf(shortest(7, 0, 6, 7)));
  write_text(dir.file("small.map"), map_text());
  write_text(dir.file("small.map.scen"), scen_text("small.map"));
  const auto r = run_cli({"bench", "movingai", "--map", dir.file("small.map"), "--scen", dir.file("small.map.scen"),
                          "--planner", "jps", "--planner", "jpsplus", "--planner", "astar", "--json", "--repeat", "3"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("planners"));
  ASSERT_EQ(j["planners"].size(), 3u);
  const char* names[] = {"jps", "jpsplus", "astar"};
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& p = j["planners"][k];
    for (const char* key : kKeys) EXPECT_TRUE(p.contains(key)) << key;
    EXPECT_EQ(p["planner"], names[k]);
    EXPECT_EQ(p["instances"], kProblems.size());
    EXPECT_EQ(p["exact"], kProblems.size());
    EXPECT_EQ(p["solved"], kProblems.size() - 1);  // the unsolvable one has no path
    EXPECT_EQ(p["unsolvable"], 1);
    EXPECT_EQ(p["shorter"], 0);
    EXPECT_LE(p["max_abs_error"].get<double>(), 1e-7);
    EXPECT_GE(p["median_time_us"].get<double>(), 0.0);
    EXPECT_GT(p["total_expanded"].get<long long>(), 0);
  }
  EXPECT_EQ(j["instances"], kProblems.size());
  EXPECT_EQ(j["repeat"], 3);
  ASSERT_EQ(j["per_map"].size(), 3u);
  EXPECT_EQ(j["per_map"][0]["map"], "small");
  // Progress on stderr: not a terminal here, so one plain line per map.
  EXPECT_NE(r.err.find("[1/1] small"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos);
}

TEST(BenchMovingAiCli, WrongAnswersAreCountedAndExitOne) {
  ScratchDir dir;
  write_text(dir.file("small.map"), map_text());
  write_text(dir.file("small.map.scen"), scen_text("small.map", 1));
  const auto r = run_cli({"bench", "movingai", "--map", dir.file("small.map"), "--scen", dir.file("small.map.scen"),
                          "--planner", "jps", "--json", "--quiet"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["planners"][0]["exact"], kProblems.size() - 1);
  EXPECT_NEAR(j["planners"][0]["max_abs_error"].get<double>(), 1.0, 1e-6);
  // The table says so too.
  const auto t = run_cli({"bench", "movingai", "--map", dir.file("small.map"), "--scen", dir.file("small.map.scen"),
                          "--planner", "jpsplus", "--quiet"});
  EXPECT_EQ(t.exit_code, 1);
  EXPECT_NE(t.out.find("NOT EXACT: jpsplus"), std::string::npos) << t.out;
}

TEST(BenchMovingAiCli, DirectoryLimitAndCsv) {
  ScratchDir dir;
  fs::create_directories(dir.path() / "a");
  fs::create_directories(dir.path() / "b" / "deeper");
  write_text(dir.file("a/x.map"), map_text());
  write_text(dir.file("a/x.map.scen"), scen_text("x.map"));
  write_text(dir.file("b/deeper/y.map"), map_text());
  write_text(dir.file("b/deeper/y.map.scen"), scen_text("maps/y.map"));
  write_text(dir.file("b/lonely.map"), map_text());  // no scenario: skipped
  const std::string csv = dir.file("rows.csv");
  // A trailing slash and a symbolic link to a map elsewhere change nothing in the names.
  // (The link targets are not .map files themselves.)
  fs::create_directories(dir.path() / "hidden");
  write_text(dir.file("hidden/z.txt"), map_text());
  write_text(dir.file("hidden/z_scen.txt"), scen_text("z.map"));
  fs::create_symlink(dir.path() / "hidden" / "z.txt", dir.path() / "b" / "z.map");
  fs::create_symlink(dir.path() / "hidden" / "z_scen.txt", dir.path() / "b" / "z.map.scen");
  const auto r = run_cli({"bench", "movingai", "--dir", dir.path().string() + "/", "--limit", "3", "--csv", csv,
                          "--json", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["maps"], 3);
  ASSERT_EQ(j["planners"].size(), 3u);  // default: astar, jps, jpsplus
  EXPECT_EQ(j["planners"][0]["planner"], "astar");
  EXPECT_EQ(j["planners"][1]["planner"], "jps");
  EXPECT_EQ(j["planners"][2]["planner"], "jpsplus");
  for (const auto& p : j["planners"]) {
    EXPECT_EQ(p["instances"], 9);
    EXPECT_EQ(p["exact"], 9);
    EXPECT_EQ(p["maps"], 3);
  }
  ASSERT_EQ(j["per_map"].size(), 9u);  // sorted by name
  EXPECT_EQ(j["per_map"][0]["map"], "a/x");
  EXPECT_EQ(j["per_map"][3]["map"], "b/deeper/y");
  EXPECT_EQ(j["per_map"][6]["map"], "b/z");
  // One header and one row per problem and planner.
  const std::string text = starnav::test::read_text(csv);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 3 * 3 * 3);
  EXPECT_EQ(text.rfind("map,problem,bucket,start_x,start_y,goal_x,goal_y,optimal,planner,status", 0), 0u);
  // The CSV is not overwritten without --force.
  const auto again = run_cli({"bench", "movingai", "--dir", dir.path().string(), "--csv", csv, "--quiet"});
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  const auto forced = run_cli({"bench", "movingai", "--dir", dir.path().string(), "--csv", csv, "--force",
                               "--planner", "jps", "--quiet"});
  EXPECT_EQ(forced.exit_code, 0) << forced.err;
}

TEST(BenchMovingAiCli, BadInputIsExitTwoWithOneLine) {
  ScratchDir dir;
  write_text(dir.file("small.map"), map_text());
  write_text(dir.file("wrong.map.scen"), scen_text("small.map", -1, 99));
  const auto mismatch = run_cli({"bench", "movingai", "--map", dir.file("small.map"), "--scen",
                                 dir.file("wrong.map.scen"), "--quiet"});
  EXPECT_EQ(mismatch.exit_code, 2);
  EXPECT_EQ(mismatch.err.rfind("starnav: error: " + dir.file("wrong.map.scen"), 0), 0u) << mismatch.err;
  EXPECT_NE(mismatch.err.find("problem 3"), std::string::npos) << mismatch.err;

  write_text(dir.file("small.map.scen"), scen_text("small.map"));
  const auto unknown = run_cli({"bench", "movingai", "--map", dir.file("small.map"), "--scen",
                                dir.file("small.map.scen"), "--planner", "nosuch"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("nosuch"), std::string::npos);

  const auto missing = run_cli({"bench", "movingai", "--map", dir.file("small.map")});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--scen"), std::string::npos) << missing.err;

  const auto nodir = run_cli({"bench", "movingai", "--dir", dir.file("absent")});
  EXPECT_EQ(nodir.exit_code, 2);
  fs::create_directories(dir.path() / "empty");
  const auto empty = run_cli({"bench", "movingai", "--dir", dir.file("empty")});
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find("no FILE.map"), std::string::npos) << empty.err;

  const auto no_sub = run_cli({"bench"});
  EXPECT_EQ(no_sub.exit_code, 2);

  write_text(dir.file("broken.map"), "type octile\nheight 2\nwidth 2\nmap\n..\n.\n");
  write_text(dir.file("broken.map.scen"), "version 1\n");
  const auto broken = run_cli({"bench", "movingai", "--map", dir.file("broken.map"), "--scen",
                               dir.file("broken.map.scen")});
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_NE(broken.err.find("broken.map"), std::string::npos) << broken.err;

  const auto repeat0 = run_cli({"bench", "movingai", "--map", dir.file("small.map"), "--scen",
                                dir.file("small.map.scen"), "--repeat", "0"});
  EXPECT_EQ(repeat0.exit_code, 2);
}

TEST(BenchMovingAiCli, SampleOfTheSharedBenchmarks) {
  STARNAV_SKIP_WITHOUT_SHARED("benchmarks/movingai/dao/den520d.map");
  const std::string map = starnav::test::shared_path("benchmarks/movingai/dao/den520d.map");
  const auto r = run_cli({"bench", "movingai", "--map", map, "--scen", map + ".scen", "--limit", "20", "--json",
                          "--quiet", "--planner", "jps", "--planner", "jpsplus"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const auto& p : j["planners"]) {
    EXPECT_EQ(p["instances"], 20);
    EXPECT_EQ(p["exact"], 20);
  }
  EXPECT_GT(j["planners"][1]["preprocess_ms"].get<double>(), 0.0);
}

}  // namespace
