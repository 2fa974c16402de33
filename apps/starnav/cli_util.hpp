#pragma once
// Small helpers shared by the CLI commands: argument parsing that names the flag in errors,
// output-file rules (conventions.md: never overwrite without --force).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/io/map_file.hpp"

namespace starnav::cli {

// Parses one finite number (the whole of `s`); false otherwise.
bool parse_double(const std::string& s, double& out);

// Parses `count` comma-separated finite numbers; throws Error naming `flag`:
// "expected <what>, got '...'".
std::vector<double> parse_number_list(const std::string& text, const std::string& flag, std::size_t count,
                                      const std::string& what);

// Parses "X,Y" (two finite numbers); throws Error naming `flag` otherwise.
Vec2 parse_xy(const std::string& text, const std::string& flag);

// A query endpoint "X,Y" as a cell: with `in_cells` X,Y must be integers (cell indices);
// otherwise a point in the map frame, and a point outside the map gives a cell outside it (a
// result, not an error).
Cell parse_endpoint_cell(const std::string& text, const std::string& flag, bool in_cells, const GridGeometry& g);

// The library Error `e` again, its field renamed to the flag the user typed: "a_b" -> "--a-b",
// or as `renamed` says.
[[noreturn]] void rethrow_with_flag(const Error& e, const std::vector<std::pair<std::string, std::string>>& renamed = {});

// `--set KEY=VALUE` options as settings of a declared parameter table (each setting's field is
// "--set KEY", so errors name the option); Error (field "--set") for text without '='.
std::vector<ParamSetting> parse_set_options(const std::vector<std::string>& sets);

// Parses a non-negative integer written in decimal digits only (no sign); throws Error naming
// `flag`: "expected <what>, got '...'" or out of range above 2^64 - 1.
std::uint64_t parse_unsigned(const std::string& text, const std::string& flag, const std::string& what);

// Every numeric option of `app` and its subcommands read as core/number_text.hpp says (decimal
// only; no sign for unsigned ones), and no option takes an empty string: call once the commands
// are registered.
void apply_number_rules(CLI::App& app);

// A library's warning (LogReadOptions::warn, ...) on stderr as `starnav: warning: TEXT`, held until release_warnings() (the command's long work starts or it
// ends without an error; main releases them), so a refused input is one error line.
void print_warning(const std::string& text);
void release_warnings();

// The one warning for a server told to listen beyond this machine (--bind other than loopback).
void warn_if_served_beyond_loopback(const std::string& bind);

// This program's own path (/proc/self/exe; "" when unknown): files installed beside it are found from it.
std::string executable_path();

// Throws Error when `path` exists and `force` is false, or its folder does not exist.
void check_output_path(const std::string& path, bool force, const std::string& flag);
// A file a command reads or writes, named for errors by `what`: the flag or positional ("--svg",
// "LOG"), or for a companion the flag and the file it goes with.
struct CommandFile {
  std::string path;
  std::string what;
  bool output = true;
};
// The files of a map written to `path` as `format` (the named one and its companions, as
// map_output_files), or read by `map` (LoadedMap::files), named after `flag`.
void add_map_files(std::vector<CommandFile>& files, const std::string& path, MapFormat format,
                   const std::optional<RosMapMetadata>& ros, const std::string& flag);
void add_map_files(std::vector<CommandFile>& files, const LoadedMap& map, const std::string& flag);
// Refuses two entries that are one file where one of them is an output (two outputs, or an output
// and an input or its companion): compared by device and inode where the files exist (links and
// hard links followed), else by their canonical paths. One Error naming the file and both; --force
// does not lift it (it would lose an output or replace an input).
void check_distinct_files(const std::vector<CommandFile>& files);

// Writes `text` to `path`; an Error naming the file and `flag` when it cannot.
void write_text_file(const std::string& path, const std::string& text, const std::string& flag);


// True for a .png picture, false for .svg; throws Error naming `flag` for anything else.
bool picture_is_png(const std::string& path, const std::string& flag);


// What a command wrote into its output folder, read off the folder itself so the "wrote" line can
// never leave a file out: the files new or changed since the listing was made (at the start of the
// command), those in subfolders counted per subfolder.
class OutputListing {
 public:
  explicit OutputListing(std::string dir);
  // "wrote DIR/{a.csv, b.json, clouds/ (12 files)}"; "wrote nothing in DIR" when nothing changed.
  std::string wrote_line() const;
  // The line on stdout, or on stderr when stdout carries a --json or --csv document (and then not
  // at all with --quiet).
  void print(bool stdout_is_a_document, bool quiet) const;

 private:
  std::string dir_;
  std::vector<std::pair<std::string, std::filesystem::file_time_type>> before_;  // relative path, time
};

// conventions.md: an existing non-empty folder is not written into without --force. Checked
// before any work; the returned claim creates and locks the folder (core/output_file.hpp) and
// must be held while the command writes into it.
OutputFolder check_out_dir(const std::string& dir, bool force);

// Progress of a long run on stderr: a live bar when stderr is a terminal, otherwise a line at
// every tenth of the work (readable in CI logs); nothing when quiet.
class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total, bool quiet);
  // `done` of the total finished; `what` names the current item.
  void update(std::size_t done, const std::string& what);
  void finish();
  // For work whose size is known only once it starts.
  void set_total(std::size_t total) { total_ = total; }

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool tty_;
  std::size_t next_line_ = 0;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace starnav::cli
