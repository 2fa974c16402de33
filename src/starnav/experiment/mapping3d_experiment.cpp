#include "starnav/experiment/mapping3d_experiment.hpp"

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/harness/encoder_odometry.hpp"
#include "starnav/harness/slam3d_run.hpp"
#include "starnav/harness/slam_run.hpp"
#include "starnav/sense/sensor_bus.hpp"
#include "starnav/harness/route_drive.hpp"
#include "starnav/sim/world.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/sim/simulation.hpp"
#include "starnav/viz/plot_svg.hpp"

namespace starnav {

namespace fs = std::filesystem;

void Mapping3dExperimentConfig::validate() const {
  require(seeds >= 1 && seeds <= 10000, "--seeds", "must be in [1, 10000]");
  require(!matchers.empty(), "--matchers", "needs at least one matcher");
  for (const std::string& m : matchers) (void)find_scan_matcher_3d(m, "--matchers");
  if (!no_floor_matcher.empty()) (void)find_scan_matcher_3d(no_floor_matcher, "--no-floor-matcher");
  // The SLAM settings, checked by building the method once before anything is simulated.
  SlamChoice choice;
  choice.method = "graph3d";
  choice.settings = slam_settings;
  choice.matcher = {matchers.front(), {}, "--matchers"};
  (void)make_slam(choice);
}

std::vector<Mapping3dVariant> Mapping3dExperimentConfig::variants() const {
  std::vector<Mapping3dVariant> v;
  for (const std::string& m : matchers) v.push_back({m, m, true});
  if (!no_floor_matcher.empty()) v.push_back({no_floor_matcher + "_no_floor", no_floor_matcher, false});
  return v;
}

namespace {

// The 2D grid of a run's map against the world's true occupancy in the same height band, and
// the improved A* on it (docs/mapping3d.md, "The 2D grid against the truth").
void judge_map(const Slam& slam, const Rigid3& to_truth, const World& world, const Mapping3dExperimentConfig& c,
               Mapping3dRun& run) {
  const Slam3dMapConfig mc;
  const OctreeMap octree = slam.map_3d(mc.octree);
  const OccupancyGrid grid = octree.project_to_grid(mc.grid);
  const double bottom = mc.grid.floor_z_m + mc.grid.min_height_m;
  // The truth at a map-frame point: something stands there reaching into the band (the world's
  // obstacles are solids standing on the floor, so the highest surface above the point says it).
  const auto truly_occupied = [&](const Vec2& p) {
    const Vec3 w = to_truth * Vec3(p.x(), p.y(), 0.0);
    const double h = world.surface_height(w.x(), w.y(), 0.0);
    return std::isfinite(h) && h >= bottom;
  };
  const GridGeometry& g = grid.geometry();
  const OccupancyThresholds th;
  const std::size_t n = static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height);
  // est: the map's occupied cells; truth: every truly occupied cell (an estimated cell on a wall's
  // face matches the wall's unseen inside); observed: the cells the map knows, where a true
  // obstacle the map lacks counts as missed.
  std::vector<std::uint8_t> est(n, 0), truth(n, 0), observed(n, 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const CellState st = th.classify(grid(x, y));
      est[g.index(x, y)] = st == CellState::Occupied;
      observed[g.index(x, y)] = st != CellState::Unknown;
      truth[g.index(x, y)] = truly_occupied(g.cell_center(x, y));
    }
  const auto near = [&](const std::vector<std::uint8_t>& m, int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (g.contains(x + dx, y + dy) && m[g.index(x + dx, y + dy)]) return true;
    return false;
  };
  std::size_t matched = 0, missed = 0;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      if (est[g.index(x, y)]) {
        ++run.occupied_cells;
        matched += near(truth, x, y);
      }
      if (truth[g.index(x, y)] && observed[g.index(x, y)]) {
        ++run.true_occupied_cells;
        missed += !near(est, x, y);
      }
    }
  run.occupied_iou = run.occupied_cells + missed > 0 ? static_cast<double>(matched) / static_cast<double>(run.occupied_cells + missed) : 0.0;
  run.mapped = true;
  run.occupied_matched = matched;
  run.true_missed = missed;
  const Vec2 start = slam.keyframes_3d().front().pose.translation().head<2>();
  const Vec2 goal = (to_truth.inverse() * Vec3(c.plan_goal.x(), c.plan_goal.y(), 0.0)).head<2>();
  // A run shorter than the route never sees its end: there is nothing to plan to.
  const auto goal_cell = g.world_to_cell(goal);
  run.goal_mapped = goal_cell && observed[g.index(goal_cell->x, goal_cell->y)];
  if (!run.goal_mapped) return;
  const PlanOutcome p = slam3d_plan(grid, start, goal, c.plan_inflation_m);
  run.path_found = p.result.found();
  if (!run.path_found) return;
  run.path_length_m = p.metrics.length;
  // Collision-free in the true world: the path's points, every 5 cm, and a 0.25 m circle round
  // each (half the robot's width) stay clear of every obstacle in the band.
  run.path_collision_free = true;
  const std::vector<Vec2>& path = p.path();
  for (std::size_t i = 0; i + 1 < path.size() && run.path_collision_free; ++i) {
    const double len = (path[i + 1] - path[i]).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(len / 0.05)));
    for (int k = 0; k <= steps && run.path_collision_free; ++k) {
      const Vec2 q = path[i] + (path[i + 1] - path[i]) * (static_cast<double>(k) / steps);
      if (truly_occupied(q)) run.path_collision_free = false;
      for (int a = 0; a < 8 && run.path_collision_free; ++a) {
        const double ang = a * kPi / 4.0;
        if (truly_occupied(q + 0.25 * Vec2(std::cos(ang), std::sin(ang)))) run.path_collision_free = false;
      }
    }
  }
}

// The prefilter's counts and the registration time of each frame, from the differences of the
// method's running totals across the frame's on_cloud.
const char* const kFrameFigures[] = {"raw_points", "windowed_points", "voxelised_points", "filtered_points", "match_s"};
using FrameFigures = std::array<double, 5>;

FrameFigures frame_totals(const Slam& slam) {
  FrameFigures out{};
  for (const auto& [name, value] : slam.statistics())
    for (std::size_t i = 0; i < out.size(); ++i)
      if (name == kFrameFigures[i]) out[i] = value;
  return out;
}

struct Mapping3dSlot {
  Mapping3dVariant variant;
  std::unique_ptr<Slam> slam;
  double mapping_s = 0.0;
  FrameFigures totals{};
  std::vector<FrameFigures> frames;  // per frame
};

double statistic(const Slam& slam, const std::string& name) {
  for (const auto& [key, value] : slam.statistics())
    if (key == name) return value;
  return 0.0;
}

}  // namespace

Mapping3dResult run_mapping3d_experiment(const Mapping3dExperimentConfig& config, const Mapping3dProgress& progress) {
  config.validate();
  const CommandOwnedKey owned[] = {{"sim.seed", "--seeds and --seed-base give each run its seed"}};
  check_user_overrides(config.overrides, owned);
  Mapping3dResult result;
  result.config = config;
  result.variants = config.variants();
  const std::size_t total = static_cast<std::size_t>(config.seeds);
  for (std::uint64_t k = 0; k < config.seeds; ++k) {
    const std::uint64_t seed = config.seed_base + k;
    if (progress) progress(static_cast<std::size_t>(k), total, "seed " + std::to_string(seed));
    std::vector<ScenarioOverride> overrides = config.overrides;
    overrides.push_back(parse_scenario_override("sim.seed=" + std::to_string(seed)));
    const ScenarioSpec spec = load_scenario(config.scenario, overrides);
    if (!spec.lidar || spec.lidar->config.lines() < 2)
      throw Error("needs a 3D LiDAR (more than one line)", config.scenario, 0, "sensors.lidar");
    const Pose3 mount = spec.lidar->config.mount;
    Simulation sim(spec);
    std::unique_ptr<RouteDrive> route;
    if (spec.route) route = make_route_drive(sim);
    std::vector<Mapping3dSlot> slots;
    for (const Mapping3dVariant& v : result.variants) {
      SlamChoice choice;
      choice.method = "graph3d";
      choice.settings = config.slam_settings;
      choice.settings.push_back({"floor", v.floor ? "true" : "false", "", 0, "floor"});
      choice.matcher = {v.matcher, {}, "--matchers"};
      Mapping3dSlot slot;
      slot.variant = v;
      slot.slam = make_slam(choice);
      slots.push_back(std::move(slot));
    }
    const std::shared_ptr<const WheelOdometry> odometry = attach_encoder_odometry(sim);
    std::vector<Rigid3> truth;
    std::vector<double> times;
    // Every variant subscribed to what the robot's drivers would publish: the wheel odometry at the
    // scan, then the cloud.
    SensorBus bus;
    for (Mapping3dSlot& slot : slots) {
      bus.subscribe<OdometryMessage>("odom", [&slot](const OdometryMessage& m) {
        const auto t0 = std::chrono::steady_clock::now();
        slot.slam->on_odometry(m);
        slot.mapping_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      });
      bus.subscribe<CloudMessage>("lidar", [&slot](const CloudMessage& m) {
        const auto t0 = std::chrono::steady_clock::now();
        slot.slam->on_cloud(m);
        slot.mapping_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const FrameFigures totals = frame_totals(*slot.slam);
        FrameFigures frame{};
        for (std::size_t i = 0; i < frame.size(); ++i) frame[i] = totals[i] - slot.totals[i];
        slot.frames.push_back(frame);
        slot.totals = totals;
      });
    }
    const Simulation* s = &sim;
    sim.lidar_feed("lidar").subscribe(SampleStage::Estimate, [&bus, &odometry, &truth, &times, s, mount](const LidarScan& scan) {
      if (odometry) bus.publish(OdometryMessage{{scan.time, "odom"}, odometry->pose(), {}});
      CloudMessage cloud;
      cloud.header = {scan.time, "lidar"};
      cloud.mount = mount;
      cloud.points = scan.points_sensor;
      bus.publish(std::move(cloud));
      bus.deliver_all();
      truth.push_back(to_rigid(s->vehicle().state().pose) * to_rigid(mount));
      times.push_back(scan.time);
    });
    sim.run();
    for (std::size_t vi = 0; vi < slots.size(); ++vi) {
      Mapping3dSlot& slot = slots[vi];
      const auto t0 = std::chrono::steady_clock::now();
      slot.slam->finish();
      slot.mapping_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::vector<Rigid3> est;
      for (const SlamPose& p : slot.slam->trajectory()) est.push_back(p.sensor);
      const Slam3dErrors e = slam3d_errors(est, truth);
      Mapping3dRun run;
      run.seed = seed;
      run.variant = slot.variant.label;
      run.matcher = slot.variant.matcher;
      run.floor = slot.variant.floor;
      run.frames = est.size();
      run.keyframes = slot.slam->keyframes_3d().size();
      run.loops = slot.slam->graph().closures();
      run.floor_edges = static_cast<std::size_t>(statistic(*slot.slam, "floor_edges"));
      run.ate_rmse_m = e.ate_rmse_m;
      run.elevation_drift_m = e.elevation_drift_m;
      run.final_error_m = e.final_error_m;
      run.driven_m = e.driven_m;
      run.recording_s = times.back() - times.front();
      run.mapping_s = slot.mapping_s;
      std::vector<double> match;
      for (std::size_t f = 0; f < slot.frames.size(); ++f) {
        const FrameFigures& fig = slot.frames[f];
        if (f > 0) match.push_back(fig[4]);  // the first frame is not registered
        run.raw_points += fig[0];
        run.windowed_points += fig[1];
        run.voxelised_points += fig[2];
        run.kept_points += fig[3];
      }
      const double n = static_cast<double>(std::max<std::size_t>(1, run.frames));
      run.raw_points /= n;
      run.windowed_points /= n;
      run.voxelised_points /= n;
      run.kept_points /= n;
      const SampleStats ms = sample_stats(match);
      run.mean_match_s = ms.mean;
      run.median_match_s = ms.median;
      if (slot.variant.label == config.map_variant) judge_map(*slot.slam, e.alignment, sim.world(), config, run);
      result.runs.push_back(run);
      if (k == 0) {
        Mapping3dTrace& tr = result.trace;
        if (vi == 0) {
          tr.t = times;
          for (const Rigid3& t : truth) tr.truth.push_back(t.translation());
          for (const FrameFigures& fig : slot.frames) tr.filter_counts.push_back({fig[0], fig[1], fig[2], fig[3]});
        }
        // Aligned as the errors are (slam3d_errors: x, y and heading of the first pose).
        const Rigid3& align = e.alignment;
        std::vector<Vec3> aligned;
        for (const Rigid3& t : est) aligned.push_back(align * t.translation());
        tr.estimates.push_back(std::move(aligned));
      }
    }
  }
  if (progress) progress(total, total, "done");
  for (const Mapping3dVariant& v : result.variants) {
    Mapping3dSummary s;
    s.variant = v.label;
    std::vector<double> ate, drift, match, rtf;
    for (const Mapping3dRun& r : result.runs) {
      if (r.variant != v.label) continue;
      ate.push_back(r.ate_rmse_m);
      drift.push_back(r.elevation_drift_m);
      match.push_back(1000.0 * r.median_match_s);
      rtf.push_back(r.mapping_s > 0 ? r.recording_s / r.mapping_s : 0.0);
    }
    s.runs = static_cast<int>(ate.size());
    const SampleStats a = sample_stats(ate), d = sample_stats(drift);
    s.ate_mean_m = a.mean;
    s.ate_max_m = a.max;
    s.drift_mean_m = d.mean;
    s.drift_max_m = d.max;
    s.median_match_ms = sample_stats(match).median;
    s.real_time_factor = sample_stats(rtf).median;
    result.summaries.push_back(s);
  }
  return result;
}

std::string mapping3d_markdown(const Mapping3dResult& r) {
  std::string s = "# 3D mapping (Ou et al. 2022, section 4.1), simulated\n\n";
  s += r.config.scenario + ", seeds " + std::to_string(r.config.seed_base) + "-" +
       std::to_string(r.config.seed_base + r.config.seeds - 1) + ".";
  if (!r.runs.empty()) {
    const Mapping3dRun& f = r.runs.front();
    s += " Per frame (seed " + std::to_string(f.seed) + "): " + format_fixed(f.raw_points, 0) + " points raw, " +
         format_fixed(f.windowed_points, 0) + " in the range window, " + format_fixed(f.voxelised_points, 0) +
         " after the voxel grid, " + format_fixed(f.kept_points, 0) + " after outlier removal (Fig. 9). " +
         format_fixed(f.driven_m, 1) + " m driven in " + format_fixed(f.recording_s, 1) + " s.";
  }
  s += "\n\n| variant | runs | ATE mean / max (cm) | elevation drift mean / max (cm) | median registration (ms) | "
       "real-time factor |\n|---|---|---|---|---|---|\n";
  for (const Mapping3dSummary& m : r.summaries)
    s += "| " + m.variant + " | " + std::to_string(m.runs) + " | " + format_fixed(100 * m.ate_mean_m, 2) + " / " +
         format_fixed(100 * m.ate_max_m, 2) + " | " + format_fixed(100 * m.drift_mean_m, 2) + " / " +
         format_fixed(100 * m.drift_max_m, 2) + " | " + format_fixed(m.median_match_ms, 1) + " | " +
         format_fixed(m.real_time_factor, 1) + " |\n";
  for (const Mapping3dRun& x : r.runs)
    if (x.mapped && x.seed == r.config.seed_base) {
      s += "\nThe " + x.variant + " map's 2D grid against the true occupancy (0.1-0.6 m above the floor, observed cells, one "
           "cell of tolerance): IoU of occupied cells ";
      std::vector<double> iou;
      int found = 0, clear = 0, mapped = 0, reached = 0;
      for (const Mapping3dRun& y : r.runs)
        if (y.mapped && y.variant == x.variant) {
          iou.push_back(y.occupied_iou);
          ++mapped;
          reached += y.goal_mapped;
          found += y.path_found;
          clear += y.path_found && y.path_collision_free;
        }
      const SampleStats st = sample_stats(iou);
      const std::string goal = "(" + format_fixed(r.config.plan_goal.x(), 1) + ", " + format_fixed(r.config.plan_goal.y(), 1) + ") m";
      s += format_fixed(st.mean, 3) + " mean, " + format_fixed(st.min, 3) + " worst over " + std::to_string(mapped) +
           (mapped == 1 ? " seed" : " seeds") + ". ";
      if (reached == 0) {
        s += "The map never reached the route's end " + goal + " (the run is shorter than the route), so the improved A* "
             "was not run.\n";
      } else {
        s += "The improved A* to the route's end " + goal + " found a path on " + std::to_string(found) + " of the " +
             std::to_string(reached) + " maps that reached it, collision-free in the true world on " + std::to_string(clear) +
             (reached < mapped ? "; " + std::to_string(mapped - reached) + " maps did not reach it (runs shorter than the route)" : "") +
             ".\n";
      }
      break;
    }
  s += "\nThe real-time factor is the recording's length over the variant's mapping time (prefilter, "
       "registration, floor, loops, graph), one variant at a time on the simulation's thread.\n";
  return s;
}

std::string mapping3d_json(const Mapping3dResult& r) {
  nlohmann::ordered_json j;
  j["scenario"] = r.config.scenario;
  j["seeds"] = r.config.seeds;
  j["seed_base"] = r.config.seed_base;
  nlohmann::ordered_json v = nlohmann::ordered_json::array();
  for (const Mapping3dSummary& m : r.summaries)
    v.push_back({{"variant", m.variant},
                 {"runs", m.runs},
                 {"ate_mean_m", m.ate_mean_m},
                 {"ate_max_m", m.ate_max_m},
                 {"elevation_drift_mean_m", m.drift_mean_m},
                 {"elevation_drift_max_m", m.drift_max_m},
                 {"median_registration_ms", m.median_match_ms},
                 {"real_time_factor", m.real_time_factor}});
  j["variants"] = v;
  nlohmann::ordered_json maps = nlohmann::ordered_json::array();
  for (const Mapping3dRun& x : r.runs)
    if (x.mapped)
      maps.push_back({{"seed", x.seed},
                      {"variant", x.variant},
                      {"occupied_iou", x.occupied_iou},
                      {"occupied_cells", x.occupied_cells},
                      {"true_occupied_cells", x.true_occupied_cells},
                      {"occupied_matched", x.occupied_matched},
                      {"true_missed", x.true_missed},
                      {"goal_mapped", x.goal_mapped},
                      {"path_found", x.path_found},
                      {"path_collision_free", x.path_collision_free},
                      {"path_length_m", x.path_length_m}});
  j["maps"] = maps;
  return j.dump(2) + "\n";
}

std::string mapping3d_csv(const Mapping3dResult& r) {
  std::string s = "seed,variant,matcher,floor,frames,keyframes,loops,floor_edges,ate_rmse_m,elevation_drift_m,final_error_m,"
                  "driven_m,recording_s,mapping_s,mean_match_s,median_match_s,raw_points,windowed_points,voxelised_points,"
                  "kept_points,occupied_iou,path_found,path_collision_free,path_length_m\n";
  for (const Mapping3dRun& x : r.runs)
    s += std::to_string(x.seed) + ',' + x.variant + ',' + x.matcher + ',' + (x.floor ? "1" : "0") + ',' +
         std::to_string(x.frames) + ',' + std::to_string(x.keyframes) + ',' + std::to_string(x.loops) + ',' +
         std::to_string(x.floor_edges) + ',' + format_fixed6(x.ate_rmse_m) + ',' + format_fixed6(x.elevation_drift_m) + ',' +
         format_fixed6(x.final_error_m) + ',' + format_fixed6(x.driven_m) + ',' + format_fixed6(x.recording_s) + ',' +
         format_fixed6(x.mapping_s) + ',' + format_fixed6(x.mean_match_s) + ',' + format_fixed6(x.median_match_s) + ',' +
         format_fixed6(x.raw_points) + ',' + format_fixed6(x.windowed_points) + ',' + format_fixed6(x.voxelised_points) + ',' +
         format_fixed6(x.kept_points) + ',' + (x.mapped ? format_fixed6(x.occupied_iou) : "") + ',' +
         (x.mapped ? (x.path_found ? "1" : "0") : "") + ',' + (x.mapped ? (x.path_collision_free ? "1" : "0") : "") + ',' +
         (x.mapped ? format_fixed6(x.path_length_m) : "") + '\n';
  return s;
}

void write_mapping3d_figures(const Mapping3dResult& r, const std::string& dir) {
  const Mapping3dTrace& tr = r.trace;
  if (tr.t.empty()) return;
  const fs::path d(dir);
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    viz::LinePlot plot({.title = std::string("Sensor ") + axes[a] + " over time (Fig. 12), seed " + std::to_string(r.config.seed_base),
                        .x_label = "t [s]",
                        .y_label = std::string(axes[a]) + " [m]"});
    std::vector<Vec2> truth;
    for (std::size_t i = 0; i < tr.t.size(); ++i) truth.emplace_back(tr.t[i], tr.truth[i][a]);
    plot.add_series(truth, {.colour = {0, 0, 0, 255}, .width_px = 2.4}, "truth");
    for (std::size_t v = 0; v < tr.estimates.size(); ++v) {
      std::vector<Vec2> pts;
      for (std::size_t i = 0; i < tr.t.size(); ++i) pts.emplace_back(tr.t[i], tr.estimates[v][i][a]);
      plot.add_series(pts, {.colour = viz::categorical_colour(v), .width_px = 1.4}, r.variants[v].label);
    }
    plot.write_svg((d / (std::string(axes[a]) + ".svg")).string());
  }
  viz::LinePlot err({.title = "Position error over time (Fig. 13)", .x_label = "t [s]", .y_label = "error [m]"});
  for (std::size_t v = 0; v < tr.estimates.size(); ++v) {
    std::vector<Vec2> pts;
    for (std::size_t i = 0; i < tr.t.size(); ++i) pts.emplace_back(tr.t[i], (tr.estimates[v][i] - tr.truth[i]).norm());
    err.add_series(pts, {.colour = viz::categorical_colour(v), .width_px = 1.4}, r.variants[v].label);
  }
  err.write_svg((d / "error.svg").string());
  viz::LinePlot filt({.title = "Points per frame after each filter (Fig. 9)", .x_label = "frame", .y_label = "points"});
  const char* names[4] = {"raw", "range window", "voxel grid", "radius outliers"};
  for (int k = 0; k < 4; ++k) {
    std::vector<Vec2> pts;
    for (std::size_t i = 0; i < tr.filter_counts.size(); ++i) pts.emplace_back(static_cast<double>(i), tr.filter_counts[i][static_cast<std::size_t>(k)]);
    filt.add_series(pts, {.colour = viz::categorical_colour(static_cast<std::size_t>(k)), .width_px = 1.4}, names[k]);
  }
  filt.write_svg((d / "filters.svg").string());
}

}  // namespace starnav
