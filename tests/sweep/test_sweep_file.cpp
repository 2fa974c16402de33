// The sweep file: axes and their expansion against hand-counted cases, placeholders, and every bad
// input as one error naming the file, the line and the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/sweep/manifest.hpp"
#include "starnav/sweep/sweep_file.hpp"
#include "support/test_support.hpp"

namespace starnav::sweep {
namespace {

using test::error_of;

SweepSpec parse(const std::string& yaml) { return parse_sweep_file(yaml, "s.yaml"); }

std::vector<std::string> values_of(const SweepAxis& a) {
  std::vector<std::string> v;
  for (std::uint64_t i = 0; i < a.size(); ++i) v.push_back(a.value(i));
  return v;
}

TEST(SweepFile, ProductOfThreeAxesHandCounted) {
  // 5 seeds x 2 planners x 5 look-ahead values = 50 tasks, the first axis slowest.
  const SweepSpec s = parse(
      "command: [sim, e.yaml, --seed, '{seed}', --planner, '{planner}']\n"
      "axes:\n"
      "  seed: {from: 0, to: 4}\n"
      "  planner: [astar, dstar_lite]\n"
      "  navigation.follower.look_ahead_m: {from: 0.2, to: 1.0, step: 0.2}\n");
  ASSERT_EQ(s.task_count(), 50u);
  EXPECT_EQ(values_of(s.axes[2]), (std::vector<std::string>{"0.2", "0.4", "0.6", "0.8", "1"}));
  const auto values = [&](std::uint64_t i) { return make_task(s, i).values; };
  EXPECT_EQ(values(0), (std::vector<std::string>{"0", "astar", "0.2"}));
  EXPECT_EQ(values(1), (std::vector<std::string>{"0", "astar", "0.4"}));
  EXPECT_EQ(values(5), (std::vector<std::string>{"0", "dstar_lite", "0.2"}));
  EXPECT_EQ(values(10), (std::vector<std::string>{"1", "astar", "0.2"}));
  EXPECT_EQ(values(49), (std::vector<std::string>{"4", "dstar_lite", "1"}));
  // The dotted axis is not a placeholder of the command: it becomes --set KEY=VALUE.
  EXPECT_EQ(make_task(s, 7).argv, (std::vector<std::string>{"starnav", "sim", "e.yaml", "--seed", "0", "--planner", "dstar_lite",
                                                            "--set", "navigation.follower.look_ahead_m=0.6"}));
  EXPECT_EQ(s.axis_columns(), (std::vector<std::string>{"seed", "planner", "navigation.follower.look_ahead_m"}));
}

TEST(SweepFile, RangesAreExactDecimals) {
  const auto range = [&](const std::string& r) { return values_of(parse("command: [plan, '{a}']\naxes:\n  a: " + r + "\n").axes[0]); };
  EXPECT_EQ(range("{from: 0, count: 3}"), (std::vector<std::string>{"0", "1", "2"}));
  EXPECT_EQ(range("{from: -1, to: 1, step: 0.5}"), (std::vector<std::string>{"-1", "-0.5", "0", "0.5", "1"}));
  // The last value is the last step at or below `to`.
  EXPECT_EQ(range("{from: 0.1, to: 0.35, step: 0.1}"), (std::vector<std::string>{"0.1", "0.2", "0.3"}));
  EXPECT_EQ(range("{from: 1e-3, to: 3e-3, step: 1e-3}"), (std::vector<std::string>{"0.001", "0.002", "0.003"}));
  EXPECT_EQ(range("{from: 5, to: 5}"), (std::vector<std::string>{"5"}));
  EXPECT_EQ(range("{from: 10, to: 100, step: 45}"), (std::vector<std::string>{"10", "55", "100"}));
  EXPECT_EQ(range("{from: 2.50, count: 2, step: 0.25}"), (std::vector<std::string>{"2.5", "2.75"}));
  // 0.1 + 0.2 in binary is 0.30000000000000004; a range never shows that.
  EXPECT_EQ(range("{from: 0.1, count: 3, step: 0.1}").back(), "0.3");
  // The widest ranges the limits allow, end to end.
  EXPECT_EQ(range("{from: -4611686018427387903, count: 3, step: 4611686018427387903}"),
            (std::vector<std::string>{"-4611686018427387903", "0", "4611686018427387903"}));
  EXPECT_EQ(error_of([&] { range("{from: -4611686018427387903, count: 4, step: 4611686018427387903}"); }),
            "s.yaml:3: axes.a: numbers too large for a range");
  EXPECT_EQ(error_of([&] { range("{from: 0, count: 2, step: 4611686018427387905}"); }),
            "s.yaml:3: axes.a.step: expected a decimal number below 2^62 with at most 12 decimals, got '4611686018427387905'");
  // A million seeds cost nothing to parse: values are computed when asked for.
  const SweepSpec big = parse("command: [sim, x.yaml, --seed, '{seed}']\naxes:\n  seed: {from: 0, count: 1000000}\n");
  EXPECT_EQ(big.task_count(), 1000000u);
  EXPECT_EQ(big.axes[0].value(999999), "999999");
}

TEST(SweepFile, ZippedAxisAndPlaceholders) {
  const SweepSpec s = parse(
      "command: [plan, --start, '{query.start}', --goal, '{query.goal}', --out, '{out}/path.csv', '{{literal}}']\n"
      "axes:\n"
      "  query:\n"
      "    - {start: '1,1', goal: '5,5'}\n"
      "    - {start: '2,3', goal: '7,1'}\n"
      "  map.name: [a, b, c]\n");
  EXPECT_EQ(s.task_count(), 6u);
  EXPECT_EQ(s.axis_columns(), (std::vector<std::string>{"query.start", "query.goal", "map.name"}));
  const SweepTask t = make_task(s, 4);  // query 1, map.name b
  EXPECT_EQ(t.values, (std::vector<std::string>{"2,3", "7,1", "b"}));
  // In the manifest {out} stays for the runner, literal braces are doubled.
  EXPECT_EQ(t.argv, (std::vector<std::string>{"starnav", "plan", "--start", "2,3", "--goal", "7,1", "--out", "{out}/path.csv",
                                              "{{literal}}", "--set", "map.name=b"}));
  EXPECT_EQ(command_for_run(t.argv, "/w/o"), (std::vector<std::string>{"starnav", "plan", "--start", "2,3", "--goal", "7,1", "--out",
                                                                       "/w/o/path.csv", "{literal}", "--set", "map.name=b"}));
}

TEST(SweepFile, AxisValuesWithBracesRoundTrip) {
  const SweepSpec s = parse("command: [plan, 'x{v}y']\naxes:\n  v: ['{out}', '}}', 'a{b']\n");
  const std::vector<std::string> want{"x{out}y", "x}}y", "xa{by"};
  for (std::uint64_t i = 0; i < 3; ++i) EXPECT_EQ(command_for_run(make_task(s, i).argv, "/o")[2], want[i]);
}

TEST(SweepFile, IdsDependOnTheCommandOnly) {
  // Two files that produce the same command give the same id; another value another id.
  const SweepSpec a = parse("command: [plan, --seed, '{s}']\naxes:\n  s: [1, 2]\n");
  const SweepSpec b = parse("name: other\ncommand: [plan, --seed, '{seed}']\naxes:\n  seed: {from: 2, count: 1}\n");
  EXPECT_EQ(make_task(a, 1).id, make_task(b, 0).id);
  EXPECT_NE(make_task(a, 0).id, make_task(a, 1).id);
  // The result file is part of what a task is.
  const SweepSpec c = parse("command: [plan, --seed, '{s}']\nresult: out.json\naxes:\n  s: [1, 2]\n");
  EXPECT_NE(make_task(a, 0).id, make_task(c, 0).id);
  EXPECT_EQ(make_task(a, 0).id.size(), 16u);
}

TEST(SweepFile, MetricsSummaryAndPlots) {
  const SweepSpec s = parse(
      "command: [plan, '{w}', '{p}']\n"
      "axes: {w: {from: 1, to: 3}, p: [a, b]}\n"
      "metrics:\n"
      "  cost: /cost\n"
      "  t: {pointer: /timing/ms, timing: true}\n"
      "  ttg: {pointer: /time_to_goal_s, when: /success}\n"
      "summary: {group_by: [p], success: cost, baseline: b}\n"
      "plots: [{metric: cost, x: w, series: p, error: sd}, {metric: wall_s, x: w}]\n");
  ASSERT_EQ(s.metrics.size(), 3u);
  EXPECT_EQ(s.metrics[1].pointer, "/timing/ms");
  EXPECT_TRUE(s.metrics[1].timing);
  EXPECT_EQ(s.metrics[2].when, "/success");
  EXPECT_EQ(s.summary.group_by, (std::vector<std::string>{"p"}));
  EXPECT_EQ(s.plots[0].file_name(), "cost-vs-w-by-p.svg");
  EXPECT_EQ(s.plots[1].error, ErrorBars::Iqr);
  check_axis_values(s);
  EXPECT_EQ(group_label(s, {"2", "b"}), "b");
}

struct BadCase {
  std::string yaml;
  std::string error;  // the whole of what(), or its start when it ends in "..."
};

TEST(SweepFile, BadInputIsOneErrorNamingFileLineAndKey) {
  const std::string cmd = "command: [plan, '{s}']\n";
  const std::vector<BadCase> cases = {
      {"", "s.yaml: expected a mapping of keys (command, result, axes, metrics, ...)"},
      {cmd + "axes: {s: [1]}\nbogus: 2\n", "s.yaml:3: bogus: unknown key (known: name, command, result, result_exit_codes, timeout_s, keep_outputs, axes, metrics, summary, plots)"},
      {"command: [plan]\n", "s.yaml: axes: missing: the axes of the sweep (seeds, parameters, maps, ...)"},
      {"axes: {s: [1]}\n", "s.yaml: command: missing: the starnav command each task runs, as a list [SUBCOMMAND, ARG, ...]"},
      {cmd + "axes:\n  s: {from: 3, to: 1}\n", "s.yaml:3: axes.s.to: must be >= from"},
      {cmd + "axes:\n  s: {from: 0, to: 3, count: 4}\n", "s.yaml:3: axes.s: give exactly one of to and count"},
      {cmd + "axes:\n  s: {from: 0, count: 3, step: 0}\n", "s.yaml:3: axes.s.step: must be > 0"},
      {cmd + "axes:\n  s: {from: 0, count: 3, stepp: 1}\n", "s.yaml:3: axes.s.stepp: unknown key (known: from, to, count, step)"},
      {cmd + "axes:\n  s: {from: x, count: 3}\n", "s.yaml:3: axes.s.from: expected a decimal number below 2^62 with at most 12 decimals, got 'x'"},
      {cmd + "axes:\n  s: {from: 0, count: -1}\n", "s.yaml:3: axes.s.count: expected a whole number >= 1, got '-1'"},
      {cmd + "axes:\n  s: [1, 2, 1]\n", "s.yaml:3: axes.s[2]: the same value twice (two tasks would be the same)"},
      {cmd + "axes:\n  s: []\n", "s.yaml:3: axes.s: an empty list: give at least one value"},
      {cmd + "axes:\n  s: {glob: ''}\n", "s.yaml:3: axes.s.glob: an empty pattern"},
      {cmd + "axes:\n  s: [1]\n  t: [2]\n", "s.yaml:4: axes.t: the command never uses this axis: name it as {t} in an argument (or give a dotted parameter key, passed as --set KEY=VALUE)"},
      {"command: [plan, '{x}']\naxes: {s: [1]}\n", "s.yaml:1: command[1]: {x} is not an axis (axes: s; and {out})"},
      {"command: [plan, '{s']\naxes: {s: [1]}\n", "s.yaml:1: command[1]: an unclosed '{' in '{s' (write {{ for a literal brace)"},
      {"command: [plan, 's}']\naxes: {s: [1]}\n", "s.yaml:1: command[1]: a lone '}' in 's}' (write }} for a literal brace)"},
      {"command: [starnav, plan, '{s}']\naxes: {s: [1]}\n", "s.yaml:1: command[0]: give the subcommand and its arguments without 'starnav' ([plan, --map, ...])"},
      {"command: ['{s}']\naxes: {s: [1]}\n", "s.yaml:1: command[0]: expected the starnav subcommand (plan, sim, bench, ...), without placeholders"},
      {"command: [plan, '{q}']\naxes:\n  q: [{a: 1}]\n", "s.yaml:1: command[1]: {q} names a zipped axis: name one of its fields ({q.a}, ...)"},
      {"command: [plan, '{q.a}']\naxes:\n  q: [{a: 1}, {b: 2}]\n", "s.yaml:3: axes.q[1].a: missing (every entry has the fields of the first)"},
      {cmd + "axes: {s: [1]}\nresult: ../x.json\n", "s.yaml:3: result: must stay inside the task's output folder (no '..'), got '../x.json'"},
      {cmd + "axes: {s: [1]}\nresult: /abs.json\n", "s.yaml:3: result: expected a file in the task's output folder, relative to {out}, got '/abs.json'"},
      {cmd + "axes: {s: [1]}\nresult_exit_codes: [0, 256]\n", "s.yaml:3: result_exit_codes: expected an exit code 0..255, got '256'"},
      {cmd + "axes: {s: [1]}\ntimeout_s: -1\n", "s.yaml:3: timeout_s: expected seconds >= 0 (0: no limit), got '-1'"},
      {cmd + "axes: {s: [1]}\nmetrics: {cost: cost}\n", "s.yaml:3: metrics.cost: expected a JSON pointer (RFC 6901: /key/0/..., ~0 for ~ and ~1 for /), got 'cost'"},
      {cmd + "axes: {s: [1]}\nmetrics: {status: /x}\n", "s.yaml:3: metrics.status: is a column of the table; choose another name"},
      {cmd + "axes: {s: [1]}\nmetrics: {c: {pointer: /c, when: x}}\n", "s.yaml:3: metrics.c.when: expected a JSON pointer to a true/false value in the result, got 'x'"},
      {cmd + "axes: {s: [1]}\nsummary: {group_by: [t]}\n", "s.yaml:3: summary.group_by: 't' is not an axis"},
      {cmd + "axes: {s: [1]}\nsummary: {baseline: a}\n", "s.yaml:3: summary.baseline: a baseline needs groups (summary.group_by)"},
      {cmd + "axes: {s: [1]}\nsummary: {success: found}\n", "s.yaml:3: summary.success: 'found' is not one of the metrics"},
      {cmd + "axes: {s: [1]}\nplots: [{metric: wall_s}]\n", "s.yaml:3: plots[0].x: missing: the axis on the x axis"},
      {cmd + "axes: {s: [1]}\nplots: [{metric: cost, x: s}]\n", "s.yaml:3: plots[0].metric: 'cost' is not one of the metrics (nor wall_s, cpu_s)"},
      {cmd + "axes: {s: [1]}\nplots: [{metric: wall_s, x: s, error: ci}]\n", "s.yaml:3: plots[0].error: expected iqr (median and quartiles), sd (mean and standard deviation) or none, got 'ci'"},
      {cmd + "axes:\n  s: {from: 0, count: 100000}\n  t: {from: 0, count: 10000}\n", "s.yaml:2: axes: the axes make more than 100000000 tasks"},
      {cmd + "axes: {s: [1], s: [2]}\n", "s.yaml:2: axes.s: duplicate key"},
      {cmd + "axes: {s: [1]\n", "s.yaml:3: YAML syntax error: ..."},
      {cmd + "axes: {id: [1]}\n", "s.yaml:2: axes.id: is a column of the table; choose another name"},
      {cmd + "name: 'a b'\naxes: {s: [1]}\n", "s.yaml:2: name: expected up to 100 letters, digits, '-', '_' or '.', got 'a b'"},
  };
  for (const BadCase& c : cases) {
    const std::string what = error_of([&] { parse(c.yaml); });
    if (c.error.size() > 3 && c.error.compare(c.error.size() - 3, 3, "...") == 0)
      EXPECT_EQ(what.substr(0, c.error.size() - 3), c.error.substr(0, c.error.size() - 3)) << c.yaml;
    else
      EXPECT_EQ(what, c.error) << c.yaml;
  }
}

TEST(SweepFile, GlobsSortedRelativeToTheSweepFile) {
  test::ScratchDir dir;
  std::filesystem::create_directories(dir.path() / "maps" / "sub");
  for (const char* f : {"maps/b.map", "maps/A.map", "maps/a.map", "maps/sub/c.map", "maps/notes.txt"}) test::write_text(dir.file(f), "x");
  test::write_text(dir.file("g.yaml"), "command: [plan, --map, '{map}']\naxes:\n  map: {glob: ['maps/*.map', 'maps/sub/*.map']}\n");
  const SweepSpec s = read_sweep_file(dir.file("g.yaml"));
  // Byte order, not the locale's: upper case first.
  EXPECT_EQ(values_of(s.axes[0]), (std::vector<std::string>{"maps/A.map", "maps/a.map", "maps/b.map", "maps/sub/c.map"}));
  test::write_text(dir.file("none.yaml"), "command: [plan, --map, '{map}']\naxes:\n  map: {glob: 'nothing/*.map'}\n");
  EXPECT_EQ(error_of([&] { read_sweep_file(dir.file("none.yaml")); }),
            dir.file("none.yaml") + ":3: axes.map.glob: the pattern 'nothing/*.map' matches no file (relative to " + dir.path().string() + ")");
  test::write_text(dir.file("twice.yaml"), "command: [plan, --map, '{map}']\naxes:\n  map: {glob: ['maps/a*', 'maps/*.map']}\n");
  EXPECT_EQ(error_of([&] { read_sweep_file(dir.file("twice.yaml")); }), dir.file("twice.yaml") + ":3: axes.map.glob: two patterns match 'maps/a.map'");
}

TEST(SweepFile, PlotAxesMustBeNumbersAndBaselineAGroup) {
  const SweepSpec s = parse("command: [plan, '{p}']\naxes: {p: [astar, jps]}\nplots: [{metric: wall_s, x: p}]\n");
  EXPECT_EQ(error_of([&] { check_axis_values(s); }), "s.yaml:3: plots[0].x: axis p has a value that is not a number ('astar'): nothing to plot against");
  const SweepSpec b = parse("command: [plan, '{p}']\naxes: {p: [astar, jps]}\nsummary: {group_by: [p], baseline: dijkstra}\n");
  EXPECT_EQ(error_of([&] { check_axis_values(b); }), "s.yaml:3: summary.baseline: no group is called 'dijkstra' (groups: astar; jps)");
}

}  // namespace
}  // namespace starnav::sweep
