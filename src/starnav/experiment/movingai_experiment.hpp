#pragma once
// The MovingAI experiment of `starnav bench movingai` (Sturtevant 2012 benchmarks): grid planners
// on map/scenario pairs, each answer checked against the scenario file's optimal length and timed,
// run on the experiment runner (runner.hpp) with the maps as instances and the planners as
// variants. An answer is exact when |cost - optimal| <= max(0.01, 1e-5 * optimal); a length-0
// line whose start differs from its goal is unsolvable and "no path" is its exact answer. Times
// exclude per-map preprocessing (preprocess_ms) and are each instance's median over the repeats.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "starnav/experiment/runner.hpp"

namespace starnav {

struct MovingAiPair {
  std::string name;  // "dao/den520d" under a folder, the map's stem otherwise
  std::string map_path;
  std::string scen_path;
};
// Every FILE.map with a FILE.map.scen beside it under `dir`, recursively, sorted by name. Throws
// Error (field "--dir") for a missing folder or one without pairs.
std::vector<MovingAiPair> find_movingai_pairs(const std::string& dir);

// Problem indices to run: all (limit 0), or `limit` spread evenly over the file (every bucket is
// represented, unlike the first N lines which are the shortest problems).
std::vector<std::size_t> select_instances(std::size_t total, std::size_t limit);

struct MovingAiConfig {
  std::vector<MovingAiPair> pairs;
  std::vector<std::string> planners{"astar", "jps", "jpsplus"};
  std::size_t limit = 0;
  int repeat = 1;
  bool csv_rows = false;  // keep one CSV row per problem and planner
  // Progress of the running planner on the current map (done of steps queries) and of finished maps.
  std::function<void(std::size_t map_index, const std::string& map, std::size_t planner_index, const std::string& planner,
                     std::size_t done, std::size_t steps)>
      on_queries;
  std::function<void(std::size_t map_index, const std::string& map, std::size_t instances, double seconds)> on_map_done;
};

// Everything a summary needs, for one planner on one map or on all of them.
struct MovingAiTally {
  std::string planner;
  bool admissible = true;
  int maps = 0;
  std::size_t instances = 0;
  std::size_t unsolvable = 0;  // length-0 lines with start != goal
  std::size_t solved = 0;      // a path was returned
  std::size_t exact = 0;
  std::size_t shorter = 0;  // cost below the 8-connected optimum by more than the tolerance (any-angle)
  double max_abs_error = 0.0;
  double max_suboptimality = 0.0;
  double sum_suboptimality = 0.0;
  std::size_t suboptimality_count = 0;
  std::vector<double> instance_time_us;  // each instance's median over repeats
  std::uint64_t expanded = 0;
  std::uint64_t generated = 0;
  double preprocess_ms = 0.0;

  void merge(const MovingAiTally& o) {
    maps += o.maps;
    instances += o.instances;
    unsolvable += o.unsolvable;
    solved += o.solved;
    exact += o.exact;
    shorter += o.shorter;
    max_abs_error = std::max(max_abs_error, o.max_abs_error);
    max_suboptimality = std::max(max_suboptimality, o.max_suboptimality);
    sum_suboptimality += o.sum_suboptimality;
    suboptimality_count += o.suboptimality_count;
    instance_time_us.insert(instance_time_us.end(), o.instance_time_us.begin(), o.instance_time_us.end());
    expanded += o.expanded;
    generated += o.generated;
    preprocess_ms += o.preprocess_ms;
  }

};

struct MovingAiResult {
  MovingAiConfig config;
  std::vector<MovingAiTally> totals;   // per planner, over every map
  std::vector<MovingAiTally> per_map;  // per map and planner, in run order
  std::vector<std::string> per_map_names;
  std::size_t total_instances = 0;
  std::string csv;                     // with csv_rows: the header and one row per problem and planner
};

// The planners to run: `requested` by their registry names without repeats (the default three
// when empty); a deprecated spelling adds its warning to `warnings`. Throws Error (field
// "--planner") for a name that is not an occupancy planner of the registry.
std::vector<std::string> movingai_planners(const std::vector<std::string>& requested, std::vector<std::string>* warnings = nullptr);

// Throws Error for an unknown planner, a bad repeat count, a map or scenario file that cannot be
// read, or a scenario for another map size.
MovingAiResult run_movingai_experiment(const MovingAiConfig& config);

// The JSON document (--json), the text report (tables, and the inexact answers), the exit code
// (1 when an admissible planner missed an optimal answer).
std::string movingai_json(const MovingAiResult& result);
std::string movingai_report(const MovingAiResult& result, bool per_map);
int movingai_exit_code(const MovingAiResult& result);

}  // namespace starnav
