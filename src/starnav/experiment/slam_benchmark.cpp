#include "starnav/experiment/slam_benchmark.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

std::string under(const std::string& dir, const std::string& file) {
  if (file.empty() || std::filesystem::path(file).is_absolute() || dir.empty()) return file;
  return (std::filesystem::path(dir) / file).string();
}

std::string number(double v, int decimals) { return std::isfinite(v) ? format_fixed(v, decimals) : "-"; }

std::string published_text(const PublishedRpe& p) {
  std::string s = number(p.t_mean, 4) + " ± " + number(p.t_sd, 4) + " m";
  if (std::isfinite(p.r_mean)) s += ", " + number(p.r_mean, 3) + " ± " + number(p.r_sd, 3) + "°";
  return s;
}

nlohmann::ordered_json published_json(const PublishedRpe& p) {
  nlohmann::ordered_json j;
  j["translation_m"] = {{"mean", p.t_mean}, {"sd", p.t_sd}};
  if (std::isfinite(p.r_mean)) j["rotation_deg"] = {{"mean", p.r_mean}, {"sd", p.r_sd}};
  return j;
}

}  // namespace

std::vector<SlamBenchmarkLog> slam_benchmark_logs() {
  LogReadOptions flaser;
  flaser.flaser_beam_angles = true;  // the aces bag was converted from FLASER lines (docs/slam.md)
  return {{"intel", "ros1_bags/intel.orig.bag", "intel.relations", {}},
          {"fr079", "ros1_bags/fr079.orig.bag", "fr079.relations", {}},
          {"aces", "ros1_bags/aces.orig.bag", "aces.relations", flaser},
          {"mit-csail", "mit-csail.clf.gz", "mit-csail.relations", {}}};
}

std::optional<SlamPublished> slam_published(const std::string& log) {
  // Kümmerle et al. 2009 Table 1 (RBPF: translation only), Hess et al. 2016 Tables II and V.
  static const std::vector<SlamPublished> table = {
      {"aces", {0.060, 0.049, kNone, kNone}, {0.044, 0.044, 0.4, 0.4}, {0.0375, 0.0426, 0.373, 0.469}, 41},
      {"intel", {0.070, 0.083, kNone, kNone}, {0.031, 0.026, 1.3, 4.7}, {0.0229, 0.0239, 0.453, 1.335}, 179},
      {"mit-killian", {0.122, 0.386, kNone, kNone}, {0.050, 0.056, 0.5, 0.5}, {0.0395, 0.0488, 0.352, 0.353}, 190},
      {"mit-csail", {0.049, 0.049, kNone, kNone}, {0.004, 0.009, 0.05, 0.08}, {0.0319, 0.0363, 0.369, 0.365}, 35},
      {"fr079", {0.061, 0.044, kNone, kNone}, {0.056, 0.042, 0.6, 0.6}, {0.0452, 0.0354, 0.538, 0.718}, 62},
  };
  for (const SlamPublished& p : table)
    if (p.log == log) return p;
  return std::nullopt;
}

SlamBenchmarkResult run_slam_benchmark(const SlamBenchmarkConfig& c) {
  if (c.logs.empty()) throw Error("no logs to run", {}, 0, "--logs");
  SlamBenchmarkResult out;
  out.method = c.method;
  out.settings = c.settings;
  for (std::size_t k = 0; k < c.logs.size(); ++k) {
    const SlamBenchmarkLog& entry = c.logs[k];
    SlamRunRequest q;
    q.record_steps = false;  // the viewer's steps would weigh on the measured peak memory
    q.log = under(c.data_dir, entry.log);
    q.relations = under(c.relations_dir, entry.relations);
    q.read = entry.read;
    q.method = c.method;
    q.settings = c.settings;
    SlamBenchmarkRow row;
    row.name = entry.name;
    row.run = run_slam_on_file(q, [&](std::size_t done, std::size_t total) {
      if (c.progress) c.progress(entry.name, k * 1000 + (total ? done * 1000 / total : 0), c.logs.size() * 1000);
    });
    row.laser_evaluated = row.run.rpe_laser.has_value();
    if (!c.out_dir.empty()) write_slam_outputs(row.run, (std::filesystem::path(c.out_dir) / entry.name).string());
    row.run.map = OccupancyGrid();  // written; the table needs none of it
    out.rows.push_back(std::move(row));
  }
  if (c.progress) c.progress("", c.logs.size() * 1000, c.logs.size() * 1000);
  return out;
}

std::string slam_benchmark_markdown(const SlamBenchmarkResult& r) {
  std::ostringstream o;
  o << "# SLAM benchmark: " << r.method << "\n\n";
  o << "One parameter set for every log";
  if (!r.settings.empty()) {
    o << " (";
    for (std::size_t i = 0; i < r.settings.size(); ++i) o << (i ? ", " : "") << r.settings[i].key << "=" << r.settings[i].value;
    o << ")";
  }
  o << ". Relative-pose error (Kümmerle et al. 2009) over every relation of each file, mean ± sd; the "
       "evaluated pose is the laser's where the log states a mount (the base pose's error beside it).\n\n";
  o << "| log | relations | starnav translation (m) | starnav rotation (°) | base pose (m) | graph mapping | Cartographer | RBPF |\n";
  o << "|---|---:|---|---|---|---|---|---|\n";
  for (const SlamBenchmarkRow& row : r.rows) {
    const RelativePoseError& e = row.evaluated();
    const std::optional<SlamPublished> p = slam_published(row.name);
    o << "| " << row.name << (row.laser_evaluated ? " (laser)" : "") << " | " << e.translation_m.n << " | "
      << number(e.translation_m.mean, 4) << " ± " << number(e.translation_m.sd, 4) << " | " << number(e.rotation_deg.mean, 3) << " ± "
      << number(e.rotation_deg.sd, 3) << " | " << number(row.run.rpe->translation_m.mean, 4) << " | "
      << (p ? published_text(p->graph_mapping) : "-") << " | " << (p ? published_text(p->cartographer) : "-") << " | "
      << (p ? published_text(p->rbpf) : "-") << " |\n";
  }
  o << "\nThe tail of the evaluated pose's translation error, beside the odometry's on the same relations, and how many relations "
       "SLAM gets wrong by more than the odometry does (by more than 1 m too).\n\n";
  o << "| log | mean (m) | p95 (m) | max (m) | odometry mean (m) | odometry p95 (m) | odometry max (m) | worse than odometry | by > 1 m |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SlamBenchmarkRow& row : r.rows) {
    const RelativePoseError& e = row.evaluated();
    const RelativePoseError& d = *row.run.rpe_odometry;
    o << "| " << row.name << " | " << number(e.translation_m.mean, 4) << " | " << number(e.translation_p95_m, 4) << " | "
      << number(e.translation_m.max, 4) << " | " << number(d.translation_m.mean, 4) << " | " << number(d.translation_p95_m, 4) << " | "
      << number(d.translation_m.max, 4) << " | " << row.run.worse_than_odometry << " | " << row.run.worse_than_odometry_by_1m << " |\n";
  }
  o << "\nShort relations (their poses at most " << number(kShortRelationS, 0)
    << " s apart: between nearby poses, set by the local matching) and long ones (across loops, set by the closures); the all-relations "
       "mean over the short relations' mean.\n\n";
  o << "| log | short: relations | short: mean (m) | long: relations | long: mean (m) | long: p95 (m) | long: max (m) | all / short |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SlamBenchmarkRow& row : r.rows) {
    const RelationSpans& s = *row.run.rpe_spans;
    const double all = row.evaluated().translation_m.mean;
    o << "| " << row.name << " | " << s.short_m.n << " | " << number(s.short_m.mean, 4) << " | " << s.long_m.n << " | "
      << (s.long_m.n ? number(s.long_m.mean, 4) : "-") << " | " << (s.long_m.n ? number(s.long_p95_m, 4) : "-") << " | "
      << (s.long_m.n ? number(s.long_m.max, 4) : "-") << " | " << (s.short_m.mean > 0 ? number(all / s.short_m.mean, 2) : "-") << " |\n";
  }
  o << "\n| log | log duration (s) | thread CPU (s) | wall (s) | real-time factor | peak memory (MB) | nodes | loop closures | Cartographer (s, 6 cores) |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SlamBenchmarkRow& row : r.rows) {
    const SlamRunResult& s = row.run;
    const std::optional<SlamPublished> p = slam_published(row.name);
    o << "| " << row.name << " | " << number(s.log_duration_s, 1) << " | " << number(s.cpu_s, 1) << " | " << number(s.wall_s, 1) << " | "
      << number(s.real_time_factor(), 1) << "x | " << number(static_cast<double>(s.peak_rss_bytes) / 1e6, 0) << " | "
      << s.graph.nodes.size() << " | " << s.graph.closures() << " | " << (p ? number(p->cartographer_runtime_s, 0) : "-") << " |\n";
  }
  return o.str();
}

std::string slam_benchmark_json(const SlamBenchmarkResult& r) {
  nlohmann::ordered_json j;
  j["method"] = r.method;
  nlohmann::ordered_json settings = nlohmann::ordered_json::object();
  for (const ParamSetting& s : r.settings) settings[s.key] = s.value;
  j["settings"] = settings;
  nlohmann::ordered_json logs = nlohmann::ordered_json::array();
  for (const SlamBenchmarkRow& row : r.rows) {
    nlohmann::ordered_json l;
    l["log"] = row.name;
    l["file"] = row.run.log;
    l["evaluated_pose"] = row.laser_evaluated ? "laser" : "base";
    l["rpe"] = rpe_summary_json(row.evaluated());
    l["rpe_base"] = rpe_summary_json(*row.run.rpe);
    l["rpe_odometry"] = rpe_summary_json(*row.run.rpe_odometry);
    l["worse_than_odometry"] = row.run.worse_than_odometry;
    l["worse_than_odometry_by_1m"] = row.run.worse_than_odometry_by_1m;
    l["rpe_spans"] = relation_spans_json(*row.run.rpe_spans);
    const nlohmann::ordered_json summary = slam_summary_json(row.run);
    for (const char* k : {"scans", "nodes", "loop_closures", "log_duration_s", "cpu_s", "wall_s", "real_time_factor", "peak_rss_mb"}) l[k] = summary[k];
    if (const std::optional<SlamPublished> p = slam_published(row.name)) {
      l["published"] = {{"rbpf", published_json(p->rbpf)},
                        {"graph_mapping", published_json(p->graph_mapping)},
                        {"cartographer", published_json(p->cartographer)},
                        {"cartographer_runtime_s", p->cartographer_runtime_s}};
    }
    logs.push_back(std::move(l));
  }
  j["logs"] = std::move(logs);
  return j.dump(1) + "\n";
}

}  // namespace starnav
