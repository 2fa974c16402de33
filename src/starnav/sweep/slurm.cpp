#include "starnav/sweep/slurm.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/sweep/process.hpp"
#include "starnav/sweep/task_record.hpp"
#include "starnav/sweep/task_runner.hpp"

namespace starnav::sweep {

namespace fs = std::filesystem;

namespace {

std::string trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

// A word for a bash script in single quotes.
std::string single_quoted(const std::string& s) {
  std::string q = "'";
  for (const char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

bool has_control(const std::string& s) {
  return std::any_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
}

// Slurm's time limit forms: MM, MM:SS, HH:MM:SS, and D-HH, D-HH:MM, D-HH:MM:SS.
bool valid_slurm_time(std::string_view t) {
  const auto digits = [](std::string_view s) {
    return !s.empty() && s.size() <= 6 && std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  };
  // Up to three numbers separated by colons.
  const auto clock = [&](std::string_view s) {
    int parts = 0;
    for (std::size_t start = 0;; ++parts) {
      const std::size_t colon = s.find(':', start);
      if (!digits(s.substr(start, colon == std::string_view::npos ? std::string_view::npos : colon - start))) return false;
      if (colon == std::string_view::npos) return parts <= 2;
      start = colon + 1;
    }
  };
  const std::size_t dash = t.find('-');
  if (dash == std::string_view::npos) return clock(t);
  return digits(t.substr(0, dash)) && clock(t.substr(dash + 1));
}

}  // namespace

std::optional<std::uint64_t> parse_max_array_size(std::string_view text) {
  for (std::size_t start = 0; start < text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    const std::size_t eq = line.find('=');
    if (eq == std::string_view::npos || trim(line.substr(0, eq)) != "MaxArraySize") continue;
    const std::optional<std::uint64_t> v = parse_unsigned_text(trim(line.substr(eq + 1)));
    if (v && *v >= 1) return v;
    return std::nullopt;
  }
  return std::nullopt;
}

ArrayLimit query_max_array_size() {
  ArrayLimit limit;
  const std::optional<CapturedRun> r = run_and_capture({"scontrol", "show", "config"});
  if (!r) {
    limit.source = "Slurm's default (scontrol not found)";
  } else if (r->exit_code != 0) {
    const std::string err = trim(r->err);
    limit.source = "Slurm's default (scontrol show config failed: " + one_line(err.substr(0, err.find('\n')), 100) + ")";
  } else if (const std::optional<std::uint64_t> v = parse_max_array_size(r->out)) {
    limit.max_array_size = *v;
    limit.source = "scontrol show config";
  } else {
    limit.source = "Slurm's default (scontrol show config does not give MaxArraySize)";
  }
  return limit;
}

std::uint64_t slurm_group_size(std::uint64_t tasks, std::uint64_t max_array_size, std::uint64_t tasks_per_job) {
  if (max_array_size == 0) throw Error("must be at least 1", {}, 0, "--max-array-size");
  const std::uint64_t needed = tasks == 0 ? 1 : (tasks + max_array_size - 1) / max_array_size;
  return std::max<std::uint64_t>({1, tasks_per_job, needed});
}

std::string slurm_array_spec(const std::vector<std::uint64_t>& indices, std::uint64_t max_running) {
  std::string out;
  for (std::size_t i = 0; i < indices.size();) {
    std::size_t j = i;
    while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
    if (!out.empty()) out += ',';
    out += std::to_string(indices[i]);
    if (j > i) out.append("-").append(std::to_string(indices[j]));
    i = j + 1;
  }
  if (max_running > 0) out.append("%").append(std::to_string(max_running));
  return out;
}

SlurmScript write_slurm_script(const SweepDir& sweep, const SlurmOptions& o) {
  if (has_control(o.partition) || (!o.partition.empty() && o.partition.find_first_not_of(
                                                               "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.,-") != std::string::npos))
    throw Error("expected a partition name (letters, digits, _ . - and commas), got '" + printable(o.partition, 60) + "'", {}, 0, "--partition");
  if (!o.time.empty() && !valid_slurm_time(o.time))
    throw Error("expected a Slurm time limit (MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS), got '" + printable(o.time, 40) + "'", {}, 0,
                "--time");
  for (const std::string& s : o.sbatch) {
    const std::string name = s.substr(0, s.find('='));
    if (name.empty() || has_control(s) || !std::isalpha(static_cast<unsigned char>(name[0])) ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyz-") != std::string::npos)
      throw Error("expected an sbatch option NAME or NAME=VALUE without the dashes (mem=4G), got '" + printable(s, 60) + "'", {}, 0, "--sbatch");
    for (const char* own : {"array", "output", "error", "job-name", "partition", "time", "cpus-per-task", "wrap"})
      if (name == own) throw Error(name + " is written by starnav sweep slurm" + (name == "partition" || name == "time" || name == "cpus-per-task" ? " (use --" + name + ")" : ""), {}, 0, "--sbatch");
  }
  if (o.starnav.empty() || !fs::path(o.starnav).is_absolute()) throw Error("expected the absolute path of starnav", {}, 0, "--starnav");

  SlurmScript script;
  script.tasks = sweep.tasks;
  if (o.max_array_size > 0) {
    script.limit.max_array_size = o.max_array_size;
    script.limit.source = "--max-array-size";
  } else {
    script.limit = query_max_array_size();
  }
  script.group_size = slurm_group_size(sweep.tasks, script.limit.max_array_size, o.tasks_per_job);
  script.groups = (sweep.tasks + script.group_size - 1) / script.group_size;

  // The groups that still have work.
  std::vector<bool> busy(static_cast<std::size_t>(script.groups), false);
  std::uint64_t index = 0;
  for_each_task(sweep, [&](const SweepTask& t) {
    bool done = false;
    try {
      if (const std::optional<TaskRecord> r = read_record(sweep.result_path(t.id)))
        done = r->status == TaskStatus::Ok || !o.retry_failed;
    } catch (const Error&) {
      done = false;  // an unreadable record: run again
    }
    if (!done) {
      ++script.pending;
      busy[static_cast<std::size_t>(index / script.group_size)] = true;
    }
    ++index;
  });
  for (std::uint64_t g = 0; g < script.groups; ++g)
    if (busy[static_cast<std::size_t>(g)]) script.array.push_back(g);
  if (script.array.empty()) return script;
  script.array_spec = slurm_array_spec(script.array, o.max_running);

  const std::string dir = fs::absolute(sweep.dir).lexically_normal().string();
  const std::string slurm_dir = dir + "/slurm";
  std::error_code ec;
  fs::create_directories(slurm_dir, ec);
  if (ec) throw Error("cannot create the folder: " + ec.message(), slurm_dir);
  std::string& s = script.text;
  s += "#!/bin/bash\n";
  s += "# starnav sweep " + sweep.spec.name + ": " + std::to_string(script.pending) + " of " + std::to_string(script.tasks) +
       " tasks to run, in array jobs of up to " + std::to_string(script.group_size) + " tasks (" + std::to_string(script.array.size()) +
       " array jobs).\n";
  s += "# MaxArraySize " + std::to_string(script.limit.max_array_size) + " (" + script.limit.source + "): array indices 0.." +
       std::to_string(script.groups - 1) + ".\n";
  s += "# Written by starnav sweep slurm; submit with sbatch, then merge with: starnav sweep merge " + single_quoted(dir) + "\n";
  s += "#SBATCH --job-name=starnav-" + sweep.spec.name + "\n";
  s += "#SBATCH --array=" + script.array_spec + "\n";
  s += "#SBATCH --output=" + slurm_dir + "/%A_%a.log\n";
  if (!o.partition.empty()) s += "#SBATCH --partition=" + o.partition + "\n";
  if (!o.time.empty()) s += "#SBATCH --time=" + o.time + "\n";
  if (o.cpus_per_task > 0) s += "#SBATCH --cpus-per-task=" + std::to_string(o.cpus_per_task) + "\n";
  for (const std::string& opt : o.sbatch) s += "#SBATCH --" + opt + "\n";
  s += "set -euo pipefail\n";
  s += "exec " + single_quoted(o.starnav) + " sweep run " + single_quoted(dir) +
       " --group \"$SLURM_ARRAY_TASK_ID\" --group-size " + std::to_string(script.group_size) +
       " --jobs \"${SLURM_CPUS_PER_TASK:-1}\" --quiet" + (o.retry_failed ? " --retry-failed" : "") + "\n";
  script.path = slurm_dir + "/sweep.sbatch";
  write_file_atomically(script.path, s);
  fs::permissions(script.path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add, ec);
  return script;
}

std::string submit_slurm_script(const SweepDir& sweep, const SlurmScript& script) {
  const std::optional<CapturedRun> r = run_and_capture({"sbatch", "--parsable", script.path});
  if (!r) throw Error("sbatch not found: is this a Slurm cluster's login node? Submit the script there with sbatch", script.path);
  if (r->exit_code != 0)
    throw Error("sbatch failed (exit " + std::to_string(r->exit_code) + "): " + one_line(text_tail(r->err, 3, 400), 400), script.path);
  const std::string out = trim(r->out);
  const std::string id = out.substr(0, out.find(';'));
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    throw Error("sbatch printed no job id ('" + printable(out, 60) + "')", script.path);
  // A log of what was submitted, for the user (squeue -j, scancel).
  const std::string log = sweep.dir + "/slurm/jobs.txt";
  std::string previous;
  std::error_code ec;
  if (fs::exists(log, ec)) previous = read_input_file(log, std::uint64_t{1} << 24);
  write_file_atomically(log, previous + id + " array=" + script.array_spec + " tasks=" + std::to_string(script.pending) + "\n");
  return id;
}

}  // namespace starnav::sweep
