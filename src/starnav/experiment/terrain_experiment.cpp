#include "starnav/experiment/terrain_experiment.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/experiment/detail/terrain_json.hpp"
#include "starnav/experiment/runner.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/experiment/terrain_report.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/terrain/terrain_generator.hpp"

namespace starnav {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

constexpr RoughTerrainPlannerKind kTerrainPlanners[3] = {RoughTerrainPlannerKind::OA, RoughTerrainPlannerKind::AOEA,
                                                         RoughTerrainPlannerKind::IA};
constexpr const char* kPlannerTitles[3] = {"OA*", "AOEA*", "IA*"};

using Stat = SampleStats;  // the tables use mean, sd, min and max

json terrain_stat_json(const Stat& s) {
  json j;
  j["n"] = s.n;
  j["mean"] = s.mean;
  j["sd"] = s.sd;
  j["min"] = s.min;
  j["max"] = s.max;
  return j;
}

// The metrics summarised, with their TerrainPathMetrics member.
struct TerrainMetricField {
  const char* key;
  double TerrainPathMetrics::*member;
  int precision;  // in the Markdown tables
};
constexpr TerrainMetricField kTable2[] = {{"lv_m", &TerrainPathMetrics::lv_m, 2},
                                   {"av_rad", &TerrainPathMetrics::av_rad, 3},
                                   {"hv_m", &TerrainPathMetrics::hv_m, 4},
                                   {"sv_m2", &TerrainPathMetrics::sv_m2, 5}};
constexpr TerrainMetricField kTable3[] = {{"roll_mean_deg", &TerrainPathMetrics::roll_mean_deg, 2},
                                   {"roll_max_deg", &TerrainPathMetrics::roll_max_deg, 2},
                                   {"pitch_mean_deg", &TerrainPathMetrics::pitch_mean_deg, 2},
                                   {"pitch_max_deg", &TerrainPathMetrics::pitch_max_deg, 2},
                                   {"tilt_mean_deg", &TerrainPathMetrics::tilt_mean_deg, 2},
                                   {"tilt_max_deg", &TerrainPathMetrics::tilt_max_deg, 2},
                                   {"roll_mean_abs_deg", &TerrainPathMetrics::roll_mean_abs_deg, 2},
                                   {"pitch_mean_abs_deg", &TerrainPathMetrics::pitch_mean_abs_deg, 2}};

// The map as a geometric scale model: distances (horizontal and vertical) times k.
ElevationMap scaled_model(const ElevationMap& m, double k) {
  GridGeometry g = m.geometry();
  g.resolution *= k;
  g.origin = Pose2(g.origin.x * k, g.origin.y * k, g.origin.yaw);
  ElevationMap out(g);
  const auto range = m.height_range();
  const double base = range ? range->min : 0.0;  // small numbers: heights above the lowest point
  for (int y = 0; y < m.height(); ++y)
    for (int x = 0; x < m.width(); ++x)
      if (m.observed_at(x, y))
        out.set_cell(x, y, (m.height_at(x, y) - base) * k, (m.min_height_at(x, y) - base) * k,
                     (m.max_height_at(x, y) - base) * k);
  return out;
}

Cell cell_of_point(const GridGeometry& g, const Vec2& p) {
  const Vec2 c = g.world_to_cell_continuous(p);
  if (!(std::abs(c.x()) < 1e9) || !(std::abs(c.y()) < 1e9)) return {-1, -1};
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

// The allowed cell nearest to `target` (cell coordinates), ties to the lower index; {-1, -1} if none.
Cell nearest_allowed(const GridGeometry& g, const Vec2& target, const std::vector<std::uint8_t>& allowed) {
  Cell best{-1, -1};
  double best_d = std::numeric_limits<double>::infinity();
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      if (!allowed[g.index(x, y)]) continue;
      const double dx = x + 0.5 - target.x(), dy = y + 0.5 - target.y();
      const double d = dx * dx + dy * dy;
      if (d < best_d) best_d = d, best = {x, y};
    }
  return best;
}

// The default endpoints of a --map (see the header comment).
void auto_endpoints(const TerrainAnalysis& t, Cell& start, Cell& goal) {
  const GridGeometry& g = t.geometry();
  std::vector<std::uint8_t> allowed(t.observed().size());
  bool any = false;
  for (std::size_t i = 0; i < allowed.size(); ++i) {
    allowed[i] = t.observed()[i] && !t.expanded_obstacle_mask()[i];
    any = any || allowed[i];
  }
  if (!any) allowed = t.observed();
  const double w = g.width, h = g.height;
  // Lower-left to upper-right, or lower-right to upper-left when that pair lies farther apart
  // (DEMs whose data run along the other diagonal, nodata around them).
  const Cell s1 = nearest_allowed(g, Vec2(0.05 * w, 0.05 * h), allowed);
  const Cell g1 = nearest_allowed(g, Vec2(0.95 * w, 0.95 * h), allowed);
  const Cell s2 = nearest_allowed(g, Vec2(0.95 * w, 0.05 * h), allowed);
  const Cell g2 = nearest_allowed(g, Vec2(0.05 * w, 0.95 * h), allowed);
  if (s1.x < 0) throw Error("no observed cell for a start or goal", {}, 0, "--map");
  auto d2 = [](Cell a, Cell b) { return double(a.x - b.x) * (a.x - b.x) + double(a.y - b.y) * (a.y - b.y); };
  const bool other = d2(s2, g2) > d2(s1, g1);
  start = other ? s2 : s1;
  goal = other ? g2 : g1;
}

std::string pm(const Stat& s, int precision) {
  if (s.n == 0) return "-";
  return format_fixed(s.mean, precision) + " ± " + format_fixed(s.sd, precision);
}

// Pairwise comparison of IA* (b) against another planner (a) over the terrains both solved.
struct Comparison {
  std::size_t n = 0;
  std::size_t ia_lower_av = 0, ia_lower_hv = 0, ia_lower_sv = 0, ia_shorter = 0, ia_lower_tilt_mean = 0,
              ia_lower_tilt_max = 0;
  Stat lv_change_pct, av_change_pct, hv_change_pct, sv_change_pct, roll_mean_change_pct, roll_max_change_pct,
      pitch_mean_change_pct, pitch_max_change_pct, tilt_mean_change_pct, tilt_max_change_pct;
  // Change of the means (mean over terrains of IA* / mean of the other - 1), %.
  double lv_change_of_means_pct = 0.0, tilt_mean_change_of_means_pct = 0.0, tilt_max_change_of_means_pct = 0.0;
};

double change_pct(double other, double ia) { return other != 0.0 ? 100.0 * (ia / other - 1.0) : 0.0; }

Comparison compare(const std::vector<TerrainOutcome>& results, int other) {
  Comparison c;
  std::vector<double> lv, av, hv, sv, rm, rx, pm_, px, tm, tx;
  double sum_lv_o = 0, sum_lv_i = 0, sum_tm_o = 0, sum_tm_i = 0, sum_tx_o = 0, sum_tx_i = 0;
  for (const TerrainOutcome& r : results) {
    const TerrainRun& a = r.runs[other];
    const TerrainRun& b = r.runs[2];
    if (!a.found || !b.found) continue;
    ++c.n;
    const TerrainPathMetrics &ma = a.metrics, &mb = b.metrics;
    c.ia_lower_av += mb.av_rad < ma.av_rad;
    c.ia_lower_hv += mb.hv_m < ma.hv_m;
    c.ia_lower_sv += mb.sv_m2 < ma.sv_m2;
    c.ia_shorter += mb.lv_m < ma.lv_m;
    c.ia_lower_tilt_mean += mb.tilt_mean_deg < ma.tilt_mean_deg;
    c.ia_lower_tilt_max += mb.tilt_max_deg < ma.tilt_max_deg;
    lv.push_back(change_pct(ma.lv_m, mb.lv_m));
    av.push_back(change_pct(ma.av_rad, mb.av_rad));
    hv.push_back(change_pct(ma.hv_m, mb.hv_m));
    sv.push_back(change_pct(ma.sv_m2, mb.sv_m2));
    rm.push_back(change_pct(ma.roll_mean_abs_deg, mb.roll_mean_abs_deg));
    rx.push_back(change_pct(ma.roll_max_deg, mb.roll_max_deg));
    pm_.push_back(change_pct(ma.pitch_mean_abs_deg, mb.pitch_mean_abs_deg));
    px.push_back(change_pct(ma.pitch_max_deg, mb.pitch_max_deg));
    tm.push_back(change_pct(ma.tilt_mean_deg, mb.tilt_mean_deg));
    tx.push_back(change_pct(ma.tilt_max_deg, mb.tilt_max_deg));
    sum_lv_o += ma.lv_m, sum_lv_i += mb.lv_m;
    sum_tm_o += ma.tilt_mean_deg, sum_tm_i += mb.tilt_mean_deg;
    sum_tx_o += ma.tilt_max_deg, sum_tx_i += mb.tilt_max_deg;
  }
  c.lv_change_pct = sample_stats(lv);
  c.av_change_pct = sample_stats(av);
  c.hv_change_pct = sample_stats(hv);
  c.sv_change_pct = sample_stats(sv);
  c.roll_mean_change_pct = sample_stats(rm);
  c.roll_max_change_pct = sample_stats(rx);
  c.pitch_mean_change_pct = sample_stats(pm_);
  c.pitch_max_change_pct = sample_stats(px);
  c.tilt_mean_change_pct = sample_stats(tm);
  c.tilt_max_change_pct = sample_stats(tx);
  c.lv_change_of_means_pct = change_pct(sum_lv_o, sum_lv_i);
  c.tilt_mean_change_of_means_pct = change_pct(sum_tm_o, sum_tm_i);
  c.tilt_max_change_of_means_pct = change_pct(sum_tx_o, sum_tx_i);
  return c;
}

json comparison_json(const Comparison& c, const char* other) {
  json j;
  j["against"] = other;
  j["terrains"] = c.n;
  j["ia_lower_av"] = c.ia_lower_av;
  j["ia_lower_hv"] = c.ia_lower_hv;
  j["ia_lower_sv"] = c.ia_lower_sv;
  j["ia_shorter"] = c.ia_shorter;
  j["ia_lower_tilt_mean"] = c.ia_lower_tilt_mean;
  j["ia_lower_tilt_max"] = c.ia_lower_tilt_max;
  j["lv_change_pct"] = terrain_stat_json(c.lv_change_pct);
  j["av_change_pct"] = terrain_stat_json(c.av_change_pct);
  j["hv_change_pct"] = terrain_stat_json(c.hv_change_pct);
  j["sv_change_pct"] = terrain_stat_json(c.sv_change_pct);
  j["roll_mean_abs_change_pct"] = terrain_stat_json(c.roll_mean_change_pct);
  j["roll_max_change_pct"] = terrain_stat_json(c.roll_max_change_pct);
  j["pitch_mean_abs_change_pct"] = terrain_stat_json(c.pitch_mean_change_pct);
  j["pitch_max_change_pct"] = terrain_stat_json(c.pitch_max_change_pct);
  j["tilt_mean_change_pct"] = terrain_stat_json(c.tilt_mean_change_pct);
  j["tilt_max_change_pct"] = terrain_stat_json(c.tilt_max_change_pct);
  j["lv_change_of_means_pct"] = c.lv_change_of_means_pct;
  j["tilt_mean_change_of_means_pct"] = c.tilt_mean_change_of_means_pct;
  j["tilt_max_change_of_means_pct"] = c.tilt_max_change_of_means_pct;
  return j;
}

// Stats of one metric of planner p over the terrains selected by `use`.
template <class Use>
Stat metric_stat(const std::vector<TerrainOutcome>& results, int p, double TerrainPathMetrics::*member, Use use) {
  std::vector<double> v;
  for (const TerrainOutcome& r : results)
    if (use(r)) v.push_back(r.runs[p].metrics.*member);
  return sample_stats(v);
}

bool all_found(const TerrainOutcome& r) { return r.runs[0].found && r.runs[1].found && r.runs[2].found; }

void write_tables(std::ostream& md, const std::vector<TerrainOutcome>& results, bool common, std::size_t terrains) {
  std::size_t n_common = 0;
  for (const TerrainOutcome& r : results) n_common += all_found(r);
  auto use_for = [&](int p) {
    return [common, p](const TerrainOutcome& r) { return common ? all_found(r) : r.runs[p].found; };
  };
  md << "| planner | paths | lv (m) | av (rad) | hv (m) | Sv (m²) |\n|---|---:|---:|---:|---:|---:|\n";
  for (int p = 0; p < 3; ++p) {
    std::size_t found = 0;
    for (const TerrainOutcome& r : results) found += r.runs[p].found;
    md << "| " << kPlannerTitles[p] << " | " << (common ? n_common : found) << " / " << terrains;
    for (const TerrainMetricField& f : kTable2) md << " | " << pm(metric_stat(results, p, f.member, use_for(p)), f.precision);
    md << " |\n";
  }
  md << "\n| planner | roll mean (°) | roll max (°) | pitch mean (°) | pitch max (°) | tilt mean (°) | tilt max (°) | "
        "mean abs roll (°) | mean abs pitch (°) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (int p = 0; p < 3; ++p) {
    md << "| " << kPlannerTitles[p];
    for (const TerrainMetricField& f : kTable3) md << " | " << pm(metric_stat(results, p, f.member, use_for(p)), f.precision);
    md << " |\n";
  }
  md << "\n";
}

void write_comparison(std::ostream& md, const Comparison& c, const char* other) {
  if (c.n == 0) {
    md << "- **IA\\* vs " << other << "**: no terrain where both found a path.\n";
    return;
  }
  md << "- **IA\\* vs " << other << "** (" << c.n << " terrains where both found a path): IA\\* has the lower av on "
     << c.ia_lower_av << ", lower hv on " << c.ia_lower_hv << ", lower Sv on " << c.ia_lower_sv << "; it is shorter (lv) on "
     << c.ia_shorter << ". Change of IA\\* against " << other << " (mean ± sd over terrains): lv "
     << pm(c.lv_change_pct, 1) << " %, av " << pm(c.av_change_pct, 1) << " %, hv " << pm(c.hv_change_pct, 1)
     << " %, Sv " << pm(c.sv_change_pct, 1) << " %; tilt mean " << pm(c.tilt_mean_change_pct, 1) << " %, tilt max "
     << pm(c.tilt_max_change_pct, 1) << " %, mean abs roll " << pm(c.roll_mean_change_pct, 1) << " %, roll max "
     << pm(c.roll_max_change_pct, 1) << " %, mean abs pitch " << pm(c.pitch_mean_change_pct, 1) << " %, pitch max "
     << pm(c.pitch_max_change_pct, 1) << " % (lower tilt mean on " << c.ia_lower_tilt_mean << ", lower tilt max on "
     << c.ia_lower_tilt_max << "). Of the means: lv " << format_fixed(c.lv_change_of_means_pct, 1) << " %, tilt mean "
     << format_fixed(c.tilt_mean_change_of_means_pct, 1) << " %, tilt max "
     << format_fixed(c.tilt_max_change_of_means_pct, 1) << " %.\n";
}

json run_json(const TerrainRun& r) {
  json j;
  j["found"] = r.found;
  if (!r.found) j["reason"] = r.reason;
  j["cost"] = r.found ? json(r.cost) : json(nullptr);
  j["length_2d_m"] = r.found ? json(r.length_2d_m) : json(nullptr);
  detail::add_terrain_metrics_json(j, r.found ? &r.metrics : nullptr);
  j["path_nodes"] = r.path.size();
  j["expanded"] = r.expanded;
  j["generated"] = r.generated;
  j["reopened"] = r.reopened;
  return j;
}

}  // namespace

const RoughTerrainPlannerKind* terrain_experiment_planners() { return kTerrainPlanners; }
const char* terrain_planner_title(int index) { return kPlannerTitles[index]; }

std::string terrain_file_stem(const std::string& name) {
  std::string s = name;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return s;
}

TerrainExperimentResult run_terrain_experiment(const TerrainExperimentConfig& c) {
  const bool from_map = !c.map.empty();
  if (from_map == (c.generate > 0)) throw Error("give exactly one of --map FILE and --generate N", {}, 0, "--map");
  if (!from_map && !(c.amplitude > 0 && std::isfinite(c.amplitude)))
    throw Error("expected a number > 0", {}, 0, "--amplitude");
  if (!(c.model_resolution >= 0) || !std::isfinite(c.model_resolution))
    throw Error("expected a cell size in metres > 0", {}, 0, "--model-resolution");
  if (!from_map && c.model_resolution > 0) throw Error("applies to --map only", {}, 0, "--model-resolution");
  if (c.start_m.has_value() != c.goal_m.has_value())
    throw Error("give both --start and --goal, or neither", {}, 0, c.start_m ? "--goal" : "--start");
  c.options.validate();

  TerrainExperimentResult res;
  res.config = c;
  if (from_map) {
    const LoadedMap loaded = load_map(c.map);
    if (!loaded.is_elevation()) throw Error("is an occupancy map; bench terrain needs an elevation map", c.map, 0, "--map");
    TerrainOutcome t;
    t.name = fs::path(c.map).stem().string();
    t.map = loaded.elevation();
    if (c.model_resolution > 0) {
      res.model_scale = c.model_resolution / t.map.resolution();
      t.map = scaled_model(t.map, res.model_scale);
    }
    res.terrains.push_back(std::move(t));
  } else {
    for (int i = 0; i < c.generate; ++i) {
      HillsOptions h;
      h.seed = c.seed + static_cast<std::uint64_t>(i);
      h.amplitude = c.amplitude;
      TerrainOutcome t;
      t.seed = h.seed;
      t.name = "hills_seed" + std::to_string(h.seed);
      t.map = generate_hills(h);
      res.terrains.push_back(std::move(t));
    }
  }

  const RoughTerrainPlannerOptions& options = c.options;
  const Vec2 start_m = c.start_m.value_or(Vec2(0.5, 0.5));
  const Vec2 goal_m = c.goal_m.value_or(Vec2(9.5, 9.5));
  ExperimentGrid grid;
  for (const TerrainOutcome& t : res.terrains) grid.instances.push_back(t.name);
  for (int p = 0; p < 3; ++p) grid.variants.push_back({kPlannerTitles[p], {}});
  grid.seeds = {0};
  // A terrain's analysis is made once, by its first trial, and serves its three planners.
  std::shared_ptr<const TerrainAnalysis> analysis;
  std::size_t analysed = res.terrains.size();
  auto prepare = [&](const TrialKey& key) {
    if (key.instance == analysed) return analysis;
    analysed = key.instance;
    TerrainOutcome& out = res.terrains[key.instance];
    TerrainAnalysisOptions ao;
    ao.unobserved = options.unobserved;
    ao.thresholds = options.cost;
    ao.robot_radius_m = options.robot_radius_m;
    const auto t0 = std::chrono::steady_clock::now();
    analysis = std::make_shared<const TerrainAnalysis>(out.map, ao);
    out.analysis_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    for (std::size_t i = 0; i < analysis->ruggedness().size(); ++i) {
      if (!analysis->observed()[i]) continue;
      ++out.observed_cells;
      out.cells_at_sy += analysis->ruggedness()[i] >= options.cost.s_y;
      out.max_s_m2 = std::max(out.max_s_m2, analysis->ruggedness()[i]);
    }
    const GridGeometry& g = out.map.geometry();
    if (c.start_m || !from_map) {
      out.start = cell_of_point(g, start_m);
      out.goal = cell_of_point(g, goal_m);
      // A query off the map is the user's mistake, not a row of failed plans.
      for (const auto& [cell, point, flag] : {std::tuple{out.start, start_m, "--start"}, std::tuple{out.goal, goal_m, "--goal"}})
        if (!g.contains(cell)) {
          std::string where = "(";  // appended: g++ 12 warns falsely (-Wrestrict) on a literal + string in some inlinings
          where += format_readable(point.x(), 6) + ", " + format_readable(point.y(), 6) + ") m is outside the map " + out.name;
          throw Error(where, {}, 0, flag);
        }
    } else {
      auto_endpoints(*analysis, out.start, out.goal);
    }
    out.start_m = g.contains(out.start) ? g.cell_center(out.start) : start_m;
    out.goal_m = g.contains(out.goal) ? g.cell_center(out.goal) : goal_m;
    if (key.instance < c.figures)
      for (std::size_t i = 0; i < analysis->expanded_obstacle_mask().size(); ++i)
        if (analysis->expanded_obstacle_mask()[i] && analysis->observed()[i])
          out.figure_obstacles.push_back(g.cell_of_index(i));
    return analysis;
  };
  auto run = [&](const std::shared_ptr<const TerrainAnalysis>& a, const TrialKey& key) {
    const TerrainOutcome& out = res.terrains[key.instance];
    RoughTerrainPlanner planner(kTerrainPlanners[key.variant], a, options);
    const PlanResult r = planner.plan(out.start, out.goal);
    TerrainRun run;
    run.found = r.found();
    run.expanded = r.expanded;
    run.generated = r.generated;
    run.reopened = planner.reopened();
    run.time_ms = r.time_ms;
    run.preprocess_ms = planner.preprocess_ms();
    if (!run.found) {
      run.reason = plan_status_reason(r.status);
      return run;
    }
    run.cost = r.cost;
    run.length_2d_m = r.length;
    run.path = r.path_cells;
    run.metrics = terrain_path_metrics(*a, run.path, {}, key.instance < c.figures ? &run.samples : nullptr);
    return run;
  };
  ExperimentProgress progress;
  if (c.progress)
    progress = [&](std::size_t done, std::size_t total, const TrialKey& next) {
      // Per terrain: the trials come in threes.
      if (done % 3 == 0) c.progress(done / 3, total / 3, done == total ? "done" : res.terrains[next.instance].name);
    };
  const auto trials = run_experiment<std::shared_ptr<const TerrainAnalysis>, TerrainRun>(grid, prepare, run, progress);
  for (const Trial<TerrainRun>& t : trials) {
    TerrainRun& run = res.terrains[t.key.instance].runs[t.key.variant];
    run = t.record;
    if (!t.completed) run.reason = t.error;
  }
  return res;
}

namespace {

struct TerrainReport {
  std::string markdown;
  json document;
};

TerrainReport terrain_report(const TerrainExperimentResult& res) {
  const TerrainExperimentConfig& c = res.config;
  const RoughTerrainPlannerOptions& options = c.options;
  const bool from_map = !c.map.empty();
  const bool given = c.start_m.has_value();
  const Vec2 start_m = c.start_m.value_or(Vec2(0.5, 0.5));
  const Vec2 goal_m = c.goal_m.value_or(Vec2(9.5, 9.5));
  const Comparison vs_oa = compare(res.terrains, 0);
  const Comparison vs_aoea = compare(res.terrains, 1);
  std::size_t n_common = 0;
  for (const TerrainOutcome& r : res.terrains) n_common += all_found(r);

  // Markdown.
  const ElevationMap& first = res.terrains.front().map;
  std::ostringstream md;
  md << "## Rough-terrain planning (Liu et al. 2024, Tables 2 and 3): ";
  if (from_map) md << fs::path(c.map).filename().string() << "\n\n";
  else md << c.generate << " generated hills terrains\n\n";
  if (from_map) {
    md << "Map " << c.map << ": " << first.width() << " x " << first.height() << " cells";
    if (res.model_scale != 1.0)
      md << ", planned as a scale model with " << format_fixed(first.resolution(), 3) << " m cells (every distance x "
         << format_fixed(res.model_scale, 6) << "; results in model metres)";
    else md << " of " << format_fixed(first.resolution(), 3) << " m";
    md << ". Start (" << format_fixed(res.terrains[0].start_m.x(), 2) << ", " << format_fixed(res.terrains[0].start_m.y(), 2)
       << ") m, goal (" << format_fixed(res.terrains[0].goal_m.x(), 2) << ", " << format_fixed(res.terrains[0].goal_m.y(), 2)
       << ") m" << (given ? "" : " (the cells free of AOEA* obstacles nearest to the points 5 % in from two opposite corners)")
       << ".\n\n";
  } else {
    md << "Hills terrains of 10 m x 10 m at 0.1 m (`starnav terrain generate --kind hills`), amplitude "
       << format_fixed(c.amplitude, 2) << ", seeds " << c.seed << ".." << c.seed + static_cast<std::uint64_t>(c.generate) - 1
       << "; start (" << format_fixed(start_m.x(), 2) << ", " << format_fixed(start_m.y(), 2) << ") m, goal ("
       << format_fixed(goal_m.x(), 2) << ", " << format_fixed(goal_m.y(), 2) << ") m.\n\n";
  }
  md << "Parameters: h_y " << options.cost.h_y << " m, a_y " << options.cost.a_y << " rad, S_y " << options.cost.s_y
     << " m², w_s/w_e/w_r " << options.cost.w_s << "/" << options.cost.w_e << "/" << options.cost.w_r << ", w1/w2 "
     << options.cost.w1 << "/" << options.cost.w2 << ", g per " << (options.cost.cost_per_metre ? "metre" : "move")
     << "; IA* heuristic " << liu_heuristic_name(options.heuristic)
     << (options.heuristic == LiuHeuristic::Paper ? " (H = distance, with reopening: the paper's Algorithm 1)"
                                                  : " (H = w2 x distance, optimal)")
     << "; AOEA* obstacle expansion " << options.robot_radius_m << " m; unobserved cells "
     << unobserved_policy_name(options.unobserved) << "; footprint 0.6 m x 0.4 m.\n\n";
  md << "### Table 2 and 3 layout: terrains where all three planners found a path (" << n_common << " of "
     << res.terrains.size() << "), mean ± sd\n\n";
  write_tables(md, res.terrains, true, res.terrains.size());
  md << "### Each planner over the terrains where it found a path\n\n";
  write_tables(md, res.terrains, false, res.terrains.size());
  md << "Paper (one terrain, for orientation): OA* lv 14.38 m, av 0.58 rad, hv 0.097 m, Sv 0.049 m²; AOEA* 19.32, "
        "0.31, 0.034, 0.014; IA* 17.54, 0.26, 0.027, 0.013.\n\n";
  md << "### Comparisons (the paper's claims)\n\n";
  write_comparison(md, vs_oa, "OA\\*");
  write_comparison(md, vs_aoea, "AOEA\\*");
  {
    std::size_t cells = 0, at_sy = 0, terrains_at_sy = 0;
    double max_s = 0.0;
    for (const TerrainOutcome& r : res.terrains) {
      cells += r.observed_cells;
      at_sy += r.cells_at_sy;
      terrains_at_sy += r.cells_at_sy > 0;
      max_s = std::max(max_s, r.max_s_m2);
    }
    md << "\nRuggedness threshold: " << at_sy << " of " << cells << " observed cells (on " << terrains_at_sy << " of "
       << res.terrains.size() << " terrains) have S >= S_y = " << options.cost.s_y << " m²; the largest S is "
       << format_fixed(max_s, 5) << " m².\n";
  }
  md << "\nNo path: ";
  for (int p = 0; p < 3; ++p) {
    std::size_t missing = 0;
    for (const TerrainOutcome& r : res.terrains) missing += !r.runs[p].found;
    md << kPlannerTitles[p] << " " << missing << (p < 2 ? ", " : ".\n\n");
  }

  json j;
  j["benchmark"] = "terrain";
  j["paper"] = "Liu et al. 2024, Tables 2 and 3";
  if (from_map) {
    j["map"] = c.map;
    j["model_scale"] = res.model_scale;
  } else {
    j["generate"] = {{"kind", "hills"}, {"terrains", c.generate}, {"seed", c.seed}, {"amplitude", c.amplitude},
                     {"size_m", {10.0, 10.0}}, {"resolution", 0.1}};
  }
  j["width"] = first.width();
  j["height"] = first.height();
  j["resolution"] = first.resolution();
  j["endpoints"] = given ? "given" : (from_map ? "auto" : "paper");
  j["options"] = detail::terrain_options_json(options);
  j["footprint_m"] = {Footprint{}.length_m, Footprint{}.width_m};
  j["terrains"] = res.terrains.size();
  j["terrains_all_found"] = n_common;
  json planners = json::array();
  for (int p = 0; p < 3; ++p) {
    json pj;
    pj["planner"] = rough_terrain_planner_name(kTerrainPlanners[p]);
    std::size_t found = 0;
    for (const TerrainOutcome& r : res.terrains) found += r.runs[p].found;
    pj["found"] = found;
    json common, own;
    for (const TerrainMetricField& f : kTable2) {
      common[f.key] = terrain_stat_json(metric_stat(res.terrains, p, f.member, all_found));
      own[f.key] = terrain_stat_json(metric_stat(res.terrains, p, f.member, [p](const TerrainOutcome& r) { return r.runs[p].found; }));
    }
    for (const TerrainMetricField& f : kTable3) {
      common[f.key] = terrain_stat_json(metric_stat(res.terrains, p, f.member, all_found));
      own[f.key] = terrain_stat_json(metric_stat(res.terrains, p, f.member, [p](const TerrainOutcome& r) { return r.runs[p].found; }));
    }
    pj["all_found"] = common;
    pj["own_found"] = own;
    planners.push_back(pj);
  }
  j["planners"] = planners;
  j["comparisons"] = {comparison_json(vs_oa, "oa"), comparison_json(vs_aoea, "aoea")};
  json per = json::array();
  for (std::size_t i = 0; i < res.terrains.size(); ++i) {
    json t;
    t["name"] = res.terrains[i].name;
    if (!from_map) t["seed"] = res.terrains[i].seed;
    t["start_cell"] = {res.terrains[i].start.x, res.terrains[i].start.y};
    t["goal_cell"] = {res.terrains[i].goal.x, res.terrains[i].goal.y};
    t["start_m"] = {res.terrains[i].start_m.x(), res.terrains[i].start_m.y()};
    t["goal_m"] = {res.terrains[i].goal_m.x(), res.terrains[i].goal_m.y()};
    t["observed_cells"] = res.terrains[i].observed_cells;
    t["cells_s_at_least_sy"] = res.terrains[i].cells_at_sy;
    t["max_s_m2"] = res.terrains[i].max_s_m2;
    for (int p = 0; p < 3; ++p) t[rough_terrain_planner_name(kTerrainPlanners[p])] = run_json(res.terrains[i].runs[p]);
    per.push_back(t);
  }
  j["per_terrain"] = per;

  return {md.str(), j};
}

}  // namespace

std::string terrain_markdown(const TerrainExperimentResult& r) { return terrain_report(r).markdown; }

std::string terrain_json(const TerrainExperimentResult& r) { return terrain_report(r).document.dump(1) + "\n"; }

std::string terrain_full_markdown(const TerrainExperimentResult& res, std::size_t figures) {
  figures = std::min(figures, res.terrains.size());
  std::ostringstream full;
  full << terrain_markdown(res) << "### Per terrain\n\n| terrain | planner | found | lv (m) | av (rad) | hv (m) | Sv (m²) | tilt mean (°) | "
                      "tilt max (°) | expanded |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t i = 0; i < res.terrains.size(); ++i)
    for (int p = 0; p < 3; ++p) {
      const TerrainRun& r = res.terrains[i].runs[p];
      full << "| " << res.terrains[i].name << " | " << kPlannerTitles[p] << " | ";
      if (!r.found) {
        full << r.reason << " | - | - | - | - | - | - | " << r.expanded << " |\n";
        continue;
      }
      const TerrainPathMetrics& m = r.metrics;
      full << "yes | " << format_fixed(m.lv_m, 2) << " | " << format_fixed(m.av_rad, 3) << " | "
           << format_fixed(m.hv_m, 4) << " | " << format_fixed(m.sv_m2, 5) << " | " << format_fixed(m.tilt_mean_deg, 2)
           << " | " << format_fixed(m.tilt_max_deg, 2) << " | " << r.expanded << " |\n";
    }
  if (figures > 0) {
    full << "\nFigures (svg/): ";
    for (std::size_t i = 0; i < figures; ++i) {
      const std::string stem = terrain_file_stem(res.terrains[i].name);
      full << "[" << stem << " paths](svg/" << stem << "_paths.svg), attitude [roll](svg/" << stem << "_roll.svg) / [pitch](svg/"
           << stem << "_pitch.svg) / [tilt](svg/" << stem << "_tilt.svg)" << (i + 1 < figures ? "; " : ".\n");
    }
  }
  return full.str();
}

std::string terrain_timing_json(const TerrainExperimentResult& res) {
  double total_search_ms[3] = {0, 0, 0}, total_preprocess_ms[3] = {0, 0, 0}, total_analysis_ms = 0;
  for (const TerrainOutcome& t : res.terrains) {
    total_analysis_ms += t.analysis_ms;
    for (int p = 0; p < 3; ++p) {
      total_search_ms[p] += t.runs[p].time_ms;
      total_preprocess_ms[p] += t.runs[p].preprocess_ms;
    }
  }
  json timing;
  timing["analysis_ms_total"] = total_analysis_ms;
  for (int p = 0; p < 3; ++p)
    timing[rough_terrain_planner_name(kTerrainPlanners[p])] = {{"search_ms_total", total_search_ms[p]},
                                                        {"preprocess_ms_total", total_preprocess_ms[p]}};
  return timing.dump(1) + "\n";
}

void write_terrain_figures(const TerrainExperimentResult& r, std::size_t i, const std::string& stem) {
  const TerrainOutcome& t = r.terrains.at(i);
  std::vector<TerrainPathLayer> layers;
  for (int p = 0; p < 3; ++p) layers.push_back({kPlannerTitles[p], t.runs[p].found ? &t.runs[p].path : nullptr});
  write_terrain_paths_svg(stem + "_paths.svg", t.map, t.name + ": OA*, AOEA*, IA*", layers, t.figure_obstacles,
                          "AOEA* obstacles (expanded)", t.start, t.goal);
  std::vector<std::pair<std::string, const std::vector<AttitudeSample>*>> series;
  for (int p = 0; p < 3; ++p) series.push_back({kPlannerTitles[p], &t.runs[p].samples});
  write_attitude_profile_svg(stem + "_roll.svg", t.name + ": roll along the paths", AttitudeAngle::Roll, series);
  write_attitude_profile_svg(stem + "_pitch.svg", t.name + ": pitch along the paths", AttitudeAngle::Pitch, series);
  write_attitude_profile_svg(stem + "_tilt.svg", t.name + ": tilt along the paths", AttitudeAngle::Tilt, series);
}

}  // namespace starnav
