// starnav sim on navigation scenarios: a run that arrives exits 0 and writes the navigation
// records and pictures; one that cannot reach its goal exits 1 with one line saying why; the
// navigation flags are refused (exit 2, one line naming the flag) where they make no sense.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

using starnav::test::CliResult;
using starnav::test::run_cli;

using starnav::test::kE1;

using starnav::test::kSmallNavWall;
using starnav::test::small_nav_scenario;

void expect_one_error_line(const CliResult& r, int code, const std::vector<std::string>& names, const std::string& what) {
  EXPECT_EQ(r.exit_code, code) << what << "\nstdout: " << r.out << "\nstderr: " << r.err;
  EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << what << ": " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ": " << r.err;
  for (const std::string& n : names) EXPECT_NE(r.err.find(n), std::string::npos) << what << ": no '" << n << "' in " << r.err;
}

TEST(SimNavCli, ArrivesAndWritesTheNavigationRecords) {
  starnav::test::ScratchDir dir;
  const std::string file = dir.file("nav.yaml");
  starnav::test::write_text(file, small_nav_scenario(kSmallNavWall));
  const std::string out = dir.file("out");
  const CliResult r = run_cli({"sim", file, "--out", out, "--quiet", "--json", "--planner", "dstar_lite", "--compare-astar"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"success\": true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"planner\": \"dstar_lite\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"costs_match_astar\": true"), std::string::npos) << r.out;
  for (const char* f : {"trajectory.csv", "paths.csv", "replans.csv", "events.csv", "steps.jsonl", "map.yaml", "map.pgm",
                        "metrics.json", "timing.json", "scene.svg", "overlay.svg"})
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(out) / f)) << f;
  EXPECT_EQ(starnav::test::read_text(out + "/paths.csv").rfind("plan_id,t_s,x_m,y_m\n", 0), 0u);
  EXPECT_EQ(starnav::test::read_text(out + "/replans.csv").rfind("plan_id,t_s,cause,status,expanded,cost_m,astar_status", 0), 0u);

  // Without --quiet: the progress ends on how the run ended (a robot that arrives early does not
  // leave the bar part way), and the wrote line names every file in the folder.
  const CliResult loud = run_cli({"sim", file, "--out", dir.file("loud")});
  ASSERT_EQ(loud.exit_code, 0) << loud.err;
  EXPECT_NE(loud.err.find("sim: 100/100 (arrived at t = "), std::string::npos) << loud.err;
  const std::string wrote = loud.out.substr(loud.out.find("wrote "));
  for (const auto& entry : std::filesystem::directory_iterator(dir.file("loud")))
    EXPECT_NE(wrote.find(entry.path().filename().string()), std::string::npos) << entry.path() << " not in: " << wrote;
}

TEST(SimNavCli, ComponentsAreChosenAndSetFromTheCommandLine) {
  starnav::test::ScratchDir dir;
  const std::string file = dir.file("nav.yaml");
  starnav::test::write_text(file, small_nav_scenario(""));
  // --help lists every registered controller and planner with their parameter sections.
  const CliResult help = run_cli({"sim", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  for (const char* name : {"straight_to_goal", "path_follower", "dstar_lite", "ground_truth", "navigation.follower.{"})
    EXPECT_NE(help.out.find(name), std::string::npos) << name << " missing from sim --help";
  // --controller and --set reach the components.
  const CliResult r = run_cli({"sim", file, "--out", dir.file("a"), "--quiet", "--json", "--controller", "straight_to_goal",
                               "--set", "navigation.straight_to_goal.speed_mps=0.25"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"controller\": \"straight_to_goal\""), std::string::npos) << r.out;
  const CliResult bad = run_cli({"sim", file, "--out", dir.file("b"), "--quiet", "--set", "navigation.follower.look_ahead_m=-1"});
  expect_one_error_line(bad, 2, {"nav.yaml", "navigation.follower.look_ahead_m (--set)", "> 0"}, "--set bad value");
  const CliResult unknown = run_cli({"sim", file, "--out", dir.file("c"), "--quiet", "--controller", "teb"});
  expect_one_error_line(unknown, 2, {"--controller", "unknown controller 'teb'", "straight_to_goal", "dwa"}, "unknown controller");
  // The old D* Lite spelling works, with a warning on stderr.
  const CliResult old = run_cli({"sim", file, "--out", dir.file("d"), "--quiet", "--planner", "dstarlite"});
  EXPECT_EQ(old.exit_code, 0) << old.err;
  EXPECT_NE(old.err.find("starnav: warning: --planner: 'dstarlite' is deprecated; use 'dstar_lite'"), std::string::npos) << old.err;
  // starnav params lists them too, as docs/parameters.md.
  const CliResult params = run_cli({"params", "--markdown"});
  EXPECT_EQ(params.exit_code, 0);
  EXPECT_NE(params.out.find("### `straight_to_goal`"), std::string::npos);
}

TEST(SimNavCli, EnclosedGoalExitsOneWithTheReason) {
  starnav::test::ScratchDir dir;
  const std::string file = dir.file("nav.yaml");
  starnav::test::write_text(file, small_nav_scenario("  obstacles:\n"
                                                     "    - {name: s, kind: box, position_m: [5.0, 0.3], size_m: [1.6, 0.2, 0.5]}\n"
                                                     "    - {name: n, kind: box, position_m: [5.0, 1.7], size_m: [1.6, 0.2, 0.5]}\n"
                                                     "    - {name: w, kind: box, position_m: [4.3, 0.8], size_m: [0.2, 1.2, 0.5]}\n"
                                                     "    - {name: e, kind: box, position_m: [5.7, 0.8], size_m: [0.2, 1.2, 0.5]}\n"));
  const CliResult r = run_cli({"sim", file, "--out", dir.file("out"), "--quiet"});
  expect_one_error_line(r, 1, {"nav.yaml", "navigation", "no path"}, "enclosed goal");
}

TEST(SimNavCli, BadNavigationFlagsNameTheFlag) {
  starnav::test::ScratchDir dir;
  const std::string file = dir.file("nav.yaml");
  starnav::test::write_text(file, small_nav_scenario(""));
  expect_one_error_line(run_cli({"sim", file, "--out", dir.file("a"), "--motion-mode", "sideways"}), 2, {"--motion-mode"},
                        "unknown mode");
  expect_one_error_line(run_cli({"sim", file, "--out", dir.file("b"), "--planner", "nonesuch"}), 2, {"--planner"},
                        "unknown planner");
  // A scripted scenario has no navigation to configure.
  expect_one_error_line(run_cli({"sim", kE1, "--out", dir.file("c"), "--motion-mode", "holonomic"}), 2,
                        {"--motion-mode", "e1_terrain_platform.yaml"}, "scripted scenario");
}

}  // namespace
