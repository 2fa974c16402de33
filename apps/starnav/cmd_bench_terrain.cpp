// starnav bench terrain: the experiment of Liu et al. 2024 (paper section 4, Tables 2 and 3,
// Figs. 6 and 8; docs/terrain.md, spec liu2024_rough_terrain.md section 7; write-up docs/papers/liu2024.md).
//
//   starnav bench terrain (--map FILE | --generate N [--seed S] [--amplitude A]) [--start X,Y --goal X,Y]
//                         [--model-resolution R] [planner flags as plan: --hy-m ... --unobserved]
//                         [--out DIR] [--json] [--svg-limit K] [--force] [--quiet]
//
// For every terrain (the map, or N hills terrains of 10 m x 10 m at 0.1 m with seeds S..S+N-1) it
// runs OA*, AOEA* and IA* (IA*: the paper's H with reopening unless --admissible) from start to
// goal and measures each path (terrain/terrain_path_metrics.hpp): lv, av, hv, Sv (Table 2) and the roll,
// pitch and tilt of the 0.6 m x 0.4 m footprint along it (Table 3: |mean| and max, degrees).
//
// Start and goal: (0.5, 0.5) and (9.5, 9.5) m on generated terrains, as the paper; on a --map the
// cells nearest (Euclidean, ties to the lower index) to the points 5 % of the map's width and height
// in from its lower-left and upper-right corners that are free in the AOEA* obstacle mask (so that
// every planner may start and end there), or the nearest observed cells when no cell is free; the
// lower-right / upper-left pair instead when it lies farther apart; --start/--goal override both.
//
// --model-resolution R plans on the map as a geometric scale model with R-metre cells: every
// horizontal and vertical distance is multiplied by R / resolution, so slopes are kept and the
// Table 1 thresholds and the robot (sized for 0.1 m cells) keep their proportion to the relief. A
// DEM with 10 m cells and 50 m of relief would otherwise have no move below h_y = 0.05 m. All
// results are then in model metres (JSON key model_scale; multiply lengths and heights by
// 1 / model_scale, Sv by its inverse square, for the real terrain).
//
// Summaries (mean, standard deviation, min, max) over the terrains where all three planners found
// a path (the paper's comparison) and over each planner's own successes; pairwise comparisons
// IA* vs OA* and IA* vs AOEA* over the terrains where both found one.
//
// Output: the Markdown report on stdout (--json: the JSON instead); with --out DIR also
// DIR/terrain.md (with the per-terrain table), DIR/terrain.json (deterministic: no times),
// DIR/timing.json (search and preprocessing times), and for the first K terrains (--svg-limit,
// default 3) DIR/svg/<terrain>_paths.svg (Fig. 6: hillshaded terrain, AOEA* obstacles, the three
// paths) and DIR/svg/<terrain>_{roll,pitch,tilt}.svg (Fig. 8: the angle along each path).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/terrain/terrain_generator.hpp"
#include "terrain_cli.hpp"

namespace starnav::cli {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

constexpr RoughTerrainPlannerKind kTerrainPlanners[3] = {RoughTerrainPlannerKind::OA, RoughTerrainPlannerKind::AOEA,
                                                  RoughTerrainPlannerKind::IA};
constexpr const char* kPlannerTitles[3] = {"OA*", "AOEA*", "IA*"};

struct TerrainBenchOptions {
  std::string map;
  int generate = 0;
  std::uint64_t seed = 0;
  double amplitude = 1.0;
  std::string start;
  std::string goal;
  double model_resolution = 0.0;
  std::string out;
  bool json = false;
  int svg_limit = 3;
  bool force = false;
  bool quiet = false;
  TerrainPlanFlags flags;
  CLI::Option* generate_opt = nullptr;
  CLI::Option* seed_opt = nullptr;
  CLI::Option* amplitude_opt = nullptr;
  CLI::Option* model_opt = nullptr;
};

struct Terrain {
  std::string name;
  std::uint64_t seed = 0;  // generated terrains
  ElevationMap map;
};

struct TerrainRun {
  bool found = false;
  std::string reason;
  double cost = 0.0;
  double length_2d_m = 0.0;
  std::uint64_t expanded = 0;
  std::uint64_t generated = 0;
  std::uint64_t reopened = 0;
  double time_ms = 0.0;
  double preprocess_ms = 0.0;
  TerrainPathMetrics metrics;
  std::vector<Cell> path;
  std::vector<AttitudeSample> samples;  // the first --svg-limit terrains only
};

struct TerrainResult {
  Cell start{}, goal{};
  Vec2 start_m{0, 0}, goal_m{0, 0};
  double analysis_ms = 0.0;
  // Whether the ruggedness threshold can matter: observed cells with S >= S_y, and the largest S.
  std::size_t observed_cells = 0;
  std::size_t cells_at_sy = 0;
  double max_s_m2 = 0.0;
  TerrainRun runs[3];
};

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

std::string terrain_file_stem(const Terrain& t) {
  std::string s = t.name;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return s;
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

Comparison compare(const std::vector<TerrainResult>& results, int other) {
  Comparison c;
  std::vector<double> lv, av, hv, sv, rm, rx, pm_, px, tm, tx;
  double sum_lv_o = 0, sum_lv_i = 0, sum_tm_o = 0, sum_tm_i = 0, sum_tx_o = 0, sum_tx_i = 0;
  for (const TerrainResult& r : results) {
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
Stat metric_stat(const std::vector<TerrainResult>& results, int p, double TerrainPathMetrics::*member, Use use) {
  std::vector<double> v;
  for (const TerrainResult& r : results)
    if (use(r)) v.push_back(r.runs[p].metrics.*member);
  return sample_stats(v);
}

bool all_found(const TerrainResult& r) { return r.runs[0].found && r.runs[1].found && r.runs[2].found; }

void write_tables(std::ostream& md, const std::vector<TerrainResult>& results, bool common, std::size_t terrains) {
  std::size_t n_common = 0;
  for (const TerrainResult& r : results) n_common += all_found(r);
  auto use_for = [&](int p) {
    return [common, p](const TerrainResult& r) { return common ? all_found(r) : r.runs[p].found; };
  };
  md << "| planner | paths | lv (m) | av (rad) | hv (m) | Sv (m²) |\n|---|---:|---:|---:|---:|---:|\n";
  for (int p = 0; p < 3; ++p) {
    std::size_t found = 0;
    for (const TerrainResult& r : results) found += r.runs[p].found;
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
  add_terrain_metrics_json(j, r.found ? &r.metrics : nullptr);
  j["path_nodes"] = r.path.size();
  j["expanded"] = r.expanded;
  j["generated"] = r.generated;
  j["reopened"] = r.reopened;
  return j;
}

void run_bench_terrain(TerrainBenchOptions& o, Context& ctx) {
  const bool from_map = !o.map.empty();
  if (from_map == (o.generate_opt->count() > 0))
    throw Error("give exactly one of --map FILE and --generate N", {}, 0, "--map");
  if (from_map) {
    if (o.seed_opt->count()) throw Error("applies to --generate only", {}, 0, "--seed");
    if (o.amplitude_opt->count()) throw Error("applies to --generate only", {}, 0, "--amplitude");
  } else {
    if (o.generate < 1) throw Error("expected a number of terrains >= 1", {}, 0, "--generate");
    if (!(o.amplitude > 0) || !std::isfinite(o.amplitude)) throw Error("expected a number > 0", {}, 0, "--amplitude");
    if (o.model_opt->count()) throw Error("applies to --map only", {}, 0, "--model-resolution");
  }
  if (o.model_opt->count() && (!(o.model_resolution > 0) || !std::isfinite(o.model_resolution)))
    throw Error("expected a cell size in metres > 0", {}, 0, "--model-resolution");
  if (o.svg_limit < 0) throw Error("expected a number >= 0", {}, 0, "--svg-limit");
  if (o.start.empty() != o.goal.empty()) throw Error("give both --start and --goal, or neither", {}, 0, o.start.empty() ? "--start" : "--goal");
  const bool given_endpoints = !o.start.empty();
  const Vec2 start_m = given_endpoints ? parse_xy(o.start, "--start") : Vec2(0.5, 0.5);
  const Vec2 goal_m = given_endpoints ? parse_xy(o.goal, "--goal") : Vec2(9.5, 9.5);
  const RoughTerrainPlannerOptions options =
      terrain_planner_options(o.flags, {kTerrainPlanners[0], kTerrainPlanners[1], kTerrainPlanners[2]});
  if (!o.out.empty()) {
    if (fs::exists(o.out) && !fs::is_directory(o.out)) throw Error("is not a directory", o.out, 0, "--out");
    if (fs::exists(fs::path(o.out) / "terrain.json") && !o.force)
      throw Error("holds results already (use --force to overwrite)", o.out, 0, "--out");
  }

  // The terrains.
  std::vector<Terrain> terrains;
  double model_scale = 1.0;
  std::string source_resolution;
  if (from_map) {
    const LoadedMap loaded = load_map(o.map);
    if (!loaded.is_elevation()) throw Error("is an occupancy map; bench terrain needs an elevation map", o.map, 0, "--map");
    Terrain t;
    t.name = fs::path(o.map).stem().string();
    t.map = loaded.elevation();
    if (o.model_opt->count()) {
      model_scale = o.model_resolution / t.map.resolution();
      t.map = scaled_model(t.map, model_scale);
    }
    terrains.push_back(std::move(t));
  } else {
    for (int i = 0; i < o.generate; ++i) {
      HillsOptions h;
      h.seed = o.seed + static_cast<std::uint64_t>(i);
      h.amplitude = o.amplitude;
      Terrain t;
      t.seed = h.seed;
      t.name = "hills_seed" + std::to_string(h.seed);
      t.map = generate_hills(h);
      terrains.push_back(std::move(t));
    }
  }

  // The runs.
  const std::size_t svgs = std::min<std::size_t>(terrains.size(), static_cast<std::size_t>(o.svg_limit));
  std::vector<TerrainResult> results(terrains.size());
  double total_search_ms[3] = {0, 0, 0}, total_preprocess_ms[3] = {0, 0, 0}, total_analysis_ms = 0;
  ProgressBar progress("bench terrain", terrains.size(), o.quiet);
  for (std::size_t i = 0; i < terrains.size(); ++i) {
    progress.update(i, terrains[i].name);
    const ElevationMap& m = terrains[i].map;
    TerrainAnalysisOptions ao;
    ao.unobserved = options.unobserved;
    ao.thresholds = options.cost;
    ao.robot_radius_m = options.robot_radius_m;
    const auto t0 = std::chrono::steady_clock::now();
    const auto analysis = std::make_shared<const TerrainAnalysis>(m, ao);
    TerrainResult& res = results[i];
    res.analysis_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    total_analysis_ms += res.analysis_ms;
    for (std::size_t c = 0; c < analysis->ruggedness().size(); ++c) {
      if (!analysis->observed()[c]) continue;
      ++res.observed_cells;
      res.cells_at_sy += analysis->ruggedness()[c] >= options.cost.s_y;
      res.max_s_m2 = std::max(res.max_s_m2, analysis->ruggedness()[c]);
    }
    if (given_endpoints || !from_map) {
      res.start = cell_of_point(m.geometry(), start_m);
      res.goal = cell_of_point(m.geometry(), goal_m);
    } else {
      auto_endpoints(*analysis, res.start, res.goal);
    }
    res.start_m = m.geometry().contains(res.start) ? m.geometry().cell_center(res.start) : start_m;
    res.goal_m = m.geometry().contains(res.goal) ? m.geometry().cell_center(res.goal) : goal_m;
    for (int p = 0; p < 3; ++p) {
      RoughTerrainPlanner planner(kTerrainPlanners[p], analysis, options);
      const PlanResult r = planner.plan(res.start, res.goal);
      TerrainRun& run = res.runs[p];
      run.found = r.found();
      run.expanded = r.expanded;
      run.generated = r.generated;
      run.reopened = planner.reopened();
      run.time_ms = r.time_ms;
      run.preprocess_ms = planner.preprocess_ms();
      total_search_ms[p] += r.time_ms;
      total_preprocess_ms[p] += run.preprocess_ms;
      if (!run.found) {
        run.reason = plan_status_reason(r.status);
        continue;
      }
      run.cost = r.cost;
      run.length_2d_m = r.length;
      run.path = r.path_cells;
      run.metrics = terrain_path_metrics(*analysis, run.path, {}, i < svgs ? &run.samples : nullptr);
    }
    if (!o.out.empty() && i < svgs) {
      fs::create_directories(fs::path(o.out) / "svg");
      const std::string stem = (fs::path(o.out) / "svg" / terrain_file_stem(terrains[i])).string();
      std::vector<Cell> obstacles;
      for (std::size_t c = 0; c < analysis->expanded_obstacle_mask().size(); ++c)
        if (analysis->expanded_obstacle_mask()[c] && analysis->observed()[c]) obstacles.push_back(m.geometry().cell_of_index(c));
      std::vector<TerrainPathLayer> layers;
      for (int p = 0; p < 3; ++p) layers.push_back({kPlannerTitles[p], res.runs[p].found ? &res.runs[p].path : nullptr});
      write_terrain_paths_svg(stem + "_paths.svg", m, terrains[i].name + ": OA*, AOEA*, IA*", layers, obstacles,
                              "AOEA* obstacles (expanded)", res.start, res.goal);
      std::vector<std::pair<std::string, const std::vector<AttitudeSample>*>> series;
      for (int p = 0; p < 3; ++p) series.push_back({kPlannerTitles[p], &res.runs[p].samples});
      write_attitude_profile_svg(stem + "_roll.svg", terrains[i].name + ": roll along the paths", AttitudeAngle::Roll, series);
      write_attitude_profile_svg(stem + "_pitch.svg", terrains[i].name + ": pitch along the paths", AttitudeAngle::Pitch, series);
      write_attitude_profile_svg(stem + "_tilt.svg", terrains[i].name + ": tilt along the paths", AttitudeAngle::Tilt, series);
    }
    for (TerrainRun& run : res.runs) {
      run.samples.clear();
      run.samples.shrink_to_fit();
    }
  }
  progress.update(terrains.size(), "done");
  progress.finish();

  const Comparison vs_oa = compare(results, 0);
  const Comparison vs_aoea = compare(results, 1);
  std::size_t n_common = 0;
  for (const TerrainResult& r : results) n_common += all_found(r);

  // Markdown.
  const ElevationMap& first = terrains.front().map;
  std::ostringstream md;
  md << "## Rough-terrain planning (Liu et al. 2024, Tables 2 and 3): ";
  if (from_map) md << fs::path(o.map).filename().string() << "\n\n";
  else md << o.generate << " generated hills terrains\n\n";
  if (from_map) {
    md << "Map " << o.map << ": " << first.width() << " x " << first.height() << " cells";
    if (model_scale != 1.0)
      md << ", planned as a scale model with " << format_fixed(first.resolution(), 3) << " m cells (every distance x "
         << format_fixed(model_scale, 6) << "; results in model metres)";
    else md << " of " << format_fixed(first.resolution(), 3) << " m";
    md << ". Start (" << format_fixed(results[0].start_m.x(), 2) << ", " << format_fixed(results[0].start_m.y(), 2)
       << ") m, goal (" << format_fixed(results[0].goal_m.x(), 2) << ", " << format_fixed(results[0].goal_m.y(), 2)
       << ") m" << (given_endpoints ? "" : " (the cells free of AOEA* obstacles nearest to the points 5 % in from two opposite corners)")
       << ".\n\n";
  } else {
    md << "Hills terrains of 10 m x 10 m at 0.1 m (`starnav terrain generate --kind hills`), amplitude "
       << format_fixed(o.amplitude, 2) << ", seeds " << o.seed << ".." << o.seed + static_cast<std::uint64_t>(o.generate) - 1
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
     << terrains.size() << "), mean ± sd\n\n";
  write_tables(md, results, true, terrains.size());
  md << "### Each planner over the terrains where it found a path\n\n";
  write_tables(md, results, false, terrains.size());
  md << "Paper (one terrain, for orientation): OA* lv 14.38 m, av 0.58 rad, hv 0.097 m, Sv 0.049 m²; AOEA* 19.32, "
        "0.31, 0.034, 0.014; IA* 17.54, 0.26, 0.027, 0.013.\n\n";
  md << "### Comparisons (the paper's claims)\n\n";
  write_comparison(md, vs_oa, "OA\\*");
  write_comparison(md, vs_aoea, "AOEA\\*");
  {
    std::size_t cells = 0, at_sy = 0, terrains_at_sy = 0;
    double max_s = 0.0;
    for (const TerrainResult& r : results) {
      cells += r.observed_cells;
      at_sy += r.cells_at_sy;
      terrains_at_sy += r.cells_at_sy > 0;
      max_s = std::max(max_s, r.max_s_m2);
    }
    md << "\nRuggedness threshold: " << at_sy << " of " << cells << " observed cells (on " << terrains_at_sy << " of "
       << results.size() << " terrains) have S >= S_y = " << options.cost.s_y << " m²; the largest S is "
       << format_fixed(max_s, 5) << " m².\n";
  }
  md << "\nNo path: ";
  for (int p = 0; p < 3; ++p) {
    std::size_t missing = 0;
    for (const TerrainResult& r : results) missing += !r.runs[p].found;
    md << kPlannerTitles[p] << " " << missing << (p < 2 ? ", " : ".\n\n");
  }

  json j;
  j["benchmark"] = "terrain";
  j["paper"] = "Liu et al. 2024, Tables 2 and 3";
  if (from_map) {
    j["map"] = o.map;
    j["model_scale"] = model_scale;
  } else {
    j["generate"] = {{"kind", "hills"}, {"terrains", o.generate}, {"seed", o.seed}, {"amplitude", o.amplitude},
                     {"size_m", {10.0, 10.0}}, {"resolution", 0.1}};
  }
  j["width"] = first.width();
  j["height"] = first.height();
  j["resolution"] = first.resolution();
  j["endpoints"] = given_endpoints ? "given" : (from_map ? "auto" : "paper");
  j["options"] = terrain_options_json(options);
  j["footprint_m"] = {Footprint{}.length_m, Footprint{}.width_m};
  j["terrains"] = terrains.size();
  j["terrains_all_found"] = n_common;
  json planners = json::array();
  for (int p = 0; p < 3; ++p) {
    json pj;
    pj["planner"] = rough_terrain_planner_name(kTerrainPlanners[p]);
    std::size_t found = 0;
    for (const TerrainResult& r : results) found += r.runs[p].found;
    pj["found"] = found;
    json common, own;
    for (const TerrainMetricField& f : kTable2) {
      common[f.key] = terrain_stat_json(metric_stat(results, p, f.member, all_found));
      own[f.key] = terrain_stat_json(metric_stat(results, p, f.member, [p](const TerrainResult& r) { return r.runs[p].found; }));
    }
    for (const TerrainMetricField& f : kTable3) {
      common[f.key] = terrain_stat_json(metric_stat(results, p, f.member, all_found));
      own[f.key] = terrain_stat_json(metric_stat(results, p, f.member, [p](const TerrainResult& r) { return r.runs[p].found; }));
    }
    pj["all_found"] = common;
    pj["own_found"] = own;
    planners.push_back(pj);
  }
  j["planners"] = planners;
  j["comparisons"] = {comparison_json(vs_oa, "oa"), comparison_json(vs_aoea, "aoea")};
  json per = json::array();
  for (std::size_t i = 0; i < terrains.size(); ++i) {
    json t;
    t["name"] = terrains[i].name;
    if (!from_map) t["seed"] = terrains[i].seed;
    t["start_cell"] = {results[i].start.x, results[i].start.y};
    t["goal_cell"] = {results[i].goal.x, results[i].goal.y};
    t["start_m"] = {results[i].start_m.x(), results[i].start_m.y()};
    t["goal_m"] = {results[i].goal_m.x(), results[i].goal_m.y()};
    t["observed_cells"] = results[i].observed_cells;
    t["cells_s_at_least_sy"] = results[i].cells_at_sy;
    t["max_s_m2"] = results[i].max_s_m2;
    for (int p = 0; p < 3; ++p) t[rough_terrain_planner_name(kTerrainPlanners[p])] = run_json(results[i].runs[p]);
    per.push_back(t);
  }
  j["per_terrain"] = per;

  if (o.json) std::cout << j.dump(1) << "\n";
  else std::cout << md.str();
  ctx.exit_code = 0;
  if (o.out.empty()) return;

  // Per-terrain table (file only).
  std::ostringstream full;
  full << md.str() << "### Per terrain\n\n| terrain | planner | found | lv (m) | av (rad) | hv (m) | Sv (m²) | tilt mean (°) | "
                      "tilt max (°) | expanded |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t i = 0; i < terrains.size(); ++i)
    for (int p = 0; p < 3; ++p) {
      const TerrainRun& r = results[i].runs[p];
      full << "| " << terrains[i].name << " | " << kPlannerTitles[p] << " | ";
      if (!r.found) {
        full << r.reason << " | - | - | - | - | - | - | " << r.expanded << " |\n";
        continue;
      }
      const TerrainPathMetrics& m = r.metrics;
      full << "yes | " << format_fixed(m.lv_m, 2) << " | " << format_fixed(m.av_rad, 3) << " | "
           << format_fixed(m.hv_m, 4) << " | " << format_fixed(m.sv_m2, 5) << " | " << format_fixed(m.tilt_mean_deg, 2)
           << " | " << format_fixed(m.tilt_max_deg, 2) << " | " << r.expanded << " |\n";
    }
  if (svgs > 0) {
    full << "\nFigures (svg/): ";
    for (std::size_t i = 0; i < svgs; ++i) {
      const std::string stem = terrain_file_stem(terrains[i]);
      full << "[" << stem << " paths](svg/" << stem << "_paths.svg), attitude [roll](svg/" << stem << "_roll.svg) / [pitch](svg/"
           << stem << "_pitch.svg) / [tilt](svg/" << stem << "_tilt.svg)" << (i + 1 < svgs ? "; " : ".\n");
    }
  }
  fs::create_directories(o.out);
  auto write_file = [&](const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
    if (!f) throw Error("cannot write", p.string(), 0, "--out");
  };
  write_file(fs::path(o.out) / "terrain.md", full.str());
  write_file(fs::path(o.out) / "terrain.json", j.dump(1) + "\n");
  json timing;
  timing["analysis_ms_total"] = total_analysis_ms;
  for (int p = 0; p < 3; ++p)
    timing[rough_terrain_planner_name(kTerrainPlanners[p])] = {{"search_ms_total", total_search_ms[p]},
                                                        {"preprocess_ms_total", total_preprocess_ms[p]}};
  write_file(fs::path(o.out) / "timing.json", timing.dump(1) + "\n");
  if (!o.quiet) std::cerr << "bench terrain: wrote " << o.out << "/terrain.md, terrain.json, timing.json, " << svgs * 4 << " SVGs\n";
}

}  // namespace

void register_bench_terrain(CLI::App& app, Context& ctx) {
  CLI::App* bench = app.get_subcommand("bench");
  auto o = std::make_shared<TerrainBenchOptions>();
  auto* cmd = bench->add_subcommand(
      "terrain",
      "Liu et al. 2024 (Tables 2 and 3, Figs. 6 and 8): OA*, AOEA* and IA* on an elevation map or on N generated\n"
      "10 m x 10 m hills terrains (0.1 m, start (0.5, 0.5), goal (9.5, 9.5)); lv, av, hv, Sv and the attitude angles\n"
      "along each path, mean and spread over the terrains, and the paper's pairwise claims.");
  cmd->add_option("--map", o->map, "an elevation map (.yaml + 16-bit PNG, .asc, .csv, .raw, GeoTIFF)");
  o->generate_opt = cmd->add_option("--generate", o->generate, "generate N hills terrains instead");
  o->seed_opt = cmd->add_option("--seed", o->seed, "--generate: seed of the first terrain (default 0; then S+1, ...)");
  o->amplitude_opt = cmd->add_option("--amplitude", o->amplitude, "--generate: hills amplitude (default 1)");
  cmd->add_option("--start", o->start, "start X,Y in metres (default (0.5, 0.5) on generated terrains; on a map: see docs/terrain.md)");
  cmd->add_option("--goal", o->goal, "goal X,Y in metres (default (9.5, 9.5) on generated terrains)");
  o->model_opt = cmd->add_option("--model-resolution", o->model_resolution,
                                 "--map: plan on a geometric scale model of the map with cells of R metres");
  add_terrain_plan_flags(cmd, o->flags);
  cmd->add_option("--out", o->out, "directory for terrain.md, terrain.json, timing.json and svg/");
  cmd->add_flag("--json", o->json, "print the JSON report instead of the Markdown");
  cmd->add_option("--svg-limit", o->svg_limit, "figures for the first K terrains (default 3)");
  cmd->add_flag("--force", o->force, "overwrite the results in --out");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o, &ctx] { run_bench_terrain(*o, ctx); });
}

}  // namespace starnav::cli
