// Merging a sweep: the table, the per-group statistics against hand-computed values, the list of
// missing and failed tasks, plots with error bars, and the same bytes on every merge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/sweep/manifest.hpp"
#include "starnav/sweep/merge.hpp"
#include "starnav/sweep/task_record.hpp"
#include "starnav/sweep/task_runner.hpp"
#include "sweep/sweep_test_support.hpp"

namespace starnav::sweep {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::ScratchDir;

// Tasks run by /bin/sh: group a gives v = 1..4, group b ten times that; "even" is true for even
// v; value 4 of group b fails (exit 2) and value 3 of group b is never run.
const std::string kValues =
    "name: values\n"
    "command: ['-c', 'k=1; [ $1 = b ] && k=10; [ $1$2 = b4 ] && {{ echo broken >&2; exit 2; }}; "
    "printf ''{{\"v\": %d, \"even\": %s, \"t\": 0.5}}'' $(( $2 * k )) $( [ $(( $2 % 2 )) = 0 ] && echo true || echo false )', "
    "sh, '{g}', '{n}']\n"
    "axes:\n  g: [a, b]\n  n: {from: 1, to: 4}\n"
    "metrics:\n  v: /v\n  even: /even\n  v_even: {pointer: /v, when: /even}\n  t: {pointer: /t, timing: true}\n"
    "summary: {group_by: [g], success: even}\n"
    "plots: [{metric: v, x: n, series: g}]\n";

SweepDir run_values(const ScratchDir& dir) {
  const SweepDir s = test::expand_in(dir, kValues);
  RunOptions o;
  o.executable = "/bin/sh";
  o.jobs = 2;
  const std::vector<SweepTask> tasks = read_tasks(s, 0, 8);
  for (const SweepTask& t : tasks)
    if (t.values != std::vector<std::string>{"b", "3"}) o.only.push_back(t.id);
  run_sweep(s, o);
  return s;
}

TEST(SweepMerge, StatisticsPerGroupAgainstHandComputedValues) {
  ScratchDir dir;
  const SweepDir s = run_values(dir);
  const MergeReport r = merge_sweep(s, dir.file("merged"));
  EXPECT_EQ(r.tasks, 8u);
  EXPECT_EQ(r.ok, 6u);
  EXPECT_EQ(r.failed, 1u);
  EXPECT_EQ(r.missing, 1u);
  const json sum = json::parse(test::read_text(dir.file("merged/summary.json")));
  const json& a = sum.at("groups").at(0);
  const json& b = sum.at("groups").at(1);
  EXPECT_EQ(a.at("group"), "a");
  EXPECT_EQ(a.at("tasks"), 4);
  EXPECT_EQ(a.at("ok"), 4);
  EXPECT_EQ(a.at("successes"), 2);  // v = 2 and 4
  // v = 1, 2, 3, 4: quartiles by linear interpolation between order statistics (numpy's default).
  const json& av = a.at("metrics").at("v");
  EXPECT_EQ(av.at("n"), 4);
  EXPECT_DOUBLE_EQ(av.at("median").get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(av.at("q25").get<double>(), 1.75);
  EXPECT_DOUBLE_EQ(av.at("q75").get<double>(), 3.25);
  EXPECT_DOUBLE_EQ(av.at("mean").get<double>(), 2.5);
  EXPECT_NEAR(av.at("sd").get<double>(), std::sqrt(5.0 / 3.0), 1e-12);
  EXPECT_DOUBLE_EQ(av.at("min").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(av.at("max").get<double>(), 4.0);
  // Booleans count as 1 and 0; a `when` metric only where its condition holds.
  EXPECT_DOUBLE_EQ(a.at("metrics").at("even").at("mean").get<double>(), 0.5);
  EXPECT_EQ(a.at("metrics").at("v_even").at("n"), 2);
  EXPECT_DOUBLE_EQ(a.at("metrics").at("v_even").at("median").get<double>(), 3.0);
  // Group b: 10 and 20 only (30 missing, 40 failed).
  EXPECT_EQ(b.at("ok"), 2);
  EXPECT_EQ(b.at("failed"), 1);
  EXPECT_EQ(b.at("missing"), 1);
  EXPECT_DOUBLE_EQ(b.at("metrics").at("v").at("median").get<double>(), 15.0);
  EXPECT_DOUBLE_EQ(b.at("median_ratio_to_baseline").at("v").get<double>(), 15.0 / 2.5);
  EXPECT_EQ(sum.at("timing_metrics"), json({"t", "wall_s", "cpu_s"}));
  // The Markdown summary uses the experiment runner's table.
  const std::string md = test::read_text(dir.file("merged/summary.md"));
  EXPECT_NE(md.find("| v | 2.5 [1.75 .. 3.25] (4) | 15 [12.5 .. 17.5] (2) | 6 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| success | 2/4 | 1/4 |"), std::string::npos) << md;
}

TEST(SweepMerge, TableListsEveryTaskAndTheIncompleteOnesWithTheirRerun) {
  ScratchDir dir;
  const SweepDir s = run_values(dir);
  const MergeReport r = merge_sweep(s, dir.file("merged"));
  const std::vector<SweepTask> tasks = read_tasks(s, 0, 8);
  EXPECT_EQ(r.failed_ids, std::vector<std::string>{tasks[7].id});
  EXPECT_EQ(r.failed_reasons, std::vector<std::string>{"exit code 2"});
  EXPECT_EQ(r.missing_ids, std::vector<std::string>{tasks[6].id});
  EXPECT_EQ(r.rerun_command, "starnav sweep run " + s.dir + " --tasks " + tasks[7].id + "," + tasks[6].id);
  const auto rows = test::read_csv(dir.file("merged/table.csv"));
  ASSERT_EQ(rows.size(), 9u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"id", "g", "n", "status", "exit_code", "reason", "v", "even", "v_even", "t", "wall_s", "cpu_s"}));
  EXPECT_EQ(std::vector<std::string>(rows[2].begin(), rows[2].begin() + 10),
            (std::vector<std::string>{tasks[1].id, "a", "2", "ok", "0", "", "2", "true", "2", "0.5"}));
  EXPECT_EQ(std::vector<std::string>(rows[7].begin(), rows[7].end()),
            (std::vector<std::string>{tasks[6].id, "b", "3", "missing", "", "", "", "", "", "", "", ""}));
  EXPECT_EQ(std::vector<std::string>(rows[8].begin(), rows[8].begin() + 7),
            (std::vector<std::string>{tasks[7].id, "b", "4", "failed", "2", "exit code 2", ""}));
  const json table = json::parse(test::read_text(dir.file("merged/table.json")));
  EXPECT_EQ(table.at("timing_columns"), json({"t", "wall_s", "cpu_s"}));
  EXPECT_EQ(table.at("rows").size(), 8u);
  EXPECT_EQ(table.at("rows").at(0).at("even"), false);
  EXPECT_TRUE(table.at("rows").at(6).at("wall_s").is_null());
  const std::string md = test::read_text(dir.file("merged/summary.md"));
  EXPECT_NE(md.find("- " + tasks[7].id + ": failed: exit code 2\n- " + tasks[6].id + ": missing (not run, or interrupted)"), std::string::npos) << md;
}

TEST(SweepMerge, MergingTwiceGivesTheSameBytes) {
  ScratchDir dir;
  const SweepDir s = run_values(dir);
  merge_sweep(s, dir.file("m1"));
  merge_sweep(s, dir.file("m2"));
  merge_sweep(s, dir.file("m1"));  // over itself
  const auto one = test::files_under(dir.file("m1")), two = test::files_under(dir.file("m2"));
  ASSERT_EQ(one.size(), 7u);  // table x3, summary x3, one plot
  EXPECT_EQ(one, two);
}

TEST(SweepMerge, MetricsAddedAfterTheRunNeedNoRerun) {
  ScratchDir dir;
  const SweepDir s = run_values(dir);
  std::string yaml = kValues;
  yaml.replace(yaml.find("  v: /v\n"), 8, "  v: /v\n  doubled: /missing_key\n  whole: ''\n");
  test::write_text(dir.file("test_sweep.yaml"), yaml);
  ExpandOptions force;
  force.force = true;
  EXPECT_EQ(expand_sweep(dir.file("test_sweep.yaml"), s.dir, force).results_kept, 7u);
  const MergeReport r = merge_sweep(open_sweep_dir(s.dir), dir.file("merged"));
  EXPECT_EQ(r.ok, 6u);
  // A pointer found in no result is named; "" is the whole document.
  EXPECT_EQ(r.warnings, std::vector<std::string>{"metric doubled (/missing_key) is in none of the 6 results"});
  const json table = json::parse(test::read_text(dir.file("merged/table.json")));
  EXPECT_EQ(table.at("rows").at(1).at("whole"), json::parse("{\"v\": 2, \"even\": true, \"t\": 0.5}"));
}

TEST(SweepMerge, PlotSeriesAndErrorBars) {
  SweepPlot plot;
  plot.metric = "m";
  plot.x = "w";
  plot.series = "p";
  // x given as text in any order; series in order of first appearance; x numerically.
  const std::vector<PlotSample> samples = {{"10", "b", 5}, {"2", "b", 1}, {"2", "b", 3}, {"2", "a", 7}, {"10", "b", 7}, {"10", "b", 9}, {"2", "b", 2}};
  std::vector<PlotSeries> series = plot_series(plot, samples);
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].label, "p=b");
  ASSERT_EQ(series[0].points.size(), 2u);
  EXPECT_EQ(series[0].points[0].x, 2.0);
  EXPECT_EQ(series[0].points[0].y, 2.0);  // median of 1, 2, 3
  EXPECT_EQ(series[0].points[0].lo, 1.5);
  EXPECT_EQ(series[0].points[0].hi, 2.5);
  EXPECT_EQ(series[0].points[1].x, 10.0);
  EXPECT_EQ(series[0].points[1].n, 3u);
  EXPECT_EQ(series[1].points.size(), 1u);
  plot.error = ErrorBars::Sd;
  series = plot_series(plot, samples);
  EXPECT_DOUBLE_EQ(series[0].points[1].y, 7.0);
  EXPECT_DOUBLE_EQ(series[0].points[1].hi, 9.0);  // sd of 5, 7, 9 is 2
  EXPECT_DOUBLE_EQ(series[0].points[1].lo, 5.0);
  // Each bar is a vertical line and two caps; one path per series; a single value has no bar.
  const std::string svg = plot_svg("s", plot, series);
  std::size_t paths = 0;
  for (std::size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1)) ++paths;
  EXPECT_EQ(paths, 2u + 2u * 3u);
  EXPECT_NE(svg.find("s: m against w (mean +- sd)"), std::string::npos);
}

}  // namespace
}  // namespace starnav::sweep
