#include "starnav/experiment/ren_table1_experiment.hpp"

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/map/distance_transform.hpp"
#include "starnav/plan/grid_planner.hpp"

namespace starnav {

void RenTable1Config::validate() const {
  if (repeats < 1 || repeats > 10000) throw Error("must be in [1, 10000]", {}, 0, "--repeats");
  if (queries < 0 || queries > 1000000) throw Error("must be in [0, 1000000]", {}, 0, "--queries");
  if (!(inflation_m >= 0.0) || inflation_m > 5.0) throw Error("must be in [0, 5] m", {}, 0, "--inflation-m");
}

namespace {

const char* const kPlanners[] = {"dijkstra", "astar"};

GridPlannerOptions options_for(double inflation_m) {
  GridPlannerOptions o;
  o.connectivity = 8;
  o.ou2022.inflation.radius_m = inflation_m;
  return o;
}

// One planner on one map: the planner object (with its inflated map) built once, the query
// searched `repeats` times.
RenTable1Row single_query(const std::string& label, const OccupancyGrid& map, const char* planner, const RenTable1Config& c) {
  RenTable1Row row;
  row.map = label;
  row.planner = planner;
  row.queries = 1;
  const auto start = map.geometry().world_to_cell({c.start_x, c.start_y});
  const auto goal = map.geometry().world_to_cell({c.goal_x, c.goal_y});
  if (!start || !goal) throw Error("the query's start or goal lies outside the map", label, 0, "query");
  const double t0 = thread_cpu_s();
  const auto p = make_grid_planner(planner, map, options_for(c.inflation_m));
  row.inflation_ms = (thread_cpu_s() - t0) * 1e3;
  std::vector<double> ms;
  for (int k = 0; k < c.repeats; ++k) {
    const double a = thread_cpu_s();
    const PlanResult r = p->plan(*start, *goal);
    ms.push_back((thread_cpu_s() - a) * 1e3);
    if (!r.found()) throw Error("no path from (" + format_fixed(c.start_x, 2) + ", " + format_fixed(c.start_y, 2) + ") to (" +
                                    format_fixed(c.goal_x, 2) + ", " + format_fixed(c.goal_y, 2) + "): " +
                                    plan_status_reason(r.status),
                                label, 0, "query");
    row.expanded_total = r.expanded;
    row.expanded_mean = static_cast<double>(r.expanded);
    row.cost_m = r.cost;
  }
  const SampleStats s = sample_stats(ms);
  row.median_ms = s.median;
  row.mean_ms = s.mean;
  return row;
}

}  // namespace

RenTable1Result run_ren_table1(const RenTable1Config& c) {
  c.validate();
  RenTable1Result result;
  result.config = c;
  for (const auto& [label, file] : {std::pair<std::string, std::string>{"empty", c.empty_room}, {"obstacles", c.obstacle_room}}) {
    const OccupancyGrid map = read_ros_map(file);
    for (const char* planner : kPlanners) result.rows.push_back(single_query(label, map, planner, c));
  }
  if (c.queries > 0) {
    const OccupancyGrid map = read_ros_map(c.indoor_map);
    // Free cells beyond the inflation radius (the planners' own rule decides the edge cases: a
    // query from a cell they call blocked is unreachable for both).
    std::vector<Cell> free;
    const std::vector<double> d = obstacle_distance_m(map);
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x)
        if (map.state(x, y) == CellState::Free && d[map.geometry().index(x, y)] > c.inflation_m) free.push_back({x, y});
    if (free.size() < 2) throw Error("fewer than two free cells", c.indoor_map, 0, "--indoor-map");
    Rng rng(c.seed);
    std::vector<std::pair<Cell, Cell>> queries;
    for (int q = 0; q < c.queries; ++q) {
      const Cell a = free[static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(free.size()) - 1))];
      const Cell b = free[static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(free.size()) - 1))];
      queries.emplace_back(a, b);
    }
    std::vector<std::vector<double>> costs(2);
    for (std::size_t k = 0; k < 2; ++k) {
      RenTable1Row row;
      row.map = "indoor";
      row.planner = kPlanners[k];
      const double t0 = thread_cpu_s();
      const auto p = make_grid_planner(kPlanners[k], map, options_for(c.inflation_m));
      row.inflation_ms = (thread_cpu_s() - t0) * 1e3;
      std::vector<double> ms;
      double cost_sum = 0.0;
      int found = 0;
      for (const auto& [a, b] : queries) {
        const double s = thread_cpu_s();
        const PlanResult r = p->plan(a, b);
        ms.push_back((thread_cpu_s() - s) * 1e3);
        row.expanded_total += r.expanded;
        costs[k].push_back(r.found() ? r.cost : -1.0);
        if (r.found()) {
          cost_sum += r.cost;
          ++found;
        }
      }
      row.queries = static_cast<int>(queries.size());
      row.expanded_mean = static_cast<double>(row.expanded_total) / static_cast<double>(queries.size());
      row.cost_m = found ? cost_sum / found : 0.0;
      const SampleStats s = sample_stats(ms);
      row.median_ms = s.median;
      row.mean_ms = s.mean;
      result.rows.push_back(row);
    }
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const double a = costs[0][q], b = costs[1][q];
      if (a < 0.0 && b < 0.0) ++result.unreachable;
      else if (a < 0.0 || b < 0.0 || std::abs(a - b) > 1e-9 * std::max(1.0, a)) ++result.cost_mismatches;
    }
  }
  return result;
}

std::string ren_table1_markdown(const RenTable1Result& r) {
  const RenTable1Config& c = r.config;
  std::string s = "# Ren et al. 2022 Table 1: A* against Dijkstra\n\n";
  s += "From (" + format_fixed(c.start_x, 1) + ", " + format_fixed(c.start_y, 1) + ") m to (" + format_fixed(c.goal_x, 1) + ", " +
       format_fixed(c.goal_y, 1) + ") m in a 20 m x 20 m room at 0.05 m, inflated by " + format_fixed(c.inflation_m, 2) +
       " m; search time = thread CPU time of the search alone (median of " + std::to_string(c.repeats) +
       " repeats; the inflation is built once per map and shown apart). The paper's times are ROS wall times of the "
       "whole planner call (map handling and publishing included).\n\n";
  s += "| map | planner | queries | nodes expanded (mean) | path cost (m) | search median (ms) | search mean (ms) | inflation (ms) |\n";
  s += "|---|---|---|---|---|---|---|---|\n";
  for (const RenTable1Row& x : r.rows)
    s += "| " + x.map + " | " + x.planner + " | " + std::to_string(x.queries) + " | " + format_fixed(x.expanded_mean, 0) + " | " +
         format_fixed(x.cost_m, 3) + " | " + format_fixed(x.median_ms, 3) + " | " + format_fixed(x.mean_ms, 3) + " | " +
         format_fixed(x.inflation_ms, 2) + " |\n";
  s += "\nPaper: Dijkstra 2.8 s (empty) / 3.8 s (obstacles), A* 1.9 s / 2.1 s.\n";
  if (c.queries > 0)
    s += "Random queries on the indoor map: " + std::to_string(r.cost_mismatches) + " cost mismatches between the planners, " +
         std::to_string(r.unreachable) + " unreachable (both agree).\n";
  return s;
}

std::string ren_table1_json(const RenTable1Result& r) {
  nlohmann::ordered_json j;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const RenTable1Row& x : r.rows)
    rows.push_back({{"map", x.map}, {"planner", x.planner}, {"queries", x.queries}, {"expanded_mean", x.expanded_mean},
                    {"expanded_total", x.expanded_total}, {"cost_m", x.cost_m}, {"median_ms", x.median_ms},
                    {"mean_ms", x.mean_ms}, {"inflation_ms", x.inflation_ms}});
  j["rows"] = std::move(rows);
  j["cost_mismatches"] = r.cost_mismatches;
  j["unreachable"] = r.unreachable;
  return j.dump(2) + "\n";
}

std::string ren_table1_csv(const RenTable1Result& r) {
  std::string s = "map,planner,queries,expanded_mean,expanded_total,cost_m,median_ms,mean_ms,inflation_ms\n";
  for (const RenTable1Row& x : r.rows)
    s += x.map + ',' + x.planner + ',' + std::to_string(x.queries) + ',' + format_fixed6(x.expanded_mean) + ',' +
         std::to_string(x.expanded_total) + ',' + format_fixed6(x.cost_m) + ',' + format_fixed6(x.median_ms) + ',' +
         format_fixed6(x.mean_ms) + ',' + format_fixed6(x.inflation_ms) + '\n';
  return s;
}

}  // namespace starnav
