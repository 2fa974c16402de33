#include "starnav/experiment/metrics.hpp"

namespace starnav {

const std::vector<MetricDef>& metric_catalog() {
  static const std::vector<MetricDef> all = {
      // starnav bench nav: one navigation run per seed and planner (harness/navigation_run.hpp).
      {"nav", "success", "1", "1 when the robot arrived within the goal tolerance, else 0"},
      {"nav", "time_to_goal_s", "s", "simulated time to arrival (runs that arrived only)"},
      {"nav", "duration_s", "s", "simulated time of the run (to arrival, no path or the timeout)"},
      {"nav", "distance_m", "m", "XY path length driven"},
      {"nav", "plans", "count", "plans made (the first included)"},
      {"nav", "replans", "count", "plans after the first"},
      {"nav", "expanded_total", "count", "nodes the planner expanded over every plan"},
      {"nav", "replan_expanded", "count", "nodes expanded over the replans (first plan excluded)"},
      {"nav", "astar_replan_expanded", "count", "compare_astar: A* from scratch over the same replans, robot to goal"},
      {"nav", "astar_backward_replan_expanded", "count", "compare_astar: the same, goal to robot (D* Lite's direction)"},
      {"nav", "expansion_ratio", "ratio", "astar_replan_expanded / replan_expanded (D* Lite's saving)"},
      {"nav", "collisions", "count", "collision episodes of the vehicle"},
      {"nav", "deviation_mean_m", "m", "mean distance from base_link to the path being followed, every step"},
      {"nav", "deviation_max_m", "m", "largest such distance"},
      {"nav", "goal_distance_m", "m", "distance to the goal at the end"},
      {"nav", "wall_s", "s", "wall-clock time of the run", true},
      {"nav", "real_time_factor", "ratio", "simulated seconds per wall second", true},
      // starnav bench movingai: MovingAI scenario instances per map and planner (docs/benchmarks.md).
      {"movingai", "instances", "count", "instances run"},
      {"movingai", "unsolvable", "count", "instances without a path (published or found)"},
      {"movingai", "solved", "count", "instances with a path"},
      {"movingai", "exact", "count", "solved instances whose cost equals the published optimum (to its rounding)"},
      {"movingai", "shorter", "count", "instances cheaper than the published optimum beyond its rounding (a bug if ever > 0)"},
      {"movingai", "max_abs_error", "cells", "largest |cost - published optimum|"},
      {"movingai", "max_suboptimality", "ratio", "largest cost / published optimum - 1"},
      {"movingai", "mean_suboptimality", "ratio", "mean of cost / published optimum - 1 over the solved instances"},
      {"movingai", "total_expanded", "count", "nodes expanded over every instance"},
      {"movingai", "total_generated", "count", "nodes generated over every instance"},
      {"movingai", "median_time_us", "us", "median over instances of each instance's median query time", true},
      {"movingai", "mean_time_us", "us", "mean over instances of each instance's median query time", true},
      {"movingai", "total_time_ms", "ms", "sum of the instances' median query times", true},
      {"movingai", "expansions_per_s", "1/s", "total_expanded per second of query time", true},
      {"movingai", "preprocess_ms", "ms", "per-map preprocessing (JPS+ jump tables)", true},
      // starnav bench ablation: Ou et al. 2022 Table 2, per query and variant ("per_query") and as
      // means over the queries every variant of a table solved ("mean").
      {"ablation", "time_ms", "ms", "search time: the least thread CPU time of the repeats (mean: over the common queries)", true},
      {"ablation", "wall_ms", "ms", "median wall time of the repeats", true},
      {"ablation", "expanded", "count", "nodes expanded (mean: over the common queries)"},
      {"ablation", "generated", "count", "nodes generated"},
      {"ablation", "tir_percent", "%", "Tir: % less search time than A* on the same query and table (mean: of the per-query figures)", true},
      {"ablation", "enr_percent", "%", "Enr: % fewer expansions than A* on the same query and table (mean: of the per-query figures)"},
      {"ablation", "tir_total_percent", "%", "Tir of the summed search times over the common queries", true},
      {"ablation", "enr_total_percent", "%", "Enr of the summed expansions over the common queries"},
      {"ablation", "solved", "count", "queries this variant solved"},
      {"ablation", "common", "count", "queries every variant of the table solved (the means' sample)"},
      {"ablation", "cost", "cells or m", "path cost in the planner's own terms (steering cost included)"},
      {"ablation", "length", "cells or m", "path length (cells on MovingAI maps, metres on map_server maps)"},
      {"ablation", "vertices", "count", "vertices of the returned path"},
      {"ablation", "turning_points", "count", "vertices where the path changes direction"},
      {"ablation", "vertices_los", "count", "vertices after line-of-sight smoothing of the returned path"},
      {"ablation", "turning_points_los", "count", "turning points after line-of-sight smoothing"},
      {"ablation", "turn_total_rad", "rad", "sum of the absolute heading changes along the path"},
      {"ablation", "turn_max_rad", "rad", "largest heading change at one vertex"},
      {"ablation", "clearance_min", "cells or m", "least distance from the path to an obstacle of the original map (null: no obstacle)"},
      {"ablation", "clearance_mean", "cells or m", "mean of that distance along the path"},
      {"ablation", "smoothness", "rad2/cell or rad2/m", "sum of squared heading changes divided by the length (plan/path_metrics.hpp)"},
      // starnav bench terrain: Liu et al. 2024 Tables 2 and 3, per terrain and planner, their
      // summaries over terrains (n, mean, sd, min, max) and IA*'s pairwise comparisons.
      {"terrain", "cost", "1", "the planner's own path cost (metres for OA* and AOEA*, the sum of Liu move costs for IA*)"},
      {"terrain", "length_2d_m", "m", "horizontal path length"},
      {"terrain", "lv_m", "m", "lv: 3D path length over the terrain (Table 2)"},
      {"terrain", "av_rad", "rad", "av: mean slope atan(h / d) over the moves with both ends observed (Table 2)"},
      {"terrain", "hv_m", "m", "hv: mean height difference |z2 - z1| over those moves (Table 2)"},
      {"terrain", "sv_m2", "m2", "Sv: mean ruggedness S (3x3 height variance) over the observed path cells (Table 2)"},
      {"terrain", "roll_mean_deg", "deg", "|mean of the signed roll| of the 0.6 m x 0.4 m footprint at the path nodes (Table 3)"},
      {"terrain", "roll_max_deg", "deg", "largest absolute roll (Table 3)"},
      {"terrain", "pitch_mean_deg", "deg", "|mean of the signed pitch| (Table 3)"},
      {"terrain", "pitch_max_deg", "deg", "largest absolute pitch (Table 3)"},
      {"terrain", "tilt_mean_deg", "deg", "mean tilt (angle between the body's z axis and the vertical)"},
      {"terrain", "tilt_max_deg", "deg", "largest tilt"},
      {"terrain", "roll_mean_abs_deg", "deg", "mean absolute roll"},
      {"terrain", "pitch_mean_abs_deg", "deg", "mean absolute pitch"},
      {"terrain", "moves_measured", "count", "moves whose slope and step were measured (both ends observed)"},
      {"terrain", "cells_measured", "count", "observed path cells (the sample of Sv)"},
      {"terrain", "attitude_nodes", "count", "path nodes where the footprint's attitude was valid"},
      {"terrain", "path_nodes", "count", "cells of the path"},
      {"terrain", "expanded", "count", "nodes expanded"},
      {"terrain", "generated", "count", "nodes generated"},
      {"terrain", "reopened", "count", "closed nodes reopened (IA* with the paper's inadmissible H)"},
      {"terrain", "observed_cells", "count", "observed cells of the terrain"},
      {"terrain", "cells_s_at_least_sy", "count", "observed cells with ruggedness S >= S_y (where the threshold can matter)"},
      {"terrain", "max_s_m2", "m2", "largest ruggedness S of the terrain"},
      {"terrain", "found", "count", "terrains where the planner found a path"},
      {"terrain", "terrains_all_found", "count", "terrains where all three planners found a path"},
      {"terrain", "terrains", "count", "terrains run (comparisons: terrains where both planners found a path)"},
      {"terrain", "ia_lower_av", "count", "comparison: terrains where IA*'s av is lower than the other planner's"},
      {"terrain", "ia_lower_hv", "count", "comparison: the same for hv"},
      {"terrain", "ia_lower_sv", "count", "comparison: the same for Sv"},
      {"terrain", "ia_shorter", "count", "comparison: terrains where IA*'s lv is shorter"},
      {"terrain", "ia_lower_tilt_mean", "count", "comparison: terrains where IA*'s mean tilt is lower"},
      {"terrain", "ia_lower_tilt_max", "count", "comparison: terrains where IA*'s largest tilt is lower"},
      {"terrain", "lv_change_pct", "%", "comparison: 100 (IA* / other - 1) of lv per terrain (summary over terrains)"},
      {"terrain", "av_change_pct", "%", "comparison: the same for av"},
      {"terrain", "hv_change_pct", "%", "comparison: the same for hv"},
      {"terrain", "sv_change_pct", "%", "comparison: the same for Sv"},
      {"terrain", "roll_mean_abs_change_pct", "%", "comparison: the same for the mean absolute roll"},
      {"terrain", "roll_max_change_pct", "%", "comparison: the same for the largest roll"},
      {"terrain", "pitch_mean_abs_change_pct", "%", "comparison: the same for the mean absolute pitch"},
      {"terrain", "pitch_max_change_pct", "%", "comparison: the same for the largest pitch"},
      {"terrain", "tilt_mean_change_pct", "%", "comparison: the same for the mean tilt"},
      {"terrain", "tilt_max_change_pct", "%", "comparison: the same for the largest tilt"},
      {"terrain", "lv_change_of_means_pct", "%", "comparison: 100 (sum of IA*'s lv / the other's - 1) over the terrains both solved"},
      {"terrain", "tilt_mean_change_of_means_pct", "%", "comparison: the same for the mean tilt"},
      {"terrain", "tilt_max_change_of_means_pct", "%", "comparison: the same for the largest tilt"},
      {"terrain", "analysis_ms_total", "ms", "timing.json: terrain analysis time over every terrain", true},
      {"terrain", "search_ms_total", "ms", "timing.json: a planner's search time over every terrain", true},
      {"terrain", "preprocess_ms_total", "ms", "timing.json: a planner's preprocessing time over every terrain", true},
  };
  return all;
}

const MetricDef* find_metric(const std::string& experiment, const std::string& name) {
  for (const MetricDef& m : metric_catalog())
    if (m.experiment == experiment && m.name == name) return &m;
  return nullptr;
}

std::string metrics_markdown() {
  std::string s =
      "# Metrics\n\n"
      "<!-- Generated by `starnav metrics --markdown` from src/starnav/experiment/metrics.cpp; do not edit by hand.\n"
      "     A test fails when this file and the catalogue differ. -->\n\n"
      "Every metric the `starnav bench` commands report, named once. Timing figures (marked) differ from run to\n"
      "run; everything else is deterministic for the same inputs and seeds.\n";
  std::string current;
  for (const MetricDef& m : metric_catalog()) {
    if (m.experiment != current) {
      current = m.experiment;
      s += "\n## `starnav bench " + current + "`\n\n| metric | unit | meaning |\n|---|---|---|\n";
    }
    s += "| `" + m.name + "` | " + m.unit + " | " + m.meaning + (m.wall_clock ? " (timing)" : "") + " |\n";
  }
  return s;
}

}  // namespace starnav
