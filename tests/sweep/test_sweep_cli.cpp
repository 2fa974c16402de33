// starnav sweep through the command line: every example sweep under examples/sweeps/ in a
// shortened form, the error lines and exit codes, and Ctrl-C.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/sweep/process.hpp"
#include "sweep/sweep_test_support.hpp"

namespace starnav::sweep {
namespace {

namespace fs = std::filesystem;
using test::run_cli;
using test::ScratchDir;

// How the tests shorten each example: a few values of its axes and a short simulation. A new
// example must be added here (ExamplesAreAllCovered).
const std::map<std::string, std::vector<std::string>> kShortened = {
    {"plan_queries_sweep.yaml", {"--take", "query=3"}},
    {"e2_seeds_sweep.yaml", {"--take", "seed=2", "--set", "sim.duration_s=3"}},
    {"e3_look_ahead_sweep.yaml", {"--take", "seed=1", "--take", "navigation.follower.look_ahead_m=2", "--set", "sim.duration_s=3"}},
    {"e4_planners_sweep.yaml", {"--take", "seed=1", "--set", "sim.duration_s=3"}},
};

const fs::path kExamples = fs::path(STARNAV_SOURCE_DIR) / "examples" / "sweeps";

TEST(SweepCli, ExamplesAreAllCovered) {
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(kExamples)) files.insert(e.path().filename().string());
  for (const std::string& f : files) {
    EXPECT_NE(f.find("sweep"), std::string::npos) << f << ": example sweep files have 'sweep' in their name";
    EXPECT_TRUE(kShortened.count(f)) << f << ": add its shortened form to kShortened";
  }
  EXPECT_EQ(files.size(), kShortened.size());
}

TEST(SweepCli, EveryExampleRunsShortened) {
  for (const auto& [file, extra] : kShortened) {
    SCOPED_TRACE(file);
    ScratchDir dir;
    std::vector<std::string> expand{"sweep", "expand", (kExamples / file).string(), "--out", dir.file("s")};
    expand.insert(expand.end(), extra.begin(), extra.end());
    const test::CliResult e = run_cli(expand);
    ASSERT_EQ(e.exit_code, 0) << e.err;
    const test::CliResult r = run_cli({"sweep", "run", dir.file("s"), "--jobs", "2", "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const nlohmann::json report = nlohmann::json::parse(r.out);
    EXPECT_GT(report.at("ran").get<int>(), 0);
    EXPECT_EQ(report.at("failed"), 0);
    const test::CliResult m = run_cli({"sweep", "merge", dir.file("s")});
    EXPECT_EQ(m.exit_code, 0) << m.out << m.err;
    EXPECT_EQ(m.err, "");  // no warning: every metric of the example is in its results
    const nlohmann::json summary = nlohmann::json::parse(test::read_text(dir.file("s/merged/summary.json")));
    EXPECT_EQ(summary.at("ok"), report.at("ran"));
    // Every plot the example asks for is drawn.
    const std::string yaml = test::read_text((kExamples / file).string());
    if (yaml.find("plots:") != std::string::npos) {
      EXPECT_TRUE(fs::is_directory(dir.file("s/merged/plots")));
    }
  }
}

TEST(SweepCli, BadInputIsOneLineAndExit2) {
  ScratchDir dir;
  test::write_text(dir.file("bad.yaml"), "command: [plan, '{s}']\naxes:\n  s: {from: 3, to: 1}\n");
  test::write_text(dir.file("nocmd.yaml"), "command: [planx, '{s}']\naxes:\n  s: [1]\n");
  test::write_text(dir.file("ok.yaml"), "command: [plan, --seed, '{s}']\naxes:\n  s: [1, 2]\n");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"sweep", "expand", dir.file("bad.yaml"), "--out", dir.file("o")}, dir.file("bad.yaml") + ":3: axes.s.to: must be >= from"},
      {{"sweep", "expand", dir.file("nocmd.yaml"), "--out", dir.file("o")}, dir.file("nocmd.yaml") + ":1: command[0]: 'planx' is not a starnav command that a sweep can run ("},
      {{"sweep", "expand", dir.file("missing.yaml"), "--out", dir.file("o")}, dir.file("missing.yaml") + ": no such file"},
      {{"sweep", "expand", dir.file("ok.yaml"), "--out", dir.file("o"), "--take", "s"}, "--take: expected AXIS=N, got 's'"},
      {{"sweep", "run", dir.path().string()}, dir.path().string() + ": not an expanded sweep (no sweep.json: run starnav sweep expand first)"},
      {{"sweep", "merge", dir.file("nothing")}, dir.file("nothing") + ": no such folder (expand a sweep into it with starnav sweep expand)"},
  };
  for (const auto& [args, want] : cases) {
    const test::CliResult r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << want;
    EXPECT_EQ(r.err.rfind("starnav: error: " + want, 0), 0u) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  }
  ASSERT_EQ(run_cli({"sweep", "expand", dir.file("ok.yaml"), "--out", dir.file("s")}).exit_code, 0);
  for (const auto& [args, want] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"sweep", "run", dir.file("s"), "--group", "1"}, "--group-size: --group and --group-size go together (the Slurm script gives both)"},
           {{"sweep", "run", dir.file("s"), "--tasks", "xyz"}, "--tasks: expected task ids of 16 hexadecimal digits (merge lists them), got 'xyz'"},
           {{"sweep", "slurm", dir.file("s"), "--time", "soon", "--max-array-size", "10"}, "--time: expected a Slurm time limit"},
           {{"sweep", "slurm", dir.file("s"), "--starnav", "bin/starnav", "--max-array-size", "10"}, "bin/starnav: --starnav: expected an absolute path"},
       }) {
    const test::CliResult r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << want;
    EXPECT_EQ(r.err.rfind("starnav: error: " + want, 0), 0u) << r.err;
  }
}

TEST(SweepCli, MergeListsWhatIsMissingWithTheRerunAndExits1) {
  ScratchDir dir;
  test::write_open_map(dir.file("m.map"), 10, 10);
  test::write_text(dir.file("s.yaml"),
                   "command: [plan, --map, m.map, --start, '0,0', --goal, '{g},9', --json]\naxes:\n  g: [1, 5, 9]\nmetrics: {cost: /cost}\n");
  ASSERT_EQ(run_cli({"sweep", "expand", dir.file("s.yaml"), "--out", dir.file("s")}).exit_code, 0);
  const test::CliResult one = run_cli({"sweep", "run", dir.file("s"), "--limit", "1"});
  EXPECT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NE(one.out.find("ran 1 of 3 tasks"), std::string::npos) << one.out;
  const test::CliResult m = run_cli({"sweep", "merge", dir.file("s")});
  EXPECT_EQ(m.exit_code, 1);
  EXPECT_NE(m.out.find("1 with a result, 0 failed, 2 missing"), std::string::npos) << m.out;
  const std::size_t rerun = m.out.find("run them again with: starnav sweep run " + dir.file("s") + " --tasks ");
  ASSERT_NE(rerun, std::string::npos) << m.out;
  // The command it gives finishes the sweep.
  const std::string ids = m.out.substr(m.out.find("--tasks ", rerun) + 8, 33);
  EXPECT_EQ(run_cli({"sweep", "run", dir.file("s"), "--tasks", ids}).exit_code, 0);
  EXPECT_EQ(run_cli({"sweep", "merge", dir.file("s")}).exit_code, 0);
  // --json prints summary.json; a folder with other files is not written into without --force.
  const test::CliResult j = run_cli({"sweep", "merge", dir.file("s"), "--json"});
  EXPECT_EQ(nlohmann::json::parse(j.out).at("ok"), 3);
  EXPECT_EQ(run_cli({"sweep", "merge", dir.file("s"), "--out", dir.path().string()}).exit_code, 2);
}

TEST(SweepCli, CtrlCStopsTheRunAndTheNextRunFinishes) {
  ScratchDir dir;
  test::write_open_map(dir.file("big.map"), 900, 900);
  test::write_text(dir.file("s.yaml"),
                   "command: [plan, --map, big.map, --start, '0,{r}', --goal, '899,899', --planner, dijkstra, --json]\n"
                   "axes:\n  r: {from: 0, count: 12}\n");
  ASSERT_EQ(run_cli({"sweep", "expand", dir.file("s.yaml"), "--out", dir.file("s")}).exit_code, 0);
  ChildSpec spec;
  spec.executable = STARNAV_CLI_PATH;
  spec.argv = {"starnav", "sweep", "run", dir.file("s"), "--jobs", "2"};
  spec.stdout_path = dir.file("out.txt");
  spec.stderr_path = dir.file("err.txt");
  Child runner(spec);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!fs::exists(dir.file("s/results")) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ::kill(runner.pid(), SIGINT);
  std::optional<ChildExit> e;
  while (!(e = runner.try_wait())) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(e->exit_code, 130) << test::read_text(dir.file("err.txt"));
  const std::string out = test::read_text(dir.file("out.txt"));
  EXPECT_NE(out.find("stopped before the end"), std::string::npos) << out;
  const test::CliResult rest = run_cli({"sweep", "run", dir.file("s"), "--jobs", "2", "--json"});
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  const nlohmann::json r = nlohmann::json::parse(rest.out);
  EXPECT_EQ(r.at("already_ok").get<int>() + r.at("ran").get<int>(), 12);
  EXPECT_GT(r.at("ran").get<int>(), 0);
  EXPECT_EQ(run_cli({"sweep", "merge", dir.file("s")}).exit_code, 0);
}

}  // namespace
}  // namespace starnav::sweep
