#pragma once
// The path-planning ablation of Ou et al. 2022 (paper 4.2, Table 2 and Fig. 15;
// docs/papers/ou2022.md, Reproduction), behind `starnav bench ablation`, on the experiment runner
// (runner.hpp) with the queries as instances and the planner variants as variants.
//
// Every variant runs on the same queries, on the same map, with the same heuristic per table: one
// table per heuristic (Manhattan as the paper, octile) and per map (the original map and, with
// inflate > 0, the inflated one). Rows:
//   A*                      plain A*
//   A* + turn_w             the paper's steering cost (cell states)
//   A* + turn_w + W         ... and the adaptive heuristic weight (1 + d/D)
//   A* + turn_w + W + LOS   ... and line-of-sight smoothing: the paper's full method on the
//                           inflated map (inflation + smoothing + turn_w + W)
//   A* + turn_w (exact)     beyond the paper: (cell, incoming direction) states (optional)
//   JPS, JPS + LOS          jump point search (octile heuristic in every table: JPS has no other)
// Per query: search time (ms: the least thread CPU time of `repeat` runs of the query, which
// filters out the disturbances of a shared machine; the median wall time is kept too),
// expansions, Tir and Enr (% less time and fewer expansions than A* on the same table; positive =
// improvement), cost, and the path metrics (plan/path_metrics.hpp; clearance against the original
// map's obstacles), plus the vertices and turning points after line-of-sight smoothing of that
// variant's path. Averages are over the queries every variant of the table solved; Tir and Enr
// are averaged per query as the paper does (its 13 % and 11 % are the means of its three queries).
//
// Query coordinates are cells (MovingAI: column, row from the top; map_server maps: ix, iy from
// the bottom). Random queries have start and goal free on the inflated map, at a Euclidean
// distance of min_dist..max_dist cells (default 40..60, the paper's), in one connected component
// of the inflated map; the draw depends only on the map, the options and the seed.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "starnav/io/map_file.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/plan/path_metrics.hpp"

namespace starnav {

struct AblationQuery {
  Cell start, goal;
};

// A MovingAI .scen, or a CSV with header start_x,start_y,goal_x,goal_y, for a map of
// map_width x map_height cells. Throws Error naming the file and line (field "--queries"), also
// for a .scen written for another map size and for a query cell outside the map.
std::vector<AblationQuery> read_ablation_queries(const std::string& path, int map_width, int map_height,
                                                 const std::string& map_name);

struct AblationConfig {
  std::string map;              // an occupancy map file
  std::string queries;          // a query file, or empty to draw `random` queries
  std::size_t random = 0;
  std::uint64_t seed = 0;       // of the random draw
  double min_dist = 40.0, max_dist = 60.0;  // random queries, cells
  double inflate = 0.0;         // hard inflation radius (metres; cells on MovingAI maps)
  double turn_cost = 1.0;       // k_turn
  int repeat = 5;               // timed runs per query and variant
  bool exact_variant = true;    // the (cell, direction) steering variant
  // Called before each table with its title and the number of queries.
  std::function<void(const std::string& table, std::size_t queries)> on_table;
};

struct AblationVariant {
  std::string name;
  bool jps = false;
  double turn_cost = 0.0;
  bool adaptive = false;
  bool exact = false;
  bool smooth = false;
};

struct AblationRun {
  bool found = false;
  std::string reason;
  double time_ms = 0.0;  // least thread CPU time of the repeats
  double wall_ms = 0.0;  // median wall time of the repeats
  std::uint64_t expanded = 0;
  std::uint64_t generated = 0;
  double cost = 0.0;
  PathMetrics metrics;
  std::size_t vertices_los = 0;
  std::size_t turning_points_los = 0;
  std::vector<Cell> path;
};

// Means over the queries every variant of a table solved.
struct AblationSummary {
  std::size_t solved = 0;  // by this variant
  std::size_t common = 0;  // by every variant of the table
  double time_ms = 0, expanded = 0, tir = 0, enr = 0, tir_total = 0, enr_total = 0, cost = 0, length = 0,
         vertices = 0, turning_points = 0, vertices_los = 0, turning_points_los = 0, turn_total = 0, turn_max = 0,
         clearance_min = 0, clearance_mean = 0, smoothness = 0;
};

struct AblationTable {
  std::string heuristic;  // manhattan, octile
  bool inflated = false;
  std::vector<AblationVariant> variants;
  std::vector<std::vector<AblationRun>> runs;  // [variant][query]
  std::vector<AblationSummary> summaries;      // [variant]
};

struct AblationResult {
  AblationConfig config;
  LoadedMap map;
  bool index_grid = false;  // MovingAI or y_down: cells
  std::string unit;         // "cells" or "m"
  std::size_t obstacle_cells = 0, inflated_cells = 0;
  std::vector<std::uint8_t> inflated_blocked;  // per cell
  std::vector<AblationQuery> queries;
  std::vector<AblationTable> tables;
};

// Throws Error (naming the flag: --repeat, --inflate, ...) for impossible options, an unreadable
// or elevation map, a bad query file or too few solvable random queries.
AblationResult run_ablation_experiment(const AblationConfig& config);

std::string ablation_table_title(const AblationResult& r, const AblationTable& t);
// The summary (heading, setup and one table per heuristic and map), as printed.
std::string ablation_summary_markdown(const AblationResult& r);
// The summary and the per-query tables (ablation.md).
std::string ablation_full_markdown(const AblationResult& r);
std::string ablation_json(const AblationResult& r);  // ablation.json
std::string ablation_queries_csv(const AblationResult& r);  // reusable as a query file
// The paper's Fig. 15 for query q: the paths of A*, A* + turn_w + W, the full method and JPS +
// LOS overlaid on the map around the query. Throws Error naming the file when it cannot write.
void write_ablation_query_svg(const AblationResult& r, std::size_t q, const std::string& path);

}  // namespace starnav
