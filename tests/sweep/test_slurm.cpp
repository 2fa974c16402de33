// The Slurm batch script without a cluster: the array-size limit and how tasks are grouped under
// it, the script's lines, and the script run the way Slurm runs an array (one bash per index with
// SLURM_ARRAY_TASK_ID) giving the same table as a local run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/sweep/manifest.hpp"
#include "starnav/sweep/merge.hpp"
#include "starnav/sweep/process.hpp"
#include "starnav/sweep/slurm.hpp"
#include "starnav/sweep/task_runner.hpp"
#include "sweep/sweep_test_support.hpp"

namespace starnav::sweep {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::ScratchDir;

TEST(SweepSlurm, MaxArraySizeFromScontrol) {
  // As `scontrol show config` prints it (Slurm 22.05), among other keys.
  const std::string config =
      "Configuration data as of 2026-12-05T13:31:00\n"
      "AccountingStorageBackupHost = (null)\n"
      "MaxArraySize            = 5001\n"
      "MaxJobCount             = 10000\n";
  EXPECT_EQ(parse_max_array_size(config), 5001u);
  EXPECT_EQ(parse_max_array_size("MaxJobCount = 10000\n"), std::nullopt);
  EXPECT_EQ(parse_max_array_size("MaxArraySize = 0\n"), std::nullopt);
  EXPECT_EQ(parse_max_array_size("MaxArraySize = lots\n"), std::nullopt);
  EXPECT_EQ(parse_max_array_size("MaxArraySizeX = 3\n"), std::nullopt);
}

TEST(SweepSlurm, GroupsKeepTheArrayUnderTheLimit) {
  // Hand-counted: a million tasks under Slurm's default 1001 are 1000 array jobs of 1000.
  EXPECT_EQ(slurm_group_size(1'000'000, 1001, 0), 1000u);
  EXPECT_EQ(slurm_group_size(50, 1001, 0), 1u);
  EXPECT_EQ(slurm_group_size(50, 5, 0), 10u);
  EXPECT_EQ(slurm_group_size(50, 5, 20), 20u);
  EXPECT_EQ(slurm_group_size(1001, 1001, 0), 1u);  // indices 0..1000 are all below 1001
  EXPECT_EQ(slurm_group_size(1002, 1001, 0), 2u);
  // For any size and limit: the indices 0 .. groups-1 stay below the limit, and no smaller group
  // size would do.
  std::mt19937_64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const std::uint64_t n = 1 + rng() % 3'000'000, m = 1 + rng() % 5000;
    const std::uint64_t s = slurm_group_size(n, m, 0);
    const std::uint64_t groups = (n + s - 1) / s;
    EXPECT_LE(groups, m) << n << " " << m;
    if (s > 1) {
      EXPECT_GT((n + s - 2) / (s - 1), m) << n << " " << m;
    }
  }
}

TEST(SweepSlurm, ArraySpecs) {
  EXPECT_EQ(slurm_array_spec({0, 1, 2, 4, 6, 7}, 0), "0-2,4,6-7");
  EXPECT_EQ(slurm_array_spec({3}, 2), "3%2");
  EXPECT_EQ(slurm_array_spec({}, 0), "");
}

const char* kPlanSweep =
    "name: grid\n"
    "command: [plan, --map, grid.map, --start, '{sx},0', --goal, '19,{gy}', --planner, '{planner}', --json]\n"
    "axes:\n  planner: [astar, jps]\n  sx: {from: 0, count: 3}\n  gy: [5, 19]\n"
    "metrics: {cost: /cost, expanded: /expanded, time_ms: {pointer: /time_ms, timing: true}}\n"
    "summary: {group_by: [planner]}\n";

TEST(SweepSlurm, ScriptLinesAndOnlyGroupsWithWorkLeft) {
  ScratchDir dir;
  test::write_open_map(dir.file("grid.map"), 20, 20);
  const SweepDir s = test::expand_in(dir, kPlanSweep);
  SlurmOptions o;
  o.max_array_size = 5;
  o.partition = "short";
  o.time = "0-00:10";
  o.cpus_per_task = 2;
  o.sbatch = {"mem=1G", "account=lab"};
  o.starnav = STARNAV_CLI_PATH;
  SlurmScript sc = write_slurm_script(s, o);
  EXPECT_EQ(sc.tasks, 12u);
  EXPECT_EQ(sc.group_size, 3u);
  EXPECT_EQ(sc.groups, 4u);
  EXPECT_EQ(sc.array_spec, "0-3");
  const std::string text = test::read_text(sc.path);
  EXPECT_EQ(text, sc.text);
  const std::string abs = fs::absolute(s.dir).lexically_normal().string();
  for (const std::string& line : std::vector<std::string>{
           "#SBATCH --array=0-3\n", "#SBATCH --partition=short\n", "#SBATCH --time=0-00:10\n", "#SBATCH --cpus-per-task=2\n",
        "#SBATCH --mem=1G\n", "#SBATCH --account=lab\n", "#SBATCH --output=" + abs + "/slurm/%A_%a.log\n",
        "exec '" + std::string(STARNAV_CLI_PATH) + "' sweep run '" + abs +
            "' --group \"$SLURM_ARRAY_TASK_ID\" --group-size 3 --jobs \"${SLURM_CPUS_PER_TASK:-1}\" --quiet\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << text;
  // Tasks 3..5 and 9 done: groups 1 and 3 drop out, except 3 still has tasks 10, 11.
  RunOptions ro = test::cli_run_options();
  for (const SweepTask& t : read_tasks(s, 0, 12))
    if ((t.index >= 3 && t.index <= 5) || t.index == 9) ro.only.push_back(t.id);
  run_sweep(s, ro);
  sc = write_slurm_script(s, o);
  EXPECT_EQ(sc.pending, 8u);
  EXPECT_EQ(sc.array_spec, "0,2-3");
  o.max_running = 2;
  EXPECT_EQ(write_slurm_script(s, o).array_spec, "0,2-3%2");
}

TEST(SweepSlurm, BadOptionsNameTheFlag) {
  ScratchDir dir;
  test::write_open_map(dir.file("grid.map"), 20, 20);
  const SweepDir s = test::expand_in(dir, kPlanSweep);
  const auto bad = [&](auto edit) {
    SlurmOptions o;
    o.max_array_size = 1001;
    o.starnav = STARNAV_CLI_PATH;
    edit(o);
    return error_of([&] { write_slurm_script(s, o); });
  };
  EXPECT_EQ(bad([](SlurmOptions& o) { o.time = "10 min"; }),
            "--time: expected a Slurm time limit (MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS), got '10 min'");
  EXPECT_EQ(bad([](SlurmOptions& o) { o.time = "1:2:3:4"; }).substr(0, 8), "--time: ");
  EXPECT_EQ(bad([](SlurmOptions& o) { o.partition = "a\nb"; }), "--partition: expected a partition name (letters, digits, _ . - and commas), got 'a\\x0ab'");
  EXPECT_EQ(bad([](SlurmOptions& o) { o.sbatch = {"--mem=1G"}; }),
            "--sbatch: expected an sbatch option NAME or NAME=VALUE without the dashes (mem=4G), got '--mem=1G'");
  EXPECT_EQ(bad([](SlurmOptions& o) { o.sbatch = {"array=1-5"}; }), "--sbatch: array is written by starnav sweep slurm");
  EXPECT_EQ(bad([](SlurmOptions& o) { o.sbatch = {"time=5"}; }), "--sbatch: time is written by starnav sweep slurm (use --time)");
  EXPECT_EQ(bad([](SlurmOptions& o) { o.starnav = "starnav"; }), "--starnav: expected the absolute path of starnav");
  for (const char* ok : {"30", "10:00", "1:00:00", "2-0", "2-12:00", "2-12:00:00"}) {
    SlurmOptions o;
    o.max_array_size = 1001;
    o.starnav = STARNAV_CLI_PATH;
    o.time = ok;
    EXPECT_NO_THROW(write_slurm_script(s, o)) << ok;
  }
}

TEST(SweepSlurm, ScriptRunAsSlurmWouldGivesTheLocalTable) {
  ScratchDir dir;
  test::write_open_map(dir.file("grid.map"), 20, 20);
  const SweepDir local = test::expand_in(dir, kPlanSweep, "local");
  const SweepDir array = test::expand_in(dir, kPlanSweep, "array");
  run_sweep(local, test::cli_run_options());
  merge_sweep(local, dir.file("local-merged"));
  SlurmOptions o;
  o.max_array_size = 5;
  o.starnav = STARNAV_CLI_PATH;
  const SlurmScript sc = write_slurm_script(array, o);
  ASSERT_EQ(sc.array.size(), 4u);
  for (const std::uint64_t i : sc.array) {
    // What slurmd does for array index i: bash SCRIPT with SLURM_ARRAY_TASK_ID=i.
    const std::optional<CapturedRun> r = run_and_capture({"env", "SLURM_ARRAY_TASK_ID=" + std::to_string(i), "bash", sc.path});
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->exit_code, 0) << r->err;
  }
  merge_sweep(array, dir.file("array-merged"));
  const std::vector<std::string> timing{"time_ms", "wall_s", "cpu_s"};
  EXPECT_EQ(test::without_columns(test::read_csv(dir.file("array-merged/table.csv")), timing),
            test::without_columns(test::read_csv(dir.file("local-merged/table.csv")), timing));
  EXPECT_EQ(test::read_csv(dir.file("array-merged/table.csv")).size(), 13u);
}

TEST(SweepSlurm, NothingLeftMeansNoScript) {
  ScratchDir dir;
  test::write_open_map(dir.file("grid.map"), 20, 20);
  const SweepDir s = test::expand_in(dir, kPlanSweep);
  run_sweep(s, test::cli_run_options());
  SlurmOptions o;
  o.max_array_size = 1001;
  o.starnav = STARNAV_CLI_PATH;
  const SlurmScript sc = write_slurm_script(s, o);
  EXPECT_TRUE(sc.array.empty());
  EXPECT_TRUE(sc.path.empty());
  EXPECT_EQ(sc.pending, 0u);
}

}  // namespace
}  // namespace starnav::sweep
