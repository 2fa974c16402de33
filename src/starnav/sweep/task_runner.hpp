#pragma once
// Runs the tasks of an expanded sweep as child processes, `jobs` at a time, and records each one's
// end (task_record.hpp). Resumable: a task with a record is not run again (a failed one only when
// asked), and a run that is interrupted or killed leaves the tasks it had not finished without a
// record, so the next run does them.
//
// A task is a result when it exits with one of the sweep's result_exit_codes (0 and 1 unless the
// sweep file says otherwise: starnav's exit 1 is "a well-formed query with no answer", e.g. no
// path) and its result file holds JSON; anything else is a failure, recorded with its exit code or
// signal and the tail of its standard error. A task ended by SIGINT, SIGTERM or SIGHUP was stopped
// from outside (Ctrl-C, scancel, a node shutting down), not failed: it gets no record.
//
// Each task runs in the sweep file's folder with its output folder {out} at
// DIR/work/ID.HOST.PID/out (unique per attempt, so two runners never share one); the folder is
// removed once the record is written, or moved to DIR/outputs/ID with keep_outputs.
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "starnav/sweep/manifest.hpp"

namespace starnav::sweep {

struct RunProgress {
  std::uint64_t total = 0;  // tasks this run starts with to do
  std::uint64_t done = 0;   // finished with a result
  std::uint64_t failed = 0;
  unsigned running = 0;
  double elapsed_s = 0.0;
  double eta_s = -1.0;  // -1 until a task has finished
};

struct RunOptions {
  unsigned jobs = 1;
  std::string executable;  // the starnav program each task's "starnav" runs
  // Only these task ids (an id not in the manifest is an Error); they are run again when failed.
  std::vector<std::string> only;
  bool retry_failed = false;  // run failed tasks again
  std::uint64_t limit = 0;    // at most this many tasks (0: all)
  // A Slurm array job's share: tasks [group * group_size, (group + 1) * group_size).
  std::optional<std::uint64_t> group;
  std::uint64_t group_size = 0;
  const std::atomic<bool>* stop = nullptr;  // set (by a signal handler) to stop: running tasks are killed, unrecorded
  std::function<void(const RunProgress&)> progress;
};

struct RunReport {
  std::uint64_t selected = 0;  // tasks in the run's scope (all, the group, or the ids given)
  std::uint64_t already_ok = 0, already_failed = 0;
  std::uint64_t ran = 0, ok = 0, failed = 0, interrupted = 0;
  bool stopped = false;  // options.stop was set
  double wall_s = 0.0;
  double task_cpu_s = 0.0, task_wall_s = 0.0;  // summed over the tasks that ended
  std::vector<std::string> failed_ids;         // of this run, in manifest order of their end
};

// Error for bad options, a sweep folder that cannot be read, or a task that cannot be started at
// all (the program or the working folder missing): nothing would run.
RunReport run_sweep(const SweepDir& sweep, const RunOptions& options);

// The last `max_lines` lines (at most `max_bytes` bytes) of `text`.
std::string text_tail(const std::string& text, std::size_t max_lines, std::size_t max_bytes);

}  // namespace starnav::sweep
