#pragma once
// The sweep file (docs/sweeps.md): one starnav command run over the product of its axes (seeds as
// a range, parameters by their dotted keys as lists or ranges, maps or scenarios as lists or
// globs), the file of each run that holds its JSON result, the metrics to collect from it (JSON
// pointers) and how to summarise and plot them.
//
//   name: planners
//   command: [plan, --map, "{map}", --start, "{query.start}", --goal, "{query.goal}", --planner, "{planner}", --json]
//   result: stdout
//   axes:
//     map: {glob: "maps/*.map"}
//     planner: [astar, jps]
//     query: [{start: "1,1", goal: "30,20"}, {start: "5,2", goal: "40,8"}]
//   metrics: {cost: /cost, expanded: /expanded, time_ms: {pointer: /time_ms, timing: true}}
//   summary: {group_by: [planner], success: found}
//   plots: [{metric: expanded, x: ..., series: planner, error: iqr}]
//
// Parsing never touches the file system; globs are resolved by resolve_globs() against the folder
// of the sweep file. Every error is an Error naming the file, the line and the key.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace starnav::sweep {

// More tasks than this in one sweep is refused (a typo in a range, not an experiment).
inline constexpr std::uint64_t kMaxSweepTasks = 100'000'000;

// A command argument with placeholders: "{axis}", "{axis.field}" and "{out}" (the task's output
// folder, known only when it runs); "{{" and "}}" are literal braces.
struct TemplatePart {
  enum class Kind { Text, Axis, Out } kind = Kind::Text;
  std::string text;       // Kind::Text
  std::size_t axis = 0;   // Kind::Axis
  std::size_t field = 0;  // Kind::Axis: the field of a zipped axis (0 for a plain one)
};
struct TemplateArg {
  std::vector<TemplatePart> parts;
  int line = 0;
};

// One axis of the sweep. Its values are text, passed to the command as written.
struct SweepAxis {
  enum class Kind { List, Range, Glob };
  std::string name;
  int line = 0;
  Kind kind = Kind::List;
  // A zipped axis (a list of mappings with the same keys) has named fields; a plain one has none
  // and one value per entry.
  std::vector<std::string> fields;
  // List (and Glob once resolved): entries x max(1, fields) texts, row by row.
  std::vector<std::string> texts;
  // Range: from + i * step for i < count, in units of 10^-decimals (exact, no rounding drift).
  std::int64_t range_from = 0, range_step = 1;
  std::uint64_t range_count = 0;
  int range_decimals = 0;
  // Glob: the patterns, relative to the sweep file's folder unless absolute.
  std::vector<std::string> patterns;
  // A dotted axis name is a parameter key: each task gets `--set NAME=VALUE` unless the command
  // names the axis as a placeholder itself.
  bool as_set_option = false;

  std::size_t width() const { return fields.empty() ? 1 : fields.size(); }
  std::uint64_t size() const;
  // The text of value `index`, field `field`.
  std::string value(std::uint64_t index, std::size_t field = 0) const;
  // The table columns of this axis: its name, or NAME.FIELD for each field of a zipped axis.
  std::vector<std::string> columns() const;
  // Keeps the first `count` values (count >= 1).
  void take(std::uint64_t count);
};

struct SweepMetric {
  std::string name;
  std::string pointer;  // JSON pointer into the result ("" is the whole document)
  // A JSON pointer to a condition: the metric applies only where it is true (or non-zero), e.g.
  // time to goal only of the runs that arrived; "" always.
  std::string when;
  bool timing = false;  // a wall-clock figure: differs from run to run, left out when runs are compared
  int line = 0;
};

enum class ErrorBars { Iqr, Sd, None };

struct SweepPlot {
  std::string metric;  // a metric, or wall_s / cpu_s
  std::string x;       // a plain axis with numeric values
  std::string series;  // an axis, or "" for one series
  ErrorBars error = ErrorBars::Iqr;
  int line = 0;
  // plots/<metric>-vs-<x>[-by-<series>].svg
  std::string file_name() const;
};

struct SweepSummary {
  std::vector<std::string> group_by;  // axis names
  std::string success;                // a metric whose truth (non-zero) counts as success; "" = a completed task
  std::string baseline;               // a group's label, or "" for the first group
  int baseline_line = 0;
};

struct SweepSpec {
  std::string source;  // the file, for messages
  std::string name;
  std::vector<TemplateArg> command;  // the starnav subcommand and its arguments (no "starnav")
  std::string result = "stdout";     // "stdout" or a file in the task's output folder
  std::vector<int> result_exit_codes{0, 1};
  double timeout_s = 0.0;  // 0: none
  bool keep_outputs = false;
  std::vector<SweepAxis> axes;
  std::vector<SweepMetric> metrics;
  SweepSummary summary;
  std::vector<SweepPlot> plots;
  int command_line = 0, axes_line = 0;

  // The table columns of the axes, in axis order.
  std::vector<std::string> axis_columns() const;
  // Index of the axis called `name`, or nullopt.
  std::optional<std::size_t> axis_index(const std::string& name) const;
  // The product of the axis sizes; Error when it exceeds kMaxSweepTasks.
  std::uint64_t task_count() const;
};

// Parses the text of a sweep file. `default_name` is the sweep's name when the file gives none.
SweepSpec parse_sweep_file(std::string_view text, const std::string& source, const std::string& default_name = "sweep");

// Reads and parses `path` (name: the file's stem) and resolves its globs.
SweepSpec read_sweep_file(const std::string& path);

// Turns each glob axis into the sorted list of the paths its patterns match, relative to
// `base_dir` as written (absolute patterns give absolute paths). Error when a pattern matches
// nothing or two patterns match the same file.
void resolve_globs(SweepSpec& spec, const std::string& base_dir);

// Checks what needs the axes' values: plot x axes are numeric, the summary's baseline is a group.
void check_axis_values(const SweepSpec& spec);

// The summary group label of a task from its axis values (one text per axis column).
std::string group_label(const SweepSpec& spec, const std::vector<std::string>& column_values);

}  // namespace starnav::sweep
