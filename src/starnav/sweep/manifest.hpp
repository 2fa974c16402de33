#pragma once
// An expanded sweep: the folder `starnav sweep expand` writes and `sweep run`, `sweep slurm` and
// `sweep merge` read (docs/sweeps.md):
//
//   DIR/sweep.yaml        the sweep file, copied byte for byte (metrics, summary, plots, result)
//   DIR/sweep.json        where tasks run (the sweep file's folder), the task count, the table's axis columns
//   DIR/manifest.jsonl    one task a line: {"id", "values": {column: text}, "argv": ["starnav", ...]}
//   DIR/manifest.index    the byte offset of every 1024th line, so a worker reads only its own tasks
//   DIR/results/XX/ID.json  each finished task's record (task_record.hpp), XX the id's first two digits
//
// A task's id is a digest of its command and result file: the same task keeps its id when the
// sweep is expanded again, also after axes grew, so finished tasks are never run twice. Tasks are
// in the product order of the axes, the first axis varying slowest.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "starnav/sweep/sweep_file.hpp"

namespace starnav::sweep {

// One task. In argv, "{out}" stands for the task's output folder (filled in when it runs) and
// "{{" / "}}" for literal braces; argv[0] is "starnav" (the runner runs its own executable).
struct SweepTask {
  std::uint64_t index = 0;
  std::string id;                   // 16 hexadecimal digits
  std::vector<std::string> values;  // one text per axis column
  std::vector<std::string> argv;
};

// Task `index` of the product of the axes; `extra_sets` are appended as --set options.
SweepTask make_task(const SweepSpec& spec, std::uint64_t index, const std::vector<std::string>& extra_sets = {});

// argv with "{out}" replaced by `out_dir` and the literal braces restored.
std::vector<std::string> command_for_run(const std::vector<std::string>& argv, const std::string& out_dir);

// The command as one line a shell would run (quoted where needed), for messages and docs.
std::string shell_command(const std::vector<std::string>& argv);

struct ExpandOptions {
  std::vector<std::pair<std::string, std::uint64_t>> take;  // keep the first N values of an axis
  std::vector<std::string> sets;                            // KEY=VALUE, passed to every task as --set
  bool force = false;                                       // write into a folder that holds a sweep
};

struct ExpandReport {
  std::uint64_t tasks = 0;
  std::uint64_t results_kept = 0;  // records already in DIR/results whose task is in the new manifest
  std::string manifest;
};

// Reads SWEEP_FILE, applies `options`, and writes DIR (created when missing). A folder that is not
// empty is refused without force; with force, an expanded sweep's results/ stay (tasks of the
// same id are done), the rest of the folder is rewritten.
ExpandReport expand_sweep(const std::string& sweep_file, const std::string& dir, const ExpandOptions& options);

// An expanded sweep folder, read back.
struct SweepDir {
  std::string dir;
  SweepSpec spec;  // from DIR/sweep.yaml (glob axes unresolved: the manifest holds their values)
  std::string cwd;  // where tasks run
  std::uint64_t tasks = 0;
  std::vector<std::string> columns;  // the axis columns
  std::string manifest_path() const { return dir + "/manifest.jsonl"; }
  std::string result_path(const std::string& id) const;
};

// Error naming the folder when it is not an expanded sweep.
SweepDir open_sweep_dir(const std::string& dir);

// Reads tasks [first, first + count) of the manifest (fewer at its end).
std::vector<SweepTask> read_tasks(const SweepDir& sweep, std::uint64_t first, std::uint64_t count);

// Calls `f` for every task, in order, without holding the manifest in memory.
void for_each_task(const SweepDir& sweep, const std::function<void(const SweepTask&)>& f);

}  // namespace starnav::sweep
