// The expanded sweep folder: the manifest (one line a task, stable ids), its index, reading tasks
// back, and expanding again into the same folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/sweep/manifest.hpp"
#include "starnav/sweep/task_record.hpp"
#include "sweep/sweep_test_support.hpp"

namespace starnav::sweep {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::ScratchDir;

std::vector<std::string> lines_of(const std::string& path) {
  std::vector<std::string> out;
  std::istringstream in(test::read_text(path));
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::set<std::string> ids_in(const std::string& manifest) {
  std::set<std::string> ids;
  for (const std::string& l : lines_of(manifest)) ids.insert(nlohmann::json::parse(l).at("id").get<std::string>());
  return ids;
}

TEST(SweepManifest, OneLinePerTaskWithIdValuesAndFullCommand) {
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir,
                                     "name: m\n"
                                     "command: [plan, --map, x.map, --planner, '{planner}', --start, '{q.s}', --goal, '{q.g}']\n"
                                     "axes:\n  planner: [astar, jps, dijkstra]\n"
                                     "  q: [{s: '1,1', g: '2,2'}, {s: '3,3', g: '4,4'}]\n");
  EXPECT_EQ(s.tasks, 6u);
  EXPECT_EQ(s.cwd, dir.path().string());
  EXPECT_EQ(s.columns, (std::vector<std::string>{"planner", "q.s", "q.g"}));
  const std::vector<std::string> lines = lines_of(s.manifest_path());
  ASSERT_EQ(lines.size(), 6u);
  const nlohmann::json l3 = nlohmann::json::parse(lines[3]);  // jps, second query
  EXPECT_EQ(l3.at("values"), nlohmann::json({{"planner", "jps"}, {"q.s", "3,3"}, {"q.g", "4,4"}}));
  EXPECT_EQ(l3.at("argv"), nlohmann::json({"starnav", "plan", "--map", "x.map", "--planner", "jps", "--start", "3,3", "--goal", "4,4"}));
  EXPECT_EQ(ids_in(s.manifest_path()).size(), 6u);
  // The sweep file is kept beside it, byte for byte.
  EXPECT_EQ(test::read_text(dir.file("sweep/sweep.yaml")), test::read_text(dir.file("test_sweep.yaml")));
}

TEST(SweepManifest, SameFileSameBytesAndGrownAxesKeepTheirIds) {
  ScratchDir dir;
  const std::string small = "command: [sim, e.yaml, --seed, '{seed}']\naxes:\n  seed: {from: 0, count: 5}\n  navigation.planner: [astar, jps]\n";
  test::expand_in(dir, small, "a");
  test::expand_in(dir, small, "b");
  EXPECT_EQ(test::read_text(dir.file("a/manifest.jsonl")), test::read_text(dir.file("b/manifest.jsonl")));
  // More seeds: the ten old tasks keep their ids, and a result recorded for one stays with it.
  const std::set<std::string> before = ids_in(dir.file("a/manifest.jsonl"));
  const SweepDir a = open_sweep_dir(dir.file("a"));
  TaskRecord rec;
  rec.id = *before.begin();
  rec.status = TaskStatus::Ok;
  rec.exit_code = 0;
  rec.result = "{\"x\":1}";
  write_record(a.result_path(rec.id), rec);
  test::write_text(dir.file("test_sweep.yaml"), "command: [sim, e.yaml, --seed, '{seed}']\naxes:\n  seed: {from: 0, count: 8}\n  navigation.planner: [astar, jps]\n");
  ExpandOptions force;
  force.force = true;
  const ExpandReport r = expand_sweep(dir.file("test_sweep.yaml"), dir.file("a"), force);
  EXPECT_EQ(r.tasks, 16u);
  EXPECT_EQ(r.results_kept, 1u);
  const std::set<std::string> after = ids_in(dir.file("a/manifest.jsonl"));
  for (const std::string& id : before) EXPECT_TRUE(after.count(id)) << id;
  EXPECT_EQ(after.size(), 16u);
}

TEST(SweepManifest, ReadingTasksAcrossTheIndexMatchesTheLines) {
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir, "command: [sim, e.yaml, --seed, '{seed}']\naxes:\n  seed: {from: 100, count: 3000}\n");
  const std::vector<std::string> lines = lines_of(s.manifest_path());
  ASSERT_EQ(lines.size(), 3000u);
  for (const auto& [first, count] : std::vector<std::pair<std::uint64_t, std::uint64_t>>{{0, 3}, {1020, 10}, {2047, 2}, {2990, 50}}) {
    const std::vector<SweepTask> tasks = read_tasks(s, first, count);
    ASSERT_EQ(tasks.size(), std::min<std::uint64_t>(count, 3000 - first));
    for (const SweepTask& t : tasks) {
      const nlohmann::json j = nlohmann::json::parse(lines.at(t.index));
      EXPECT_EQ(t.id, j.at("id").get<std::string>());
      EXPECT_EQ(t.values.at(0), std::to_string(100 + t.index));
      EXPECT_EQ(t.argv, j.at("argv").get<std::vector<std::string>>());
    }
  }
  std::uint64_t n = 0;
  for_each_task(s, [&](const SweepTask& t) { EXPECT_EQ(t.index, n++); });
  EXPECT_EQ(n, 3000u);
}

TEST(SweepManifest, TakeAndSetShortenAndExtendEveryTask) {
  ScratchDir dir;
  ExpandOptions o;
  o.take = {{"seed", 2}};
  o.sets = {"sim.duration_s=5"};
  const SweepDir s = test::expand_in(dir, "command: [sim, e.yaml, --seed, '{seed}']\naxes:\n  seed: {from: 0, count: 1000}\n  navigation.planner: [astar, jps]\n",
                                     "sweep", o);
  EXPECT_EQ(s.tasks, 4u);
  EXPECT_EQ(read_tasks(s, 3, 1)[0].argv, (std::vector<std::string>{"starnav", "sim", "e.yaml", "--seed", "1", "--set", "navigation.planner=jps",
                                                                    "--set", "sim.duration_s=5"}));
  o.take = {{"seeds", 2}};
  EXPECT_EQ(error_of([&] { test::expand_in(dir, test::read_text(dir.file("test_sweep.yaml")), "other", o); }),
            "--take: 'seeds' is not an axis of " + dir.file("test_sweep.yaml") + " (axes: seed, navigation.planner)");
  o.take = {};
  o.sets = {"navigation.planner=x"};
  EXPECT_EQ(error_of([&] { test::expand_in(dir, test::read_text(dir.file("test_sweep.yaml")), "other2", o); }),
            "--set: navigation.planner is an axis of the sweep (use --take to keep fewer of its values)");
}

TEST(SweepManifest, FolderRules) {
  ScratchDir dir;
  const std::string yaml = "command: [plan, '{s}']\naxes: {s: [1, 2]}\n";
  test::expand_in(dir, yaml, "s");
  // An expanded sweep is not overwritten without --force; a folder of other files never.
  EXPECT_EQ(error_of([&] { test::expand_in(dir, yaml, "s"); }),
            dir.file("s") + ": --out: holds an expanded sweep (use --force to expand again: finished tasks of the same id are kept)");
  fs::create_directories(dir.file("other"));
  test::write_text(dir.file("other/keep.txt"), "mine");
  ExpandOptions force;
  force.force = true;
  EXPECT_EQ(error_of([&] { test::expand_in(dir, yaml, "other", force); }),
            dir.file("other") + ": --out: is not empty and holds no sweep: refusing to write into it");
  EXPECT_EQ(test::read_text(dir.file("other/keep.txt")), "mine");
  EXPECT_EQ(error_of([&] { open_sweep_dir(dir.file("other")); }),
            dir.file("other") + ": not an expanded sweep (no sweep.json: run starnav sweep expand first)");
  // Two tasks with the same command: an axis value the command never sees.
  EXPECT_EQ(error_of([&] { test::expand_in(dir, "command: [plan, '{q.a}']\naxes:\n  q: [{a: 1, b: 1}, {a: 1, b: 2}]\n", "dup"); }),
            dir.file("test_sweep.yaml") + ":2: axes: tasks 0 and 1 run the same command (starnav plan 1): an axis value the command does not use?");
}

TEST(SweepManifest, LargeManifestIsCompleteAndIndexed) {
  // Not a timing test (scripts/bench-sweep.sh measures): the manifest and index of a large sweep
  // are complete and consistent.
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir, "command: [sim, e.yaml, --seed, '{seed}', --x, '{x}']\naxes:\n  seed: {from: 0, count: 200}\n  x: {from: 0, count: 100}\n");
  EXPECT_EQ(s.tasks, 20000u);
  const std::vector<SweepTask> last = read_tasks(s, 19999, 5);
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].values, (std::vector<std::string>{"199", "99"}));
  // The index: a header and one offset per 1024 lines.
  EXPECT_EQ(lines_of(dir.file("sweep/manifest.index")).size(), 1u + (20000 + 1023) / 1024);
}

}  // namespace
}  // namespace starnav::sweep
