// starnav bench nav: bad flags and scenarios are rejected with exit code 2 and exactly one line
// `starnav: error: ...` naming the flag or the file, before any run (nothing on stdout).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

using starnav::test::CliResult;
using starnav::test::run_cli;

using starnav::test::kE1;

// A valid scripted scenario without a navigation section.
const char* kScripted =
    "name: scripted\n"
    "world:\n"
    "  terrain:\n"
    "    generate: {kind: flat, size_m: [6, 4], resolution_m: 0.1, z_m: 0.0}\n"
    "robot:\n"
    "  start: {x_m: 1, y_m: 2, yaw_deg: 0}\n"
    "sim: {dt_s: 0.02, seed: 1}\n"
    "commands:\n"
    "  - {duration_s: 1, vx_mps: 0.2}\n";

// Exit 2, nothing on stdout, one line `starnav: error: ...` holding every word of `names`.
void expect_one_error_line(const CliResult& r, const std::vector<std::string>& names, const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << what << "\nstdout: " << r.out << "\nstderr: " << r.err;
  EXPECT_TRUE(r.out.empty()) << what << ": printed a result: " << r.out;
  EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << what << ": " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ": " << r.err;
  for (const std::string& n : names) EXPECT_NE(r.err.find(n), std::string::npos) << what << ": no '" << n << "' in " << r.err;
}

TEST(BenchNavCli, SeedsMustBeAPositiveInteger) {
  for (const std::vector<std::string>& seeds :
       {std::vector<std::string>{"--seeds", "0"}, {"--seeds", "-3"}, {"--seeds=-1"}, {"--seeds", "abc"},
        {"--seeds", "2.5"}, {"--seeds", ""}}) {
    std::vector<std::string> args = {"bench", "nav", "--scenario", kE1};
    args.insert(args.end(), seeds.begin(), seeds.end());
    std::string what;
    for (const auto& s : seeds) what += s + " ";
    expect_one_error_line(run_cli(args), {"--seeds"}, what);
  }
}

TEST(BenchNavCli, SeedsAreRequired) {
  expect_one_error_line(run_cli({"bench", "nav", "--scenario", kE1}), {"--seeds"}, "no --seeds");
}

TEST(BenchNavCli, ScenarioIsRequired) {
  expect_one_error_line(run_cli({"bench", "nav", "--seeds", "3"}), {"--scenario"}, "no --scenario");
}

TEST(BenchNavCli, ScenarioWithoutNavigationSectionNamesTheFile) {
  starnav::test::ScratchDir dir;
  const std::string file = dir.file("scripted.yaml");
  starnav::test::write_text(file, kScripted);
  expect_one_error_line(run_cli({"bench", "nav", "--scenario", file, "--seeds", "2", "--quiet"}), {file, "navigation"},
                        "scripted scenario");
  // The repository's E1 scenario is scripted as well.
  expect_one_error_line(run_cli({"bench", "nav", "--scenario", kE1, "--seeds", "1"}), {kE1, "navigation"}, "E1");
}

TEST(BenchNavCli, MissingScenarioFileIsNamed) {
  starnav::test::ScratchDir dir;
  const std::string file = dir.file("absent.yaml");
  expect_one_error_line(run_cli({"bench", "nav", "--scenario", file, "--seeds", "2"}), {file}, "absent file");
}

TEST(BenchNavCli, OtherBadFlagsAreNamed) {
  expect_one_error_line(run_cli({"bench", "nav", "--scenario", kE1, "--seeds", "2", "--seed-base", "-1"}),
                        {"--seed-base"}, "negative --seed-base");
  // The motion mode is the controller's parameter: checked against the scenario's controller.
  expect_one_error_line(run_cli({"bench", "nav", "--scenario", starnav::test::scenario_path("e2_stochastic_pit_mound.yaml"), "--seeds",
                                 "2", "--motion-mode", "sideways"}),
                        {"--motion-mode", "unknown value 'sideways'"}, "unknown --motion-mode");
  expect_one_error_line(run_cli({"bench", "nav", "--scenario", kE1, "--seeds", "2", "--json", "--csv"}), {"--csv"},
                        "--json with --csv");
}

}  // namespace

namespace {

// The records of identical runs are identical bytes: wall-clock figures live in timing.json only.
TEST(BenchNavCli, RecordsAreByteIdenticalAndWallClockGoesToTiming) {
  starnav::test::ScratchDir dir;
  const std::string scenario = dir.file("nav.yaml");
  starnav::test::write_text(scenario, starnav::test::small_nav_scenario(starnav::test::kSmallNavWall));
  for (const char* out : {"a", "b"}) {
    const CliResult r = run_cli({"bench", "nav", "--scenario", scenario, "--seeds", "2", "--quiet", "--out", dir.file(out)});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  for (const char* f : {"/summary.json", "/runs.csv"}) {
    const std::string a = starnav::test::read_text(dir.file("a") + f);
    ASSERT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, starnav::test::read_text(dir.file("b") + f)) << f;
    EXPECT_EQ(a.find("wall"), std::string::npos) << f;
    EXPECT_EQ(a.find("real_time_factor"), std::string::npos) << f;
  }
  const std::string timing = starnav::test::read_text(dir.file("a") + "/timing.json");
  EXPECT_NE(timing.find("\"real_time_factor\""), std::string::npos) << timing;
  EXPECT_NE(timing.find("\"wall_s\""), std::string::npos) << timing;
}

}  // namespace
