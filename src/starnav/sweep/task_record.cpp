#include "starnav/sweep/task_record.hpp"

#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/output_file.hpp"

namespace starnav::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

std::string record_json(const TaskRecord& r) {
  json j;
  j["id"] = r.id;
  j["status"] = r.status == TaskStatus::Ok ? "ok" : "failed";
  j["exit_code"] = r.exit_code;
  if (r.status == TaskStatus::Failed) {
    j["signal"] = r.signal;
    j["reason"] = r.reason;
    j["stderr_tail"] = r.stderr_tail;
  }
  j["wall_s"] = r.wall_s;
  j["cpu_s"] = r.cpu_s;
  j["host"] = r.host;
  if (r.status == TaskStatus::Ok) j["result"] = json::parse(r.result);
  // Replace invalid UTF-8 (a stderr tail cut mid-character) rather than refuse to write.
  return j.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

TaskRecord parse_record(std::string_view text, const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw Error("not a task record (invalid JSON: " + one_line(e.what(), 120) + ")", source);
  }
  TaskRecord r;
  try {
    if (!j.is_object()) throw Error("not a task record (expected a JSON object)", source);
    r.id = j.at("id").get<std::string>();
    const std::string status = j.at("status").get<std::string>();
    if (status != "ok" && status != "failed") throw Error("unknown status '" + printable(status, 40) + "'", source, 0, "status");
    r.status = status == "ok" ? TaskStatus::Ok : TaskStatus::Failed;
    r.exit_code = j.at("exit_code").get<int>();
    r.wall_s = j.at("wall_s").get<double>();
    r.cpu_s = j.at("cpu_s").get<double>();
    r.host = j.at("host").get<std::string>();
    if (r.status == TaskStatus::Ok) {
      r.result = j.at("result").dump();
    } else {
      r.signal = j.at("signal").get<int>();
      r.reason = j.at("reason").get<std::string>();
      r.stderr_tail = j.at("stderr_tail").get<std::string>();
    }
  } catch (const json::exception& e) {
    throw Error("not a task record (" + one_line(e.what(), 120) + ")", source);
  }
  return r;
}

std::optional<TaskRecord> read_record(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  return parse_record(read_input_file(path, std::uint64_t{1} << 30), path);
}

void write_record(const std::string& path, const TaskRecord& record) {
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  write_file_atomically(path, record_json(record));
}

}  // namespace starnav::sweep
