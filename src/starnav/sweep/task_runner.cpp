#include "starnav/sweep/task_runner.hpp"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <set>
#include <system_error>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/sweep/process.hpp"
#include "starnav/sweep/task_record.hpp"

namespace starnav::sweep {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::uint64_t kBlock = 4096;                          // tasks read from the manifest at once
constexpr double kStopGraceS = 5.0;                            // SIGTERM, then SIGKILL after this long
constexpr std::uint64_t kMaxResultBytes = std::uint64_t{256} << 20;  // a result document larger is refused

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string read_tail(const std::string& path, std::size_t max_bytes) {
  std::string s;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return s;
  if (std::fseek(f.get(), 0, SEEK_END) == 0) {
    const long size = std::ftell(f.get());
    if (size > static_cast<long>(max_bytes)) std::fseek(f.get(), size - static_cast<long>(max_bytes), SEEK_SET);
    else std::fseek(f.get(), 0, SEEK_SET);
  }
  char buf[8192];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f.get())) > 0;) s.append(buf, n);
  return s;
}

bool interrupted_from_outside(int sig) { return sig == SIGINT || sig == SIGTERM || sig == SIGHUP; }

// "ID.HOST.PID": the attempt folder of one runner process on one machine.
std::string attempt_name(const std::string& id, const std::string& host) {
  return id + "." + host + "." + std::to_string(::getpid());
}

// Removes the attempt folders that runners on this machine left when they were killed.
void remove_stale_attempts(const std::string& work_dir, const std::string& host) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(work_dir, ec)) {
    const std::string name = e.path().filename().string();
    const std::size_t last = name.rfind('.');
    if (name.size() < 19 || name[16] != '.' || last == std::string::npos || last <= 17) continue;
    if (name.substr(17, last - 17) != host) continue;
    const long pid = std::strtol(name.c_str() + last + 1, nullptr, 10);
    if (pid <= 0 || (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH)) fs::remove_all(e.path(), ec);
  }
}

struct Running {
  SweepTask task;
  std::string attempt;
  std::unique_ptr<Child> child;
  Clock::time_point start;
  bool timed_out = false;
  bool stopped = false;
};

class Runner {
 public:
  Runner(const SweepDir& sweep, const RunOptions& options) : sweep_(sweep), options_(options), host_(host_name()) {}

  RunReport run() {
    const auto t0 = Clock::now();
    select();
    RunReport& r = report_;
    progress_.total = pending_.size();
    const std::string work_dir = sweep_.dir + "/work";
    std::error_code ec;
    fs::create_directories(work_dir, ec);
    if (ec) throw Error("cannot create the folder: " + ec.message(), work_dir);
    remove_stale_attempts(work_dir, host_);
    std::size_t next = 0;
    std::vector<Running> running;
    const unsigned jobs = std::max(1u, options_.jobs);
    report_progress(t0, running.size());
    while (next < pending_.size() || !running.empty()) {
      const bool stopping = options_.stop && options_.stop->load();
      if (stopping && !r.stopped) {
        r.stopped = true;
        stop_time_ = Clock::now();
        for (Running& run : running) {
          run.stopped = true;
          run.child->kill_group(SIGTERM);
        }
      }
      while (!r.stopped && running.size() < jobs && next < pending_.size()) running.push_back(start(task_at(pending_[next++])));
      if (running.empty()) break;
      wait_for_any(running);
      for (std::size_t i = 0; i < running.size();) {
        if (std::optional<ChildExit> e = running[i].child->try_wait()) {
          finish(running[i], *e);
          running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
          report_progress(t0, running.size());
        } else {
          ++i;
        }
      }
      check_timeouts(running);
      // Tasks that do not stop on SIGTERM are killed after a grace period.
      if (r.stopped && seconds_since(stop_time_) > kStopGraceS)
        for (Running& run : running) run.child->kill_group(SIGKILL);
    }
    r.wall_s = seconds_since(t0);
    fs::remove(work_dir, ec);  // only when empty: other runners may still be at work
    return r;
  }

 private:
  // The tasks to run, in manifest order.
  void select() {
    std::uint64_t first = 0, last = sweep_.tasks;
    if (options_.group) {
      if (options_.group_size == 0) throw Error("a group needs a group size", {}, 0, "--group-size");
      if (*options_.group >= (sweep_.tasks + options_.group_size - 1) / options_.group_size)
        throw Error("group " + std::to_string(*options_.group) + " is past the last task (" + std::to_string(sweep_.tasks) +
                        " tasks in groups of " + std::to_string(options_.group_size) + ")",
                    {}, 0, "--group");
      first = *options_.group * options_.group_size;
      last = std::min(sweep_.tasks, first + options_.group_size);
    }
    const std::set<std::string> only(options_.only.begin(), options_.only.end());
    std::set<std::string> found;
    for (std::uint64_t b = first; b < last; b += kBlock) {
      for (SweepTask& t : read_tasks(sweep_, b, std::min(kBlock, last - b))) {
        const bool named = only.count(t.id) > 0;
        if (!only.empty() && !named) continue;
        found.insert(t.id);
        ++report_.selected;
        const std::optional<TaskRecord> rec = read_existing(t.id);
        if (rec && rec->status == TaskStatus::Ok) {
          ++report_.already_ok;
          continue;
        }
        if (rec && !(options_.retry_failed || named)) {
          ++report_.already_failed;
          continue;
        }
        if (options_.limit && pending_.size() >= options_.limit) continue;
        pending_.push_back(t.index);
      }
    }
    for (const std::string& id : only)
      if (!found.count(id))
        throw Error("no task " + printable(id, 40) + " in " + (options_.group ? "this group of " : "") + sweep_.manifest_path(), {}, 0, "--tasks");
  }

  std::optional<TaskRecord> read_existing(const std::string& id) const {
    try {
      return read_record(sweep_.result_path(id));
    } catch (const Error&) {
      return std::nullopt;  // an unreadable record is no result: the task runs again and replaces it
    }
  }

  const SweepTask& task_at(std::uint64_t index) {
    const std::uint64_t block = index / kBlock * kBlock;
    if (block_first_ != block || block_.empty()) {
      block_ = read_tasks(sweep_, block, kBlock);
      block_first_ = block;
    }
    return block_.at(static_cast<std::size_t>(index - block));
  }

  Running start(const SweepTask& task) {
    Running run;
    run.task = task;
    run.attempt = fs::absolute(sweep_.dir + "/work/" + attempt_name(task.id, host_)).string();
    std::error_code ec;
    fs::remove_all(run.attempt, ec);
    // Another runner that finishes removes the work folder when it is empty (its last act), which
    // can fall between making the work folder and making this task's inside it: make them again.
    for (int tries = 0; tries < 20; ++tries) {
      ec.clear();
      fs::create_directories(run.attempt + "/out", ec);
      if (ec != std::errc::no_such_file_or_directory) break;
    }
    if (ec) throw Error("cannot create the task's folder: " + ec.message(), run.attempt);
    ChildSpec spec;
    spec.executable = options_.executable;
    spec.argv = command_for_run(task.argv, run.attempt + "/out");
    spec.cwd = sweep_.cwd;
    spec.stdout_path = run.attempt + "/stdout";
    spec.stderr_path = run.attempt + "/stderr";
    run.start = Clock::now();
    try {
      run.child = std::make_unique<Child>(spec);
    } catch (const Error& e) {
      fs::remove_all(run.attempt, ec);
      throw Error("task " + task.id + ": " + e.message());
    }
    return run;
  }

  void wait_for_any(std::vector<Running>& running) const {
    int timeout_ms = 1000;
    if (sweep_.spec.timeout_s > 0)
      for (const Running& run : running) {
        const double left = sweep_.spec.timeout_s - seconds_since(run.start);
        timeout_ms = std::min(timeout_ms, std::max(1, static_cast<int>(std::ceil(left * 1000.0))));
      }
    std::vector<pollfd> fds;
    for (const Running& run : running) {
      if (run.child->wait_fd() < 0) {
        timeout_ms = std::min(timeout_ms, 5);  // no pidfd: poll the children
        continue;
      }
      fds.push_back({run.child->wait_fd(), POLLIN, 0});
    }
    ::poll(fds.data(), fds.size(), timeout_ms);  // EINTR (a signal) just returns early
  }

  void check_timeouts(std::vector<Running>& running) const {
    if (sweep_.spec.timeout_s <= 0) return;
    for (Running& run : running)
      if (!run.timed_out && seconds_since(run.start) >= sweep_.spec.timeout_s) {
        run.timed_out = true;
        run.child->kill_group(SIGKILL);
      }
  }

  void finish(Running& run, const ChildExit& e) {
    RunReport& r = report_;
    const double wall = seconds_since(run.start);
    std::error_code ec;
    if (run.stopped || (!run.timed_out && interrupted_from_outside(e.signal))) {
      ++r.interrupted;
      fs::remove_all(run.attempt, ec);
      return;
    }
    ++r.ran;
    r.task_cpu_s += e.cpu_s;
    r.task_wall_s += wall;
    TaskRecord rec;
    rec.id = run.task.id;
    rec.exit_code = e.exit_code;
    rec.signal = e.signal;
    // Microseconds: what the clocks resolve, and short numbers in the tables.
    rec.wall_s = std::round(wall * 1e6) / 1e6;
    rec.cpu_s = std::round(e.cpu_s * 1e6) / 1e6;
    rec.host = host_;
    const auto& codes = sweep_.spec.result_exit_codes;
    if (run.timed_out) {
      char limit[32];
      std::snprintf(limit, sizeof limit, "%g", sweep_.spec.timeout_s);
      rec.reason = std::string("timed out after ") + limit + " s (timeout_s)";
      rec.exit_code = -1;
    } else if (e.signal != 0) {
      rec.reason = "killed by signal " + std::to_string(e.signal) + " (" + std::string(::strsignal(e.signal)) + ")";
    } else if (std::find(codes.begin(), codes.end(), e.exit_code) == codes.end()) {
      rec.reason = "exit code " + std::to_string(e.exit_code);
    } else {
      const bool from_stdout = sweep_.spec.result == "stdout";
      const std::string path = from_stdout ? run.attempt + "/stdout" : run.attempt + "/out/" + sweep_.spec.result;
      const std::string what = from_stdout ? "its standard output" : "its result file " + sweep_.spec.result;
      try {
        if (!from_stdout && !fs::exists(path, ec)) throw Error(what + " is missing");
        const std::string text = read_input_file(path, kMaxResultBytes);
        rec.result = nlohmann::json::parse(text).dump();
        rec.status = TaskStatus::Ok;
      } catch (const nlohmann::json::exception& x) {
        rec.reason = what + " is not JSON (" + one_line(x.what(), 160) + ")";
      } catch (const Error& x) {
        rec.reason = x.file().empty() ? x.message() : what + ": " + x.message();
      }
    }
    if (rec.status == TaskStatus::Failed) rec.stderr_tail = text_tail(read_tail(run.attempt + "/stderr", 64 * 1024), 20, 4000);
    if (sweep_.spec.keep_outputs) {
      const std::string kept = sweep_.dir + "/outputs/" + rec.id;
      fs::create_directories(sweep_.dir + "/outputs", ec);
      fs::remove_all(kept, ec);
      fs::rename(run.attempt, kept, ec);
    }
    write_record(sweep_.result_path(rec.id), rec);
    fs::remove_all(run.attempt, ec);
    if (rec.status == TaskStatus::Ok) {
      ++r.ok;
      ++progress_.done;
    } else {
      ++r.failed;
      ++progress_.failed;
      r.failed_ids.push_back(rec.id);
    }
  }

  void report_progress(Clock::time_point t0, std::size_t running) {
    if (!options_.progress) return;
    progress_.elapsed_s = seconds_since(t0);
    progress_.running = static_cast<unsigned>(running);
    const std::uint64_t finished = progress_.done + progress_.failed;
    progress_.eta_s = finished ? progress_.elapsed_s / static_cast<double>(finished) * static_cast<double>(progress_.total - finished) : -1.0;
    options_.progress(progress_);
  }

  const SweepDir& sweep_;
  const RunOptions& options_;
  std::string host_;
  std::vector<std::uint64_t> pending_;
  std::vector<SweepTask> block_;
  std::uint64_t block_first_ = 0;
  RunReport report_;
  RunProgress progress_;
  Clock::time_point stop_time_{};
};

}  // namespace

std::string text_tail(const std::string& text, std::size_t max_lines, std::size_t max_bytes) {
  std::size_t end = text.size();
  while (end > 0 && (text[end - 1] == '\n' || text[end - 1] == '\r')) --end;
  std::size_t start = end, lines = 0;
  while (start > 0 && end - start < max_bytes) {
    if (text[start - 1] == '\n' && ++lines >= max_lines) break;
    --start;
  }
  return text.substr(start, end - start);
}

RunReport run_sweep(const SweepDir& sweep, const RunOptions& options) {
  if (options.executable.empty()) throw Error("no starnav program to run the tasks with");
  // A whole-sweep run on this machine holds the folder, so a second one cannot run the same tasks
  // beside it; the array jobs of a Slurm run share it, each with its own group.
  std::optional<OutputFolder> claim;
  if (!options.group) claim.emplace(sweep.dir, "DIR");
  Runner runner(sweep, options);
  return runner.run();
}

}  // namespace starnav::sweep
