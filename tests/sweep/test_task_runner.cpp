// Running a sweep's tasks on this machine: failures recorded with their exit code and stderr, a
// resumed run that redoes nothing finished, a runner killed halfway, timeouts, signals, and the
// interruption that leaves no record.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/sweep/manifest.hpp"
#include "starnav/sweep/process.hpp"
#include "starnav/sweep/task_record.hpp"
#include "starnav/sweep/task_runner.hpp"
#include "sweep/sweep_test_support.hpp"

namespace starnav::sweep {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::ScratchDir;

// id -> bytes of every record file, and the names of anything else in results/.
std::map<std::string, std::string> records_in(const SweepDir& s, std::vector<std::string>* strays = nullptr) {
  std::map<std::string, std::string> out;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(s.dir + "/results", ec)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    if (name.size() == 21 && e.path().extension() == ".json") out[e.path().stem().string()] = test::read_text(e.path().string());
    else if (strays) strays->push_back(name);
  }
  return out;
}

std::map<std::string, TaskRecord> parsed_records(const SweepDir& s) {
  std::map<std::string, TaskRecord> out;
  for (const auto& [id, text] : records_in(s)) out[id] = parse_record(text, id);
  return out;
}

TEST(SweepRun, InjectedFailuresAreRecordedThenResumeRedoesNothingFinished) {
  ScratchDir dir;
  test::write_open_map(dir.file("open.map"), 20, 20);
  // late.map is missing at first: those tasks fail with starnav's exit 2 and its error line.
  const SweepDir s = test::expand_in(dir,
                                     "command: [plan, --map, '{map}', --start, '0,0', --goal, '{goal}', --planner, '{planner}', --json]\n"
                                     "result: stdout\n"
                                     "axes:\n"
                                     "  map: [open.map, late.map]\n"
                                     "  planner: [astar, jps]\n"
                                     "  goal: ['19,19', '5,10', '12,0']\n"
                                     "metrics: {cost: /cost}\n");
  ASSERT_EQ(s.tasks, 12u);
  RunOptions o = test::cli_run_options();
  o.limit = 5;
  RunReport r = run_sweep(s, o);
  EXPECT_EQ(r.ran, 5u);
  EXPECT_EQ(r.ok, 5u);  // the first five tasks are all on open.map
  const std::map<std::string, std::string> first = records_in(s);
  ASSERT_EQ(first.size(), 5u);
  const std::vector<SweepTask> tasks = read_tasks(s, 0, 12);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_TRUE(first.count(tasks[i].id)) << "task " << i << " ran first";

  o.limit = 0;
  r = run_sweep(s, o);
  EXPECT_EQ(r.already_ok, 5u);
  EXPECT_EQ(r.ran, 7u);
  EXPECT_EQ(r.ok, 1u);
  EXPECT_EQ(r.failed, 6u);
  // Nothing finished ran again: its record is the same bytes.
  const std::map<std::string, std::string> second = records_in(s);
  for (const auto& [id, text] : first) EXPECT_EQ(second.at(id), text) << id;
  const TaskRecord bad = parse_record(second.at(tasks[6].id), "late");
  EXPECT_EQ(bad.status, TaskStatus::Failed);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.reason, "exit code 2");
  EXPECT_NE(bad.stderr_tail.find("starnav: error: late.map"), std::string::npos) << bad.stderr_tail;
  const TaskRecord good = parse_record(second.at(tasks[0].id), "open");
  EXPECT_EQ(nlohmann::json::parse(good.result).at("found"), true);
  EXPECT_GT(good.cpu_s, 0.0);

  // Failed tasks wait for --retry-failed; then, with the map there, they give results.
  r = run_sweep(s, o);
  EXPECT_EQ(r.ran, 0u);
  EXPECT_EQ(r.already_failed, 6u);
  fs::copy_file(dir.file("open.map"), dir.file("late.map"));
  o.retry_failed = true;
  r = run_sweep(s, o);
  EXPECT_EQ(r.ran, 6u);
  EXPECT_EQ(r.ok, 6u);
  for (const auto& [id, rec] : parsed_records(s)) EXPECT_EQ(rec.status, TaskStatus::Ok) << id;
  // Nothing left behind but the records.
  EXPECT_FALSE(fs::exists(s.dir + "/work"));
  std::vector<std::string> strays;
  records_in(s, &strays);
  EXPECT_TRUE(strays.empty()) << strays.front();
}

// Processes whose command line contains `needle` (the tasks of one test).
int processes_with(const std::string& needle) {
  int n = 0;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string pid = e.path().filename().string();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmd = test::read_text("/proc/" + pid + "/cmdline");
    for (char& c : cmd)
      if (c == '\0') c = ' ';
    if (cmd.find(needle) != std::string::npos && cmd.find("sweep run") == std::string::npos) ++n;
  }
  return n;
}

TEST(SweepRun, RunnerKilledHalfwayLeavesNoHalfRecordAndResumes) {
  ScratchDir dir;
  // Dijkstra corner to corner on an open map: a few tenths of a second per task.
  const std::string map = test::write_open_map(dir.file("killtest_open.map"), 900, 900);
  const SweepDir s = test::expand_in(dir,
                                     "command: [plan, --map, killtest_open.map, --start, '0,{row}', --goal, '899,899', --planner, dijkstra, --json]\n"
                                     "axes:\n  row: {from: 0, count: 14}\n"
                                     "metrics: {cost: /cost}\n");
  ChildSpec spec;
  spec.executable = STARNAV_CLI_PATH;
  spec.argv = {"starnav", "sweep", "run", s.dir, "--jobs", "2", "--quiet"};
  spec.stdout_path = dir.file("runner.out");
  spec.stderr_path = dir.file("runner.err");
  auto runner = std::make_unique<Child>(spec);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (records_in(s).size() < 4 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ::kill(runner->pid(), SIGKILL);  // the runner only: its tasks must die with it
  while (!runner->try_wait()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const std::map<std::string, std::string> before = records_in(s);
  ASSERT_GE(before.size(), 4u);
  ASSERT_LT(before.size(), 14u) << "the run finished before it was killed: make the tasks longer";
  for (int i = 0; i < 200 && processes_with("killtest_open.map") > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(processes_with("killtest_open.map"), 0) << "a task outlived its runner";
  // Every record is whole; no temporary file is left among them.
  std::vector<std::string> strays;
  for (const auto& [id, text] : records_in(s, &strays)) EXPECT_EQ(parse_record(text, id).status, TaskStatus::Ok);
  EXPECT_TRUE(strays.empty()) << strays.front();

  const RunReport r = run_sweep(s, test::cli_run_options());
  EXPECT_EQ(r.already_ok, before.size());
  EXPECT_EQ(r.ran, 14u - before.size());
  EXPECT_EQ(r.ok, r.ran);
  const std::map<std::string, std::string> after = records_in(s);
  EXPECT_EQ(after.size(), 14u);
  for (const auto& [id, text] : before) EXPECT_EQ(after.at(id), text);
  EXPECT_FALSE(fs::exists(s.dir + "/work")) << "the killed runner's task folders were not cleaned";
}

// Tasks run by /bin/sh instead of starnav: every way a task can end.
const char* kShellSweep =
    "command: ['-c', 'case $1 in\n"
    "  ok) printf ''{{\"v\": 1, \"flag\": true}}'';;\n"
    "  slow*) sleep 30;;\n"
    "  segv) kill -SEGV $$;;\n"
    "  term) kill -TERM $$;;\n"
    "  badjson) echo not json;;\n"
    "  exit3) echo first >&2; echo oops >&2; exit 3;;\n"
    "  exit1) printf ''{{\"v\": 2}}''; exit 1;;\n"
    "  file) printf ''{{\"v\": 3}}'' > \"$2/r.json\";;\n"
    "  nofile) true;;\n"
    "esac', sh, '{case}', '{out}']\n";

TEST(SweepRun, EveryWayATaskEnds) {
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir, std::string(kShellSweep) +
                                              "result: stdout\ntimeout_s: 0.5\n"
                                              "axes:\n  case: [ok, slow, segv, term, badjson, exit3, exit1]\n");
  RunOptions o;
  o.jobs = 4;
  o.executable = "/bin/sh";
  const auto t0 = std::chrono::steady_clock::now();
  const RunReport r = run_sweep(s, o);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0) << "the timeout did not stop the slow task";
  EXPECT_EQ(r.ran, 6u);
  EXPECT_EQ(r.interrupted, 1u);  // term: stopped from outside, no record, runs again next time
  EXPECT_EQ(r.ok, 2u);
  EXPECT_EQ(r.failed, 4u);
  const std::vector<SweepTask> tasks = read_tasks(s, 0, 7);
  std::map<std::string, TaskRecord> recs = parsed_records(s);
  const auto rec = [&](int i) { return recs.at(tasks[static_cast<std::size_t>(i)].id); };
  EXPECT_EQ(rec(0).status, TaskStatus::Ok);
  EXPECT_EQ(nlohmann::json::parse(rec(0).result), nlohmann::json::parse("{\"v\": 1, \"flag\": true}"));
  EXPECT_EQ(rec(1).reason, "timed out after 0.5 s (timeout_s)");
  EXPECT_EQ(rec(1).exit_code, -1);
  EXPECT_EQ(rec(2).reason, "killed by signal 11 (Segmentation fault)");
  EXPECT_EQ(rec(2).signal, SIGSEGV);
  EXPECT_EQ(recs.count(tasks[3].id), 0u);
  EXPECT_EQ(rec(4).reason.rfind("its standard output is not JSON (", 0), 0u) << rec(4).reason;
  EXPECT_EQ(rec(5).reason, "exit code 3");
  EXPECT_EQ(rec(5).stderr_tail, "first\noops");
  EXPECT_EQ(rec(6).status, TaskStatus::Ok);  // exit 1 is a result by default
  EXPECT_EQ(rec(6).exit_code, 1);
}

TEST(SweepRun, ResultFileInTheOutputFolderAndKeptOutputs) {
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir, std::string(kShellSweep) + "result: r.json\nresult_exit_codes: [0]\nkeep_outputs: true\n"
                                                                      "axes:\n  case: [file, nofile, exit1]\n");
  RunOptions o;
  o.executable = "/bin/sh";
  const RunReport r = run_sweep(s, o);
  EXPECT_EQ(r.ok, 1u);
  EXPECT_EQ(r.failed, 2u);
  const std::vector<SweepTask> tasks = read_tasks(s, 0, 3);
  std::map<std::string, TaskRecord> recs = parsed_records(s);
  EXPECT_EQ(nlohmann::json::parse(recs.at(tasks[0].id).result), nlohmann::json::parse("{\"v\": 3}"));
  EXPECT_EQ(recs.at(tasks[1].id).reason, "its result file r.json is missing");
  EXPECT_EQ(recs.at(tasks[2].id).reason, "exit code 1");  // not a result code here
  EXPECT_EQ(test::read_text(s.dir + "/outputs/" + tasks[0].id + "/out/r.json"), "{\"v\": 3}");
}

TEST(SweepRun, StopKillsRunningTasksAndRecordsNothing) {
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir, std::string(kShellSweep) + "axes:\n  case: [slow1, slow2, slow3]\n");
  std::atomic<bool> stop{false};
  RunOptions o;
  o.jobs = 2;
  o.executable = "/bin/sh";
  o.stop = &stop;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    stop.store(true);
  });
  const auto t0 = std::chrono::steady_clock::now();
  const RunReport r = run_sweep(s, o);
  stopper.join();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  EXPECT_TRUE(r.stopped);
  EXPECT_EQ(r.interrupted, 2u);  // the two running
  EXPECT_EQ(r.ran, 0u);          // the third never started
  EXPECT_TRUE(records_in(s).empty());
}

TEST(SweepRun, GroupsTaskListsAndTheFolderLock) {
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir, std::string(kShellSweep) + "axes:\n  case: [ok, exit1, exit3, nofile, badjson, ok2]\n");
  RunOptions o;
  o.executable = "/bin/sh";
  o.group = 1;
  o.group_size = 4;  // tasks 4 and 5
  RunReport r = run_sweep(s, o);
  EXPECT_EQ(r.selected, 2u);
  const std::vector<SweepTask> tasks = read_tasks(s, 0, 6);
  EXPECT_EQ(records_in(s).size(), 2u);
  EXPECT_TRUE(records_in(s).count(tasks[4].id) && records_in(s).count(tasks[5].id));
  o.group = 2;
  EXPECT_EQ(error_of([&] { run_sweep(s, o); }), "--group: group 2 is past the last task (6 tasks in groups of 4)");
  o.group.reset();
  o.only = {tasks[2].id, tasks[4].id};  // exit3 not run yet; badjson failed: named, so run again
  r = run_sweep(s, o);
  EXPECT_EQ(r.selected, 2u);
  EXPECT_EQ(r.ran, 2u);
  o.only = {"0123456789abcdef"};
  EXPECT_EQ(error_of([&] { run_sweep(s, o); }), "--tasks: no task 0123456789abcdef in " + s.manifest_path());
  // A second whole-sweep run on this machine at the same time is refused.
  o.only.clear();
  OutputFolder held(s.dir, "DIR");
  EXPECT_EQ(error_of([&] { run_sweep(s, o); }), s.dir + ": DIR: another starnav run is writing into this folder now");
}

TEST(SweepRun, AProgramThatCannotStartStopsTheRun) {
  ScratchDir dir;
  const SweepDir s = test::expand_in(dir, std::string(kShellSweep) + "axes:\n  case: [ok]\n");
  RunOptions o;
  o.executable = dir.file("no-such-program");
  const std::string what = error_of([&] { run_sweep(s, o); });
  EXPECT_NE(what.find("cannot run " + dir.file("no-such-program") + " in " + dir.path().string() + ": No such file or directory"), std::string::npos)
      << what;
  EXPECT_TRUE(records_in(s).empty());
}

}  // namespace
}  // namespace starnav::sweep
