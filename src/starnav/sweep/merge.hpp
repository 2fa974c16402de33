#pragma once
// Merging a sweep's task records into one table, a summary and plots (docs/sweeps.md):
//
//   OUT/table.csv, table.json, table.md   one row per task of the manifest, in its order: id, the
//       axis columns, status (ok, failed, missing), exit_code, reason, the metrics, then the timing
//       columns (metrics marked timing, wall_s, cpu_s), which differ from run to run
//   OUT/summary.csv, summary.json, summary.md   per group of summary.group_by: counts, and each
//       metric's sample statistics (n, median, quartiles, mean, sd, min, max) over the tasks that
//       gave a result, the medians' ratios to the baseline group
//   OUT/plots/METRIC-vs-X[-by-SERIES].svg  a metric against a numeric axis, with error bars
//
// Everything depends only on the manifest and the records: merging twice gives the same bytes.
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/sweep/manifest.hpp"

namespace starnav::sweep {

struct MergeReport {
  std::uint64_t tasks = 0, ok = 0, failed = 0, missing = 0;
  std::vector<std::string> failed_ids, missing_ids;  // in manifest order
  std::vector<std::string> failed_reasons;           // one per failed id
  std::vector<std::string> files;                    // written, relative to the output folder
  std::vector<std::string> warnings;                 // e.g. a metric found in no result
  std::string rerun_command;                         // empty when nothing is left to do
};

// Writes the merged files into `out_dir` (created when missing).
MergeReport merge_sweep(const SweepDir& sweep, const std::string& out_dir);

// One point of a plot: the metric's centre (median with iqr and none, mean with sd) and its error
// bar (quartiles or mean +- sd) at one value of the x axis, over n results.
struct PlotPoint {
  double x = 0.0, y = 0.0, lo = 0.0, hi = 0.0;
  std::size_t n = 0;
};
struct PlotSeries {
  std::string label;  // "SERIES=VALUE", or "" for a plot without series
  std::vector<PlotPoint> points;  // by increasing x
};

// The series of `plot` from rows of (x text, series text, value): for tests and the SVG writer.
struct PlotSample {
  std::string x, series;
  double value = 0.0;
};
std::vector<PlotSeries> plot_series(const SweepPlot& plot, const std::vector<PlotSample>& samples);

// The SVG picture of the series.
std::string plot_svg(const std::string& sweep_name, const SweepPlot& plot, const std::vector<PlotSeries>& series);

// A number as the table writes it (shortest text that reads back to the same double).
std::string number_text(double v);

}  // namespace starnav::sweep
