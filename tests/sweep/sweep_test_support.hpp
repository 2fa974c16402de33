#pragma once
// Helpers of the sweep tests: sweep files in a scratch folder, maps for `starnav plan` tasks, and
// the merged table read back without its timing columns.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "starnav/sweep/manifest.hpp"
#include "starnav/sweep/task_runner.hpp"
#include "support/test_support.hpp"

namespace starnav::test {

// A MovingAI map of `width` x `height` free cells: a Dijkstra query corner to corner expands every
// cell, so its time grows with the size (tasks long enough to be caught running).
inline std::string write_open_map(const std::string& path, int width, int height) {
  std::string text = "type octile\nheight " + std::to_string(height) + "\nwidth " + std::to_string(width) + "\nmap\n";
  for (int y = 0; y < height; ++y) text += std::string(static_cast<std::size_t>(width), '.') + "\n";
  write_text(path, text);
  return path;
}

// Writes `yaml` as DIR/NAME and expands it into DIR/OUT; returns the opened sweep.
inline sweep::SweepDir expand_in(const ScratchDir& dir, const std::string& yaml, const std::string& out = "sweep",
                                 const sweep::ExpandOptions& options = {}, const std::string& name = "test_sweep.yaml") {
  write_text(dir.file(name), yaml);
  sweep::expand_sweep(dir.file(name), dir.file(out), options);
  return sweep::open_sweep_dir(dir.file(out));
}

inline sweep::RunOptions cli_run_options(unsigned jobs = 2) {
  sweep::RunOptions o;
  o.jobs = jobs;
  o.executable = STARNAV_CLI_PATH;
  return o;
}

// CSV rows split at commas outside quotes (the merged tables quote fields with commas).
inline std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_text(path));
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> row;
    std::string cell;
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (quoted) {
        if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
          cell += '"';
          ++i;
        } else if (c == '"') {
          quoted = false;
        } else {
          cell += c;
        }
      } else if (c == '"') {
        quoted = true;
      } else if (c == ',') {
        row.push_back(cell);
        cell.clear();
      } else {
        cell += c;
      }
    }
    row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

// The table without the columns named in `timing` (the header row first).
inline std::vector<std::vector<std::string>> without_columns(const std::vector<std::vector<std::string>>& rows,
                                                             const std::vector<std::string>& timing) {
  std::vector<std::vector<std::string>> out;
  if (rows.empty()) return out;
  std::vector<bool> keep;
  for (const std::string& c : rows[0]) keep.push_back(std::find(timing.begin(), timing.end(), c) == timing.end());
  for (const auto& r : rows) {
    std::vector<std::string> kept;
    for (std::size_t i = 0; i < r.size() && i < keep.size(); ++i)
      if (keep[i]) kept.push_back(r[i]);
    out.push_back(kept);
  }
  return out;
}

// Every regular file under `dir` (relative path -> bytes), for comparing merges byte for byte.
inline std::vector<std::pair<std::string, std::string>> files_under(const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out.emplace_back(std::filesystem::relative(e.path(), dir).string(), read_text(e.path().string()));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace starnav::test
