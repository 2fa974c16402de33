#pragma once
// What a finished task leaves: one small JSON file, DIR/results/XX/ID.json, written atomically
// (temporary file, then rename) once the task has ended, so a task killed with its node leaves no
// record at all and the next run does it again.
//
//   {"id": "...", "status": "ok", "exit_code": 0, "wall_s": 0.52, "cpu_s": 0.49, "host": "node7",
//    "result": {...the command's JSON result...}}
//   {"id": "...", "status": "failed", "exit_code": 2, "signal": 0, "reason": "exit code 2",
//    "stderr_tail": "...", "wall_s": ..., "cpu_s": ..., "host": ...}
//
// The whole result document is kept, so metrics added to the sweep file later are merged without
// running anything again.
#include <optional>
#include <string>
#include <string_view>

namespace starnav::sweep {

enum class TaskStatus { Ok, Failed };

struct TaskRecord {
  std::string id;
  TaskStatus status = TaskStatus::Failed;
  int exit_code = -1;  // -1: the task did not exit by itself (a signal, a timeout, not started)
  int signal = 0;
  std::string reason;       // failed: why, one line
  std::string stderr_tail;  // failed: the end of its standard error
  double wall_s = 0.0, cpu_s = 0.0;
  std::string host;
  std::string result;  // ok: the result document, as compact JSON
};

std::string record_json(const TaskRecord& record);

// Error naming `source` when `text` is not a record.
TaskRecord parse_record(std::string_view text, const std::string& source);

// The record at `path`, or nullopt when there is none; Error when it is unreadable.
std::optional<TaskRecord> read_record(const std::string& path);

// Writes the record atomically, creating its folder.
void write_record(const std::string& path, const TaskRecord& record);

}  // namespace starnav::sweep
