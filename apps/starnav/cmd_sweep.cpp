// starnav sweep: a starnav command over thousands of seeds and parameter values, on this machine
// or as a Slurm job array, merged into one table (docs/sweeps.md).
//
//   starnav sweep expand SWEEP.yaml --out DIR [--take AXIS=N] [--set KEY=VALUE] [--force]
//   starnav sweep run DIR [--jobs N] [--tasks ID,...] [--retry-failed] [--limit N] [--quiet] [--json]
//   starnav sweep slurm DIR [--partition P] [--time T] [--cpus-per-task C] [--tasks-per-job K]
//                       [--max-array-size M] [--max-running R] [--sbatch NAME=VALUE] [--submit]
//   starnav sweep merge DIR [--out OUT] [--json]
//
// Exit codes: expand and slurm 0 done; run 0 when every task it ran gave a result, 1 when one
// failed, 130 when interrupted; merge 0 when every task has a result, 1 when some are missing or
// failed (the tables are written either way); 2 bad input everywhere.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/sweep/manifest.hpp"
#include "starnav/sweep/merge.hpp"
#include "starnav/sweep/slurm.hpp"
#include "starnav/sweep/task_record.hpp"
#include "starnav/sweep/task_runner.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;
using namespace starnav::sweep;

// ---- expand -------------------------------------------------------------------------------------

struct ExpandCliOptions {
  std::string file, out;
  std::vector<std::string> take, sets;
  bool force = false;
};

void run_expand(const ExpandCliOptions& o, const CLI::App& root) {
  ExpandOptions options;
  options.force = o.force;
  options.sets = o.sets;
  for (const std::string& t : o.take) {
    const std::size_t eq = t.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("expected AXIS=N, got '" + printable(t, 60) + "'", {}, 0, "--take");
    options.take.emplace_back(t.substr(0, eq), parse_unsigned(t.substr(eq + 1), "--take", "AXIS=N with N >= 1"));
  }
  // The command must be one of starnav's (and not a sweep: no sweeps of sweeps).
  const SweepSpec spec = read_sweep_file(o.file);
  const std::string sub = spec.command.front().parts.front().text;
  std::string known;
  bool found = false;
  for (const CLI::App* c : root.get_subcommands([](const CLI::App*) { return true; })) {
    if (c->get_name() == "sweep") continue;
    known += (known.empty() ? "" : ", ") + c->get_name();
    found = found || c->get_name() == sub;
  }
  if (!found)
    throw Error("'" + printable(sub, 40) + "' is not a starnav command that a sweep can run (" + known + ")", o.file,
                spec.command.front().line, "command[0]");
  const ExpandReport r = expand_sweep(o.file, o.out, options);
  const SweepDir sweep = open_sweep_dir(o.out);
  std::cout << "sweep " << sweep.spec.name << ": " << r.tasks << " tasks in " << r.manifest;
  if (r.results_kept) std::cout << " (" << r.results_kept << " finished already: their results are kept)";
  std::cout << "\n";
  const std::vector<SweepTask> first = read_tasks(sweep, 0, 1);
  if (!first.empty()) std::cout << "first task: " << shell_command(first[0].argv) << "\n";
  std::cout << "run here:   starnav sweep run " << o.out << " --jobs " << std::max(1u, std::thread::hardware_concurrency()) << "\n"
            << "or on Slurm: starnav sweep slurm " << o.out << " --submit\n";
}

// ---- run ----------------------------------------------------------------------------------------

std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int) { g_stop.store(true); }

struct RunCliOptions {
  std::string dir;
  unsigned jobs = 0;
  std::vector<std::string> tasks;
  bool retry_failed = false;
  std::uint64_t limit = 0;
  std::uint64_t group = 0, group_size = 0;
  CLI::Option* group_opt = nullptr;
  CLI::Option* group_size_opt = nullptr;
  bool quiet = false, json = false;
};

std::string duration_text(double s) {
  if (s < 0) return "?";
  const long long t = std::llround(s);
  char buf[32];
  if (t >= 3600) std::snprintf(buf, sizeof buf, "%lldh%02lldm", t / 3600, (t % 3600) / 60);
  else if (t >= 60) std::snprintf(buf, sizeof buf, "%lldm%02llds", t / 60, t % 60);
  else std::snprintf(buf, sizeof buf, "%llds", t);
  return buf;
}

void run_run(const RunCliOptions& o, Context& ctx) {
  if ((o.group_opt->count() > 0) != (o.group_size_opt->count() > 0))
    throw Error("--group and --group-size go together (the Slurm script gives both)", {}, 0, o.group_opt->count() ? "--group-size" : "--group");
  if (o.group_size_opt->count() && o.group_size == 0) throw Error("must be at least 1", {}, 0, "--group-size");
  if (o.jobs > 4096) throw Error("at most 4096 tasks at once", {}, 0, "--jobs");
  const SweepDir sweep = open_sweep_dir(o.dir);
  RunOptions options;
  options.jobs = o.jobs ? o.jobs : std::max(1u, std::thread::hardware_concurrency());
  options.executable = executable_path();
  if (options.executable.empty()) throw Error("cannot find this program's own path (/proc/self/exe) to run the tasks with");
  for (const std::string& id : o.tasks) {
    if (id.size() != 16 || id.find_first_not_of("0123456789abcdef") != std::string::npos)
      throw Error("expected task ids of 16 hexadecimal digits (merge lists them), got '" + printable(id, 40) + "'", {}, 0, "--tasks");
    options.only.push_back(id);
  }
  options.retry_failed = o.retry_failed;
  options.limit = o.limit;
  if (o.group_opt->count()) {
    options.group = o.group;
    options.group_size = o.group_size;
  }
  options.stop = &g_stop;
  ProgressBar bar("sweep " + sweep.spec.name, 0, o.quiet);
  options.progress = [&](const RunProgress& p) {
    bar.set_total(p.total);
    bar.update(p.done + p.failed, std::to_string(p.failed) + " failed, " + std::to_string(p.running) + " running, ETA " +
                                      (p.eta_s < 0 ? std::string("?") : duration_text(p.eta_s)));
  };
  // Ctrl-C, scancel and a node going down stop the run: the tasks running are killed and left
  // without a record, so the next run does them.
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
  RunReport r;
  try {
    r = run_sweep(sweep, options);
  } catch (...) {
    bar.finish();
    throw;
  }
  bar.finish();
  if (o.json) {
    nlohmann::ordered_json j;
    j["sweep"] = sweep.spec.name;
    j["selected"] = r.selected;
    j["already_ok"] = r.already_ok;
    j["already_failed"] = r.already_failed;
    j["ran"] = r.ran;
    j["ok"] = r.ok;
    j["failed"] = r.failed;
    j["interrupted"] = r.interrupted;
    j["stopped"] = r.stopped;
    j["jobs"] = options.jobs;
    j["wall_s"] = r.wall_s;
    j["task_cpu_s"] = r.task_cpu_s;
    j["task_wall_s"] = r.task_wall_s;
    j["failed_ids"] = r.failed_ids;
    std::cout << j.dump(2) << "\n";
  } else if (!o.quiet || r.failed || r.stopped) {
    std::cout << "sweep " << sweep.spec.name << ": ran " << r.ran << " of " << r.selected << " tasks in " << duration_text(r.wall_s) << " ("
              << r.ok << " with a result, " << r.failed << " failed";
    if (r.interrupted) std::cout << ", " << r.interrupted << " interrupted";
    std::cout << ")";
    // Stopped between tasks, none is interrupted: the stop is said either way.
    if (r.stopped) std::cout << "; stopped before the end (a signal): the same command runs the rest";
    if (r.already_ok || r.already_failed)
      std::cout << "; done before: " << r.already_ok << " with a result, " << r.already_failed << " failed"
                << (r.already_failed ? " (--retry-failed runs them again)" : "");
    std::cout << "\n";
    if (r.wall_s > 0 && r.ran > 0) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "task CPU time %.1f s over %.1f s: %.2f cores busy of %u jobs\n", r.task_cpu_s, r.wall_s,
                    r.task_cpu_s / r.wall_s, options.jobs);
      std::cout << buf;
    }
    for (std::size_t i = 0; i < r.failed_ids.size() && i < 10; ++i) {
      const std::optional<TaskRecord> rec = read_record(sweep.result_path(r.failed_ids[i]));
      std::cout << "failed: " << r.failed_ids[i] << ": " << (rec ? rec->reason : std::string("?")) << "\n";
    }
    if (r.failed_ids.size() > 10) std::cout << "failed: ... and " << r.failed_ids.size() - 10 << " more (starnav sweep merge lists them)\n";
    std::cout << "merge with: starnav sweep merge " << o.dir << "\n";
  }
  ctx.exit_code = r.stopped ? 130 : r.failed ? 1 : 0;
}

// ---- slurm --------------------------------------------------------------------------------------

struct SlurmCliOptions {
  std::string dir;
  SlurmOptions slurm;
  bool submit = false;
};

void run_slurm(SlurmCliOptions o, Context& ctx) {
  const SweepDir sweep = open_sweep_dir(o.dir);
  if (o.slurm.starnav.empty()) o.slurm.starnav = executable_path();
  if (!o.slurm.starnav.empty() && !fs::path(o.slurm.starnav).is_absolute())
    throw Error("expected an absolute path (the nodes run it from any folder)", o.slurm.starnav, 0, "--starnav");
  const SlurmScript s = write_slurm_script(sweep, o.slurm);
  if (s.array.empty()) {
    std::cout << "sweep " << sweep.spec.name << ": nothing to run: all " << s.tasks << " tasks have a result"
              << (o.slurm.retry_failed ? "" : " or failed (--retry-failed runs failed ones again)") << "; merge with: starnav sweep merge "
              << o.dir << "\n";
    ctx.exit_code = 0;
    return;
  }
  std::cout << "wrote " << s.path << ": " << s.pending << " of " << s.tasks << " tasks in " << s.array.size() << " array jobs of up to "
            << s.group_size << " tasks (--array=" << s.array_spec << "; MaxArraySize " << s.limit.max_array_size << ", "
            << s.limit.source << ")\n";
  if (o.submit) {
    const std::string id = submit_slurm_script(sweep, s);
    std::cout << "submitted job " << id << ": watch it with squeue -j " << id << ", then: starnav sweep merge " << o.dir << "\n";
  } else {
    std::cout << "submit with: sbatch " << s.path << "\n";
  }
  ctx.exit_code = 0;
}

// ---- merge --------------------------------------------------------------------------------------

struct MergeCliOptions {
  std::string dir, out;
  bool force = false, json = false;
};

void run_merge(const MergeCliOptions& o, Context& ctx) {
  const SweepDir sweep = open_sweep_dir(o.dir);
  const std::string out = o.out.empty() ? sweep.dir + "/merged" : o.out;
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) throw Error("exists and is not a folder", out, 0, "--out");
    // A previous merge is replaced; anything else needs --force.
    bool other = false;
    for (const fs::directory_entry& e : fs::directory_iterator(out, ec)) {
      const std::string name = e.path().filename().string();
      if (name != ".starnav-lock" && name != "plots" && name.rfind("table.", 0) != 0 && name.rfind("summary.", 0) != 0) other = true;
    }
    if (other && !o.force) throw Error("holds other files than a merge (use --force to write into it)", out, 0, "--out");
  }
  OutputFolder claim(out, "--out");
  const MergeReport r = merge_sweep(sweep, out);
  for (const std::string& w : r.warnings) print_warning(w);
  if (o.json) {
    std::cout << read_input_file(out + "/summary.json");
  } else {
    std::cout << "merged " << r.tasks << " tasks of " << sweep.spec.name << " into " << out << ": " << r.ok << " with a result, " << r.failed
              << " failed, " << r.missing << " missing\n";
    std::size_t listed = 0;
    for (std::size_t i = 0; i < r.failed_ids.size() && listed < 20; ++i, ++listed)
      std::cout << "failed: " << r.failed_ids[i] << ": " << escape_control_characters(r.failed_reasons[i]) << "\n";
    for (std::size_t i = 0; i < r.missing_ids.size() && listed < 20; ++i, ++listed) std::cout << "missing: " << r.missing_ids[i] << "\n";
    if (r.failed + r.missing > listed) std::cout << "... and " << r.failed + r.missing - listed << " more (" << out << "/summary.json lists them)\n";
    if (!r.rerun_command.empty()) std::cout << "run them again with: " << r.rerun_command << "\n";
    std::cout << "wrote";
    for (std::size_t i = 0; i < r.files.size(); ++i) std::cout << (i ? ", " : " ") << r.files[i];
    std::cout << "\n";
  }
  ctx.exit_code = r.failed + r.missing > 0 ? 1 : 0;
}

}  // namespace

void register_sweep_commands(CLI::App& app, Context& ctx) {
  auto* sweep = app.add_subcommand(
      "sweep",
      "a starnav command over thousands of seeds and parameter values, on this machine or as a Slurm job array, merged into\n"
      "one table (docs/sweeps.md): expand a sweep file into tasks, run them, merge their results");
  sweep->require_subcommand(1);
  CLI::App* root = &app;

  auto e = std::make_shared<ExpandCliOptions>();
  auto* expand = sweep->add_subcommand("expand", "write the manifest of a sweep file's tasks (one line each: id, axis values, command)");
  expand->add_option("sweep", e->file, "the sweep file (YAML; docs/sweeps.md)")->required();
  expand->add_option("--out", e->out, "the sweep's folder (created)")->required();
  expand->add_option("--take", e->take, "AXIS=N: only the first N values of an axis (a trial before the full sweep; repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  expand->add_option("--set", e->sets, "KEY=VALUE: one more --set option for every task (repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  expand->add_flag("--force", e->force, "expand into a folder that holds a sweep (finished tasks of the same id stay finished)");
  expand->callback([e, root] { run_expand(*e, *root); });

  auto r = std::make_shared<RunCliOptions>();
  auto* run = sweep->add_subcommand(
      "run",
      "run the tasks without a result on this machine, N at a time, with progress; resumable: finished tasks are never run\n"
      "again, and an interrupted run (Ctrl-C, kill) leaves the unfinished ones to the next. Exit 0 when every task run gave a\n"
      "result, 1 when one failed, 130 when interrupted");
  run->add_option("dir", r->dir, "the sweep's folder (starnav sweep expand --out)")->required();
  run->add_option("--jobs,-j", r->jobs, "tasks at once (default: one per hardware thread)");
  run->add_option("--tasks", r->tasks, "only these task ids (comma-separated; run again when they failed)")->delimiter(',');
  run->add_flag("--retry-failed", r->retry_failed, "run failed tasks again");
  run->add_option("--limit", r->limit, "run at most N tasks (e.g. 1 to try the command before the sweep)");
  r->group_opt = run->add_option("--group", r->group, "a Slurm array job's share: tasks GROUP*SIZE .. (GROUP+1)*SIZE-1 (the batch script gives it)");
  r->group_size_opt = run->add_option("--group-size", r->group_size, "tasks per group, with --group");
  run->add_flag("--quiet", r->quiet, "no progress and no report unless a task failed");
  run->add_flag("--json", r->json, "print the run's counts and times as JSON");
  run->callback([r, &ctx] { run_run(*r, ctx); });

  auto s = std::make_shared<SlurmCliOptions>();
  auto* slurm = sweep->add_subcommand(
      "slurm",
      "write a Slurm batch script that runs the tasks without a result as a job array (sbatch --array), tasks grouped so the\n"
      "array stays within the cluster's MaxArraySize (scontrol show config; 1001 when unknown)");
  slurm->add_option("dir", s->dir, "the sweep's folder, on a file system the nodes share")->required();
  slurm->add_option("--partition", s->slurm.partition, "the partition (sbatch --partition)");
  slurm->add_option("--time", s->slurm.time, "each array job's time limit (sbatch --time: MM, HH:MM:SS, D-HH:MM, ...)");
  slurm->add_option("--cpus-per-task", s->slurm.cpus_per_task, "CPUs per array job; it runs that many tasks at once");
  slurm->add_option("--tasks-per-job", s->slurm.tasks_per_job, "at least this many tasks per array job (default: as few as the limit allows)");
  slurm->add_option("--max-array-size", s->slurm.max_array_size, "the array-size limit to respect (default: scontrol show config, else 1001)");
  slurm->add_option("--max-running", s->slurm.max_running, "at most this many array jobs at once (--array=...%N)");
  slurm->add_option("--sbatch", s->slurm.sbatch, "one more #SBATCH option NAME=VALUE without dashes (mem=4G, account=lab; repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  slurm->add_option("--starnav", s->slurm.starnav, "the starnav program on the nodes (default: this one)");
  slurm->add_flag("--retry-failed", s->slurm.retry_failed, "run failed tasks again too");
  slurm->add_flag("--submit", s->submit, "submit the script with sbatch and print the job id");
  slurm->callback([s, &ctx] { run_slurm(*s, ctx); });

  auto m = std::make_shared<MergeCliOptions>();
  auto* merge = sweep->add_subcommand(
      "merge",
      "collect the task results into one table (table.csv/.json/.md), a summary per group (summary.csv/.json/.md) and plots;\n"
      "list missing and failed tasks with the command to run them again. Exit 0 when every task has a result, else 1");
  merge->add_option("dir", m->dir, "the sweep's folder")->required();
  merge->add_option("--out", m->out, "the folder for the merged files (default DIR/merged)");
  merge->add_flag("--force", m->force, "write into an --out folder that holds other files");
  merge->add_flag("--json", m->json, "print summary.json");
  merge->callback([m, &ctx] { run_merge(*m, ctx); });
}

}  // namespace starnav::cli
