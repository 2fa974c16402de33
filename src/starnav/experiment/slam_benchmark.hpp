#pragma once
// `starnav bench slam`: a SLAM method on every raw log of the Freiburg SLAM benchmark (Kümmerle
// et al. 2009) with one parameter set, each evaluated against its relation file, in one table
// beside the published figures of RBPF (Gmapping), graph mapping and Cartographer
// (Kümmerle et al. 2009; docs/slam.md, docs/papers/ren2022.md).
//
// Per log: the relative-pose error of the base pose and, where the log states a laser mount, of
// the laser pose, which is the pose the benchmark's relations describe (fr079's converter stores
// +0.04 m in /tf_static; docs/slam.md); thread CPU and wall time of the SLAM run, real-time factor
// (log duration / CPU time) and the peak resident memory of the run.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "starnav/harness/slam_report.hpp"

namespace starnav {

// One log of the benchmark: where it lies under the data folder and its relation file.
struct SlamBenchmarkLog {
  std::string name;
  std::string log;        // relative to the data folder, or absolute
  std::string relations;  // relative to the relations folder, or absolute
  LogReadOptions read;
};
// intel, fr079, aces, mit-csail as ../shared/datasets/carmen_raw holds them.
std::vector<SlamBenchmarkLog> slam_benchmark_logs();

// A published result: translation mean and sd (m), rotation mean and sd (deg; NaN where the
// source gives none).
struct PublishedRpe {
  double t_mean = 0, t_sd = 0, r_mean = 0, r_sd = 0;
};
struct SlamPublished {
  std::string log;
  PublishedRpe rbpf, graph_mapping, cartographer;
  double cartographer_runtime_s = 0;  // Hess et al. 2016 Table V (6-core Xeon, background threads)
};
// The published table; nullopt for a log it does not list.
std::optional<SlamPublished> slam_published(const std::string& log);

struct SlamBenchmarkConfig {
  std::string data_dir, relations_dir;
  std::vector<SlamBenchmarkLog> logs = slam_benchmark_logs();
  std::string method = "graph";
  std::vector<ParamSetting> settings;  // one parameter set for every log
  std::string out_dir;                 // each log's outputs in out_dir/<name>/ (none when empty)
  std::function<void(const std::string& log, std::size_t done, std::size_t total)> progress;
};

struct SlamBenchmarkRow {
  std::string name;
  SlamRunResult run;
  bool laser_evaluated = false;  // the laser pose is the evaluated one
  const RelativePoseError& evaluated() const { return laser_evaluated ? *run.rpe_laser : *run.rpe; }
};

struct SlamBenchmarkResult {
  std::string method;
  std::vector<ParamSetting> settings;
  std::vector<SlamBenchmarkRow> rows;
};

SlamBenchmarkResult run_slam_benchmark(const SlamBenchmarkConfig& config);
std::string slam_benchmark_markdown(const SlamBenchmarkResult& r);
std::string slam_benchmark_json(const SlamBenchmarkResult& r);

}  // namespace starnav
