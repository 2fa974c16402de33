#include "starnav/sweep/merge.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <system_error>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/experiment/runner.hpp"
#include "starnav/sweep/streamed_file.hpp"
#include "starnav/sweep/task_record.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav::sweep {

namespace fs = std::filesystem;
using nlohmann::json;
using nlohmann::ordered_json;

namespace {

constexpr std::size_t kListedIds = 20;      // ids named in the rerun command and messages
constexpr std::size_t kListedInMarkdown = 100;

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos && (s.empty() || (s.front() != ' ' && s.back() != ' '))) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

std::string md_cell(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out;
}

// A result value as table text: numbers in their shortest exact form, true/false, text as is,
// nothing for null or absent, other JSON compact.
std::string value_text(const json* v) {
  if (!v || v->is_null()) return {};
  if (v->is_string()) return v->get<std::string>();
  return v->dump(-1, ' ', false, json::error_handler_t::replace);
}

std::optional<double> numeric(const json* v) {
  if (!v) return std::nullopt;
  if (v->is_boolean()) return v->get<bool>() ? 1.0 : 0.0;
  if (v->is_number()) {
    const double d = v->get<double>();
    if (std::isfinite(d)) return d;
  }
  return std::nullopt;
}

const json* lookup(const json& doc, const json::json_pointer& p) {
  try {
    if (!doc.contains(p)) return nullptr;
    return &doc.at(p);
  } catch (const json::exception&) {
    return nullptr;
  }
}

struct Group {
  std::string label;
  std::vector<std::string> values;  // the group_by axes' texts
  std::uint64_t tasks = 0, ok = 0, failed = 0, missing = 0, successes = 0;
  std::vector<std::vector<double>> samples;  // per summarised metric
};

ordered_json stats_json(const SampleStats& s) {
  ordered_json j;
  j["n"] = s.n;
  const auto put = [&](const char* k, double v) {
    if (s.n) j[k] = v;
    else j[k] = nullptr;
  };
  put("median", s.median);
  put("q25", s.q25);
  put("q75", s.q75);
  put("mean", s.mean);
  put("sd", s.sd);
  put("min", s.min);
  put("max", s.max);
  return j;
}

std::string shell_quote_path(const std::string& p) {
  if (!p.empty() && p.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_./+@%:,=") == std::string::npos)
    return p;
  std::string q = "'";
  for (const char c : p) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

}  // namespace

std::string number_text(double v) {
  if (!std::isfinite(v)) return {};
  return json(v).dump();
}

std::vector<PlotSeries> plot_series(const SweepPlot& plot, const std::vector<PlotSample>& samples) {
  // Series in order of first appearance; x values numerically.
  std::vector<std::string> order;
  std::map<std::string, std::map<double, std::vector<double>>> data;
  for (const PlotSample& s : samples) {
    const std::optional<double> x = [&]() -> std::optional<double> {
      char* end = nullptr;
      const double v = std::strtod(s.x.c_str(), &end);
      if (s.x.empty() || end != s.x.c_str() + s.x.size() || !std::isfinite(v)) return std::nullopt;
      return v;
    }();
    if (!x) continue;
    if (!data.count(s.series)) order.push_back(s.series);
    data[s.series][*x].push_back(s.value);
  }
  std::vector<PlotSeries> out;
  for (const std::string& name : order) {
    PlotSeries series;
    series.label = plot.series.empty() ? std::string() : plot.series + "=" + name;
    for (const auto& [x, values] : data[name]) {
      const SampleStats st = sample_stats(values);
      PlotPoint p;
      p.x = x;
      p.n = st.n;
      switch (plot.error) {
        case ErrorBars::Iqr: p.y = st.median; p.lo = st.q25; p.hi = st.q75; break;
        case ErrorBars::Sd: p.y = st.mean; p.lo = st.mean - st.sd; p.hi = st.mean + st.sd; break;
        case ErrorBars::None: p.y = p.lo = p.hi = st.median; break;
      }
      series.points.push_back(p);
    }
    out.push_back(std::move(series));
  }
  return out;
}

std::string plot_svg(const std::string& sweep_name, const SweepPlot& plot, const std::vector<PlotSeries>& series) {
  const char* centre = plot.error == ErrorBars::Sd ? "mean +- sd" : plot.error == ErrorBars::Iqr ? "median, quartiles" : "median";
  viz::LinePlot chart({.title = sweep_name + ": " + plot.metric + " against " + plot.x + " (" + centre + ")",
                       .x_label = plot.x,
                       .y_label = plot.metric});
  double x_lo = 0.0, x_hi = 0.0;
  bool any = false;
  for (const PlotSeries& s : series)
    for (const PlotPoint& p : s.points) {
      x_lo = any ? std::min(x_lo, p.x) : p.x;
      x_hi = any ? std::max(x_hi, p.x) : p.x;
      any = true;
    }
  // Caps a fixed share of the x span wide (of the value when the span is 0).
  const double cap = 0.008 * (x_hi > x_lo ? x_hi - x_lo : std::max(1.0, std::abs(x_lo)));
  for (std::size_t k = 0; k < series.size(); ++k) {
    const viz::Rgba colour = viz::categorical_colour(k);
    std::vector<Vec2> centres;
    for (const PlotPoint& p : series[k].points) centres.emplace_back(p.x, p.y);
    chart.add_series(centres, {.colour = colour, .width_px = 1.6, .dashed = false, .markers = true}, series[k].label);
    if (plot.error == ErrorBars::None) continue;
    for (const PlotPoint& p : series[k].points) {
      if (!(p.hi > p.lo)) continue;
      const viz::SeriesStyle bar{.colour = colour, .width_px = 1.2, .dashed = false, .markers = false};
      chart.add_series({Vec2(p.x, p.lo), Vec2(p.x, p.hi)}, bar);
      chart.add_series({Vec2(p.x - cap, p.lo), Vec2(p.x + cap, p.lo)}, bar);
      chart.add_series({Vec2(p.x - cap, p.hi), Vec2(p.x + cap, p.hi)}, bar);
    }
  }
  return chart.svg_string();
}

MergeReport merge_sweep(const SweepDir& sweep, const std::string& out_dir) {
  const SweepSpec& spec = sweep.spec;
  MergeReport report;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw Error("cannot create the folder: " + ec.message(), out_dir, 0, "--out");

  // Columns: id, axes, status, exit_code, reason, metrics, then the timing ones.
  std::vector<std::size_t> plain_metrics, timing_metrics;
  for (std::size_t m = 0; m < spec.metrics.size(); ++m) (spec.metrics[m].timing ? timing_metrics : plain_metrics).push_back(m);
  std::vector<std::string> columns{"id"};
  columns.insert(columns.end(), sweep.columns.begin(), sweep.columns.end());
  for (const char* c : {"status", "exit_code", "reason"}) columns.emplace_back(c);
  for (const std::size_t m : plain_metrics) columns.push_back(spec.metrics[m].name);
  std::vector<std::string> timing_columns;
  for (const std::size_t m : timing_metrics) timing_columns.push_back(spec.metrics[m].name);
  timing_columns.emplace_back("wall_s");
  timing_columns.emplace_back("cpu_s");
  columns.insert(columns.end(), timing_columns.begin(), timing_columns.end());

  // Summarised metrics: the sweep's, then wall_s and cpu_s.
  std::vector<std::string> summary_names;
  for (const SweepMetric& m : spec.metrics) summary_names.push_back(m.name);
  summary_names.emplace_back("wall_s");
  summary_names.emplace_back("cpu_s");
  std::vector<json::json_pointer> pointers, conditions;
  for (const SweepMetric& m : spec.metrics) {
    pointers.emplace_back(m.pointer);
    conditions.emplace_back(m.when);
  }
  std::optional<std::size_t> success_metric;
  for (std::size_t m = 0; m < spec.metrics.size(); ++m)
    if (spec.metrics[m].name == spec.summary.success) success_metric = m;
  std::vector<std::uint64_t> found_in(spec.metrics.size(), 0);

  std::vector<Group> groups;
  std::unordered_map<std::string, std::size_t> group_of;
  std::vector<std::vector<PlotSample>> plot_samples(spec.plots.size());
  std::vector<std::size_t> plot_x_col, plot_series_col, plot_metric;
  const auto column_of_axis = [&](const std::string& axis) {
    return static_cast<std::size_t>(std::find(sweep.columns.begin(), sweep.columns.end(), axis) - sweep.columns.begin());
  };
  for (const SweepPlot& p : spec.plots) {
    plot_x_col.push_back(column_of_axis(p.x));
    plot_series_col.push_back(p.series.empty() ? sweep.columns.size() : column_of_axis(p.series));
    plot_metric.push_back(static_cast<std::size_t>(std::find(summary_names.begin(), summary_names.end(), p.metric) - summary_names.begin()));
  }

  StreamedFile csv(out_dir + "/table.csv"), js(out_dir + "/table.json"), md(out_dir + "/table.md");
  {
    std::string line;
    for (std::size_t i = 0; i < columns.size(); ++i) line.append(i ? "," : "").append(csv_field(columns[i]));
    csv.write(line + "\n");
    ordered_json head;
    head["sweep"] = spec.name;
    head["columns"] = columns;
    head["timing_columns"] = timing_columns;
    std::string h = head.dump();
    h.pop_back();  // reopen the object for the rows
    js.write(h + ",\"rows\":[");
    std::string m = "|", rule = "|";
    for (const std::string& c : columns) {
      m.append(" ").append(md_cell(c)).append(" |");
      rule += "---|";
    }
    md.write("# " + md_cell(spec.name) + ": every task\n\n" + m + "\n" + rule + "\n");
  }

  bool first_row = true;
  for_each_task(sweep, [&](const SweepTask& task) {
    ++report.tasks;
    std::optional<TaskRecord> rec;
    try {
      rec = read_record(sweep.result_path(task.id));
      if (rec && rec->id != task.id) throw Error("holds the record of task " + printable(rec->id, 40), sweep.result_path(task.id));
    } catch (const Error& e) {
      report.warnings.push_back(std::string(e.what()) + ": counted as missing");
      rec.reset();
    }
    json doc;
    if (rec && rec->status == TaskStatus::Ok) {
      try {
        doc = json::parse(rec->result);
      } catch (const json::exception&) {
        report.warnings.push_back(sweep.result_path(task.id) + ": its result is not JSON: counted as missing");
        rec.reset();
      }
    }
    const std::string status = !rec ? "missing" : rec->status == TaskStatus::Ok ? "ok" : "failed";
    if (!rec) {
      ++report.missing;
      report.missing_ids.push_back(task.id);
    } else if (rec->status == TaskStatus::Ok) {
      ++report.ok;
    } else {
      ++report.failed;
      report.failed_ids.push_back(task.id);
      report.failed_reasons.push_back(rec->reason);
    }
    const bool ok = rec && rec->status == TaskStatus::Ok;
    std::vector<const json*> values(spec.metrics.size(), nullptr);
    if (ok)
      for (std::size_t m = 0; m < spec.metrics.size(); ++m) {
        if ((values[m] = lookup(doc, pointers[m]))) ++found_in[m];
        if (!spec.metrics[m].when.empty()) {
          const std::optional<double> c = numeric(lookup(doc, conditions[m]));
          if (!c || *c == 0.0) values[m] = nullptr;
        }
      }

    // The row.
    std::vector<std::string> texts{task.id};
    texts.insert(texts.end(), task.values.begin(), task.values.end());
    texts.push_back(status);
    texts.push_back(rec ? std::to_string(rec->exit_code) : std::string());
    texts.push_back(rec && !ok ? rec->reason : std::string());
    ordered_json row;
    row["id"] = task.id;
    for (std::size_t c = 0; c < sweep.columns.size(); ++c) row[sweep.columns[c]] = task.values[c];
    row["status"] = status;
    row["exit_code"] = rec ? ordered_json(rec->exit_code) : ordered_json(nullptr);
    row["reason"] = rec && !ok ? ordered_json(rec->reason) : ordered_json(nullptr);
    const auto put_metric = [&](std::size_t m) {
      texts.push_back(value_text(values[m]));
      row[spec.metrics[m].name] = values[m] ? ordered_json::parse(values[m]->dump()) : ordered_json(nullptr);
    };
    for (const std::size_t m : plain_metrics) put_metric(m);
    for (const std::size_t m : timing_metrics) put_metric(m);
    texts.push_back(rec ? number_text(rec->wall_s) : std::string());
    texts.push_back(rec ? number_text(rec->cpu_s) : std::string());
    row["wall_s"] = rec ? ordered_json(rec->wall_s) : ordered_json(nullptr);
    row["cpu_s"] = rec ? ordered_json(rec->cpu_s) : ordered_json(nullptr);
    std::string line, mline = "|";
    for (std::size_t i = 0; i < texts.size(); ++i) {
      line.append(i ? "," : "").append(csv_field(texts[i]));
      mline.append(" ").append(md_cell(texts[i])).append(" |");
    }
    csv.write(line + "\n");
    md.write(mline + "\n");
    js.write(std::string(first_row ? "\n" : ",\n") + row.dump(-1, ' ', false, json::error_handler_t::replace));
    first_row = false;

    // The summary's group and samples.
    const std::string label = group_label(spec, task.values);
    auto [it, fresh] = group_of.try_emplace(label, groups.size());
    if (fresh) {
      Group g;
      g.label = label;
      for (const std::string& axis : spec.summary.group_by) {
        const SweepAxis& ax = spec.axes[*spec.axis_index(axis)];
        const std::size_t col = column_of_axis(ax.columns()[0]);
        std::string v;
        for (std::size_t f = 0; f < ax.width(); ++f) v += (f ? " " : "") + task.values[col + f];
        g.values.push_back(v);
      }
      g.samples.resize(summary_names.size());
      groups.push_back(std::move(g));
    }
    Group& g = groups[it->second];
    ++g.tasks;
    if (!rec) ++g.missing;
    else if (!ok) ++g.failed;
    else {
      ++g.ok;
      if (!success_metric) ++g.successes;
      else if (const std::optional<double> v = numeric(values[*success_metric]); v && *v != 0.0) ++g.successes;
    }
    if (!ok) return;
    std::vector<std::optional<double>> nums(summary_names.size());
    for (std::size_t m = 0; m < spec.metrics.size(); ++m) nums[m] = numeric(values[m]);
    nums[spec.metrics.size()] = rec->wall_s;
    nums[spec.metrics.size() + 1] = rec->cpu_s;
    for (std::size_t m = 0; m < nums.size(); ++m)
      if (nums[m]) g.samples[m].push_back(*nums[m]);
    for (std::size_t p = 0; p < spec.plots.size(); ++p)
      if (const std::optional<double> v = nums[plot_metric[p]])
        plot_samples[p].push_back({task.values[plot_x_col[p]],
                                   plot_series_col[p] < task.values.size() ? task.values[plot_series_col[p]] : std::string(), *v});
  });
  js.write("\n]}\n");
  csv.commit();
  js.commit();
  md.commit();
  report.files = {"table.csv", "table.json", "table.md"};

  for (std::size_t m = 0; m < spec.metrics.size(); ++m)
    if (report.ok > 0 && found_in[m] == 0)
      report.warnings.push_back("metric " + spec.metrics[m].name + " (" + spec.metrics[m].pointer + ") is in none of the " +
                                std::to_string(report.ok) + " results");

  // The rerun command.
  const std::string dir_arg = shell_quote_path(sweep.dir);
  const std::uint64_t incomplete = report.failed + report.missing;
  if (incomplete > 0 && incomplete <= kListedIds) {
    std::string ids;
    for (const auto* list : {&report.failed_ids, &report.missing_ids})
      for (const std::string& id : *list) ids += (ids.empty() ? "" : ",") + id;
    report.rerun_command = "starnav sweep run " + dir_arg + " --tasks " + ids;
  } else if (incomplete > 0) {
    report.rerun_command = "starnav sweep run " + dir_arg + (report.failed ? " --retry-failed" : "");
  }

  // The summary.
  std::size_t baseline = 0;
  if (!spec.summary.baseline.empty()) {
    const auto b = group_of.find(spec.summary.baseline);
    if (b == group_of.end())
      throw Error("no group is called '" + printable(spec.summary.baseline, 60) + "'", spec.source, spec.summary.baseline_line,
                  "summary.baseline");
    baseline = b->second;
  }
  std::vector<VariantSummary> summaries;
  for (const Group& g : groups) {
    VariantSummary s;
    s.variant = g.label;
    s.runs = static_cast<std::size_t>(g.tasks);
    s.completed = static_cast<std::size_t>(g.ok);
    s.successes = static_cast<std::size_t>(g.successes);
    s.success_rate = g.tasks ? static_cast<double>(g.successes) / static_cast<double>(g.tasks) : 0.0;
    for (const std::vector<double>& v : g.samples) s.metrics.push_back(sample_stats(v));
    summaries.push_back(std::move(s));
  }
  const std::vector<std::string> stat_names{"n", "median", "q25", "q75", "mean", "sd", "min", "max"};
  {
    std::string out;
    std::vector<std::string> head = spec.summary.group_by.empty() ? std::vector<std::string>{"group"} : spec.summary.group_by;
    for (const char* c : {"tasks", "ok", "failed", "missing", "successes"}) head.emplace_back(c);
    for (const std::string& m : summary_names)
      for (const std::string& st : stat_names) head.push_back(m + "_" + st);
    for (std::size_t i = 0; i < head.size(); ++i) out.append(i ? "," : "").append(csv_field(head[i]));
    out += "\n";
    for (std::size_t k = 0; k < groups.size(); ++k) {
      const Group& g = groups[k];
      std::vector<std::string> cells = spec.summary.group_by.empty() ? std::vector<std::string>{g.label} : g.values;
      for (const std::uint64_t c : {g.tasks, g.ok, g.failed, g.missing, g.successes}) cells.push_back(std::to_string(c));
      for (const SampleStats& st : summaries[k].metrics) {
        cells.push_back(std::to_string(st.n));
        for (const double v : {st.median, st.q25, st.q75, st.mean, st.sd, st.min, st.max})
          cells.push_back(st.n ? number_text(v) : std::string());
      }
      for (std::size_t i = 0; i < cells.size(); ++i) out.append(i ? "," : "").append(csv_field(cells[i]));
      out += "\n";
    }
    write_file_atomically(out_dir + "/summary.csv", out);
  }
  {
    ordered_json j;
    j["sweep"] = spec.name;
    j["tasks"] = report.tasks;
    j["ok"] = report.ok;
    j["failed"] = report.failed;
    j["missing"] = report.missing;
    j["group_by"] = spec.summary.group_by;
    j["success"] = spec.summary.success.empty() ? ordered_json("a result") : ordered_json(spec.summary.success);
    j["baseline"] = groups.empty() ? ordered_json(nullptr) : ordered_json(groups[baseline].label);
    j["metrics"] = summary_names;
    j["timing_metrics"] = timing_columns;
    ordered_json list = ordered_json::array();
    for (std::size_t k = 0; k < groups.size(); ++k) {
      const Group& g = groups[k];
      ordered_json gj;
      gj["group"] = g.label;
      ordered_json values = ordered_json::object();
      for (std::size_t a = 0; a < spec.summary.group_by.size(); ++a) values[spec.summary.group_by[a]] = g.values[a];
      gj["values"] = values;
      gj["tasks"] = g.tasks;
      gj["ok"] = g.ok;
      gj["failed"] = g.failed;
      gj["missing"] = g.missing;
      gj["successes"] = g.successes;
      ordered_json metrics = ordered_json::object();
      for (std::size_t m = 0; m < summary_names.size(); ++m) metrics[summary_names[m]] = stats_json(summaries[k].metrics[m]);
      gj["metrics"] = metrics;
      if (groups.size() > 1 && k != baseline) {
        ordered_json ratios = ordered_json::object();
        const std::vector<double> r = median_ratios(summaries[k], summaries[baseline]);
        for (std::size_t m = 0; m < summary_names.size(); ++m) ratios[summary_names[m]] = std::isfinite(r[m]) ? ordered_json(r[m]) : ordered_json(nullptr);
        gj["median_ratio_to_baseline"] = ratios;
      }
      list.push_back(gj);
    }
    j["groups"] = list;
    ordered_json failed = ordered_json::array();
    for (std::size_t i = 0; i < report.failed_ids.size(); ++i)
      failed.push_back({{"id", report.failed_ids[i]}, {"reason", report.failed_reasons[i]}});
    j["failed"] = failed;
    j["missing_ids"] = report.missing_ids;
    j["rerun"] = report.rerun_command.empty() ? ordered_json(nullptr) : ordered_json(report.rerun_command);
    write_file_atomically(out_dir + "/summary.json", j.dump(2, ' ', false, json::error_handler_t::replace) + "\n");
  }
  {
    std::string out = "# " + md_cell(spec.name) + ": summary\n\n";
    out += std::to_string(report.tasks) + " tasks: " + std::to_string(report.ok) + " with a result, " + std::to_string(report.failed) +
           " failed, " + std::to_string(report.missing) + " missing. ";
    out += spec.summary.group_by.empty() ? std::string("All tasks in one group.") : "Grouped by " + [&] {
      std::string s;
      for (const std::string& g : spec.summary.group_by) s += (s.empty() ? "" : ", ") + g;
      return s;
    }() + ".";
    out += " Each cell: median [q25 .. q75] (n) over the tasks with a result; success: " +
           (spec.summary.success.empty() ? std::string("tasks with a result") : "tasks whose " + spec.summary.success + " is true (non-zero)") +
           " of all tasks";
    if (groups.size() > 1) out += "; the last columns: each group's median over the baseline's (" + md_cell(groups[baseline].label) + ")";
    out += ". Timing metrics (" + [&] {
      std::string s;
      for (const std::string& c : timing_columns) s += (s.empty() ? "" : ", ") + c;
      return s;
    }() + ") differ from run to run.\n\n";
    out += summary_markdown(summaries, summary_names, baseline);
    if (incomplete > 0) {
      out += "\n## Tasks without a result\n\n";
      std::size_t listed = 0;
      for (std::size_t i = 0; i < report.failed_ids.size() && listed < kListedInMarkdown; ++i, ++listed)
        out += "- " + report.failed_ids[i] + ": failed: " + md_cell(report.failed_reasons[i]) + "\n";
      for (std::size_t i = 0; i < report.missing_ids.size() && listed < kListedInMarkdown; ++i, ++listed)
        out += "- " + report.missing_ids[i] + ": missing (not run, or interrupted)\n";
      if (incomplete > listed) out += "- ... and " + std::to_string(incomplete - listed) + " more (summary.json lists them all)\n";
      out += "\nRun them again with `" + report.rerun_command + "`.\n";
    }
    write_file_atomically(out_dir + "/summary.md", out);
  }
  for (const char* f : {"summary.csv", "summary.json", "summary.md"}) report.files.emplace_back(f);

  if (!spec.plots.empty()) {
    fs::create_directories(out_dir + "/plots", ec);
    if (ec) throw Error("cannot create the folder: " + ec.message(), out_dir + "/plots");
    for (std::size_t p = 0; p < spec.plots.size(); ++p) {
      const std::vector<PlotSeries> series = plot_series(spec.plots[p], plot_samples[p]);
      write_file_atomically(out_dir + "/plots/" + spec.plots[p].file_name(), plot_svg(spec.name, spec.plots[p], series));
      report.files.push_back("plots/" + spec.plots[p].file_name());
    }
  }
  return report;
}

}  // namespace starnav::sweep
