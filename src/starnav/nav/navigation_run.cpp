#include "starnav/nav/navigation_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/ros_map.hpp"

namespace starnav {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

[[noreturn]] void fail_at(const ScenarioSpec& spec, const ScenarioSource& src, const std::string& message) {
  throw Error(message, spec.file, src.line, src.field);
}

// The map grid: the world's terrain, or the box around start, goal and the obstacles (extent
// world); the paper's 1.5 x |goal - start| per axis around their midpoint (extent paper).
GridGeometry map_geometry(const ScenarioSpec& spec, const WorldDescription& world, const ScenarioNavigation& n) {
  const Vec2 start = spec.start.translation();
  Vec2 lo, hi;
  if (n.extent == "paper") {
    const Vec2 mid = 0.5 * (start + n.goal);
    const Vec2 half = (0.75 * (n.goal - start).cwiseAbs()).cwiseMax(Vec2::Constant(0.5 * n.paper_min_size_m));
    lo = mid - half;
    hi = mid + half;
  } else if (world.terrain) {
    const GridGeometry& g = world.terrain->geometry();
    lo = g.origin.translation();
    hi = lo + Vec2(g.width_m(), g.height_m());
  } else {
    lo = start.cwiseMin(n.goal);
    hi = start.cwiseMax(n.goal);
    for (const Obstacle& o : world.obstacles) {
      const Vec2 a = o.anchor_at(o.appear).head<2>();
      lo = lo.cwiseMin(a);
      hi = hi.cwiseMax(a);
    }
    lo -= Vec2::Constant(2.0);
    hi += Vec2::Constant(2.0);
  }
  GridGeometry g;
  g.resolution = n.resolution_m;
  g.origin = Pose2(lo.x(), lo.y(), 0.0);
  const double w = std::ceil((hi.x() - lo.x()) / n.resolution_m - 1e-9);
  const double h = std::ceil((hi.y() - lo.y()) / n.resolution_m - 1e-9);
  if (!(w >= 1.0 && h >= 1.0) || w * h > 1e8)
    fail_at(spec, n.source, "the navigation map would have " + std::to_string(w) + " x " + std::to_string(h) +
                                " cells (at most 1e8; raise map.resolution_m)");
  g.width = static_cast<int>(w);
  g.height = static_cast<int>(h);
  return g;
}

}  // namespace

NavigatorConfig navigator_config(const ScenarioSpec& spec, const WorldDescription& world,
                                 const NavigationOptions& options) {
  if (!spec.navigation)
    throw Error("not a navigation scenario (no navigation section)", spec.file, 0, "navigation");
  const ScenarioNavigation& n = *spec.navigation;
  if (!spec.lidar) throw Error("navigation needs sensors.lidar", spec.file, n.source.line, "sensors.lidar");
  NavigatorConfig c;
  c.geometry = map_geometry(spec, world, n);
  const auto field_error = [&](const Error& e, const ScenarioSource& src) {
    throw Error(e.message(), spec.file, src.line, e.field().empty() ? src.field : e.field());
  };

  NodeMapParams& m = c.map;
  const bool lidar2d = spec.lidar->config.lines() <= 1;
  m.mode = n.map_mode.empty() ? (lidar2d ? NodeMapMode::Lidar2D : NodeMapMode::Nodes3D)
                              : (n.map_mode == "lidar_2d" ? NodeMapMode::Lidar2D : NodeMapMode::Nodes3D);
  const RobotConfig& rc = spec.vehicle.robot;
  m.li.max_step_m = n.max_step_m.value_or(rc.max_step_m);
  if (n.max_slope_rad) m.li.max_slope_rad = *n.max_slope_rad;
  // The robot is a point in the expanded map: the body's circumscribed radius by default.
  m.barrier_distance_m = n.barrier_distance_m.value_or(0.5 * std::hypot(rc.body_length_m, rc.body_width_m));
  if (n.clear_margin_m) m.clear_margin_m = *n.clear_margin_m;
  if (n.hit_gain) m.hit_gain = *n.hit_gain;
  if (n.miss_loss) m.miss_loss = *n.miss_loss;
  if (n.evidence_max) m.evidence_max = *n.evidence_max;
  c.no_return_clear_m = n.no_return_clear_m;

  try {
    c.planner = parse_nav_planner(options.planner.value_or(n.planner), "navigation.planner");
  } catch (const Error& e) {
    if (options.planner) throw Error(e.message(), "", 0, "--planner");
    field_error(e, n.source);
  }
  c.compare_astar = options.compare_astar && c.planner == NavPlanner::DStarLite;
  c.goal_tolerance_m = n.goal_tolerance_m;

  PathFollowerConfig& f = c.follower;
  if (n.cruise_speed_mps) f.cruise_speed_mps = *n.cruise_speed_mps;
  if (n.look_ahead_m) f.look_ahead_m = *n.look_ahead_m;
  if (n.pursuit_look_ahead_m) f.pursuit_look_ahead_m = *n.pursuit_look_ahead_m;
  if (n.heading_gain) f.heading_gain = *n.heading_gain;
  if (n.max_yaw_rate_radps) f.max_yaw_rate_radps = *n.max_yaw_rate_radps;
  if (n.turn_tolerance_rad) f.turn_tolerance_rad = *n.turn_tolerance_rad;
  if (n.slow_down_distance_m) f.slow_down_distance_m = *n.slow_down_distance_m;
  const std::string mode = options.motion_mode.value_or(spec.motion_mode.empty() ? "auto" : spec.motion_mode);
  try {
    f.mode = resolve_motion_mode(parse_motion_mode(mode, "motion_mode"), rc.drive, "motion_mode");
  } catch (const Error& e) {
    if (options.motion_mode) throw Error(e.message(), "", 0, "--motion-mode");
    field_error(e, spec.motion_mode.empty() ? spec.robot_source : spec.motion_mode_source);
  }
  try {
    c.validate();
  } catch (const Error& e) {
    field_error(e, n.source);
  }
  if (!c.geometry.world_to_cell(n.goal)) fail_at(spec, n.goal_source, "the goal lies outside the navigation map");
  if (!c.geometry.world_to_cell(spec.start.translation()))
    fail_at(spec, spec.start_source, "the start lies outside the navigation map");
  return c;
}

NavigationRun::NavigationRun(const ScenarioSpec& spec, const NavigationOptions& options)
    : spec_(spec), options_(options) {
  const auto t0 = Clock::now();
  if (!spec_.navigation)
    throw Error("not a navigation scenario (no navigation section)", spec_.file, 0, "navigation");
  const WorldDescription world = build_world(spec_);
  const NavigatorConfig config = navigator_config(spec_, world, options_);
  sim_ = std::make_unique<Simulation>(spec_, world);
  nav_ = std::make_unique<Navigator>(config, spec_.vehicle.robot, spec_.navigation->goal);

  sim_->on_scan = [this](const LidarScan& scan) {
    const Pose3 pose3 = sim_->vehicle().state().pose;
    const Pose2 pose = pose3.to_pose2();
    const double t = sim_->time();
    NavCycle cycle = nav_->on_scan(scan, pose, t);
    if (options_.record_steps) {
      NavStepRecord r;
      r.t_s = t;
      r.pose = pose3;
      r.returns = scan.points_world.size();
      const NodeHeightMap& map = nav_->map();
      if (options_.step_all_hits) {
        r.hits = scan.points_world;
      } else {
        // One hit per obstacle cell (its highest return this scan), the paper's "laser lines that
        // have detected obstacles": enough for a viewer at a fraction of the bytes.
        std::vector<std::pair<std::size_t, Vec3>> top;
        for (const Vec3& p : scan.points_world) {
          const auto c = map.geometry().world_to_cell(p.head<2>());
          if (c && map.raw_blocked(c->x, c->y)) top.emplace_back(map.geometry().index(c->x, c->y), p);
        }
        std::stable_sort(top.begin(), top.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (std::size_t i = 0; i < top.size();) {
          std::size_t j = i;
          Vec3 best = top[i].second;
          for (; j < top.size() && top[j].first == top[i].first; ++j)
            if (top[j].second.z() > best.z()) best = top[j].second;
          r.hits.push_back(best);
          i = j;
        }
      }
      const OccupancyGrid& occ = map.occupancy();
      for (const Cell& c : cycle.update.occupancy_changed) r.changed.emplace_back(c, occ.at(c.x, c.y));
      r.path_id = nav_->plans().empty() ? 0 : nav_->plans().back().id;
      r.new_path = cycle.planned;
      steps_.push_back(std::move(r));
    }
    if (nav_->status() == NavStatus::NoPath) sim_->stop();
  };
  sim_->command_source = [this](double t) {
    const Pose2 pose = sim_->vehicle().state().pose.to_pose2();
    const BodyTwist cmd = nav_->command(pose, t);
    if (nav_->status() == NavStatus::Arrived || nav_->status() == NavStatus::NoPath) {
      sim_->stop();
      return BodyTwist{};
    }
    if (nav_->status() == NavStatus::Navigating && nav_->follower().has_path()) {
      const double d = nav_->distance_to_path(pose.translation());
      deviation_sum_ += d;
      deviation_max_ = std::max(deviation_max_, d);
      ++deviation_n_;
    }
    return cmd;
  };
  setup_s_ = seconds_since(t0);
}

NavigationRun::~NavigationRun() = default;

void NavigationRun::run(const std::function<void(double)>& progress) {
  const auto t0 = Clock::now();
  sim_->run(progress);
  wall_s_ += seconds_since(t0);
}

NavigationMetrics NavigationRun::metrics() const {
  NavigationMetrics m;
  const SimulationMetrics s = sim_->metrics();
  const Navigator& nav = *nav_;
  m.success = nav.status() == NavStatus::Arrived;
  m.outcome = m.success ? "arrived" : nav.status() == NavStatus::NoPath ? "no_path" : "timeout";
  m.reason = nav.no_path_reason();
  m.time_to_goal_s = m.success ? nav.arrival_time_s() : -1.0;
  m.duration_s = s.duration_s;
  m.distance_m = s.distance_m;
  m.plans = static_cast<int>(nav.plans().size());
  m.replans = std::max(0, m.plans - 1);
  for (std::size_t i = 0; i < nav.plans().size(); ++i) {
    const NavPlan& p = nav.plans()[i];
    m.expanded_total += p.expanded;
    if (i > 0) {
      m.replan_expanded += p.expanded;
      m.astar_replan_expanded += p.astar_expanded;
      m.astar_backward_replan_expanded += p.astar_backward_expanded;
    }
    const auto differs = [&](const std::string& status, double cost) {
      return status != "found" || std::abs(cost - p.cost_m) > 1e-9 * std::max(1.0, p.cost_m);
    };
    if (p.compared && p.status == "found" &&
        (differs(p.astar_status, p.astar_cost_m) || differs(p.astar_backward_status, p.astar_backward_cost_m)))
      m.costs_match = false;
  }
  m.collisions = s.collisions;
  if (deviation_n_ > 0) {
    m.deviation_mean_m = deviation_sum_ / static_cast<double>(deviation_n_);
    m.deviation_max_m = deviation_max_;
  }
  m.goal_distance_m = (s.final_state.position.head<2>() - nav.goal()).norm();
  m.planner = nav_planner_name(nav.config().planner);
  m.motion_mode = motion_mode_name(nav.follower().mode());
  return m;
}

std::string navigation_metrics_json(const NavigationRun& run) {
  const NavigationMetrics m = run.metrics();
  nlohmann::ordered_json j;
  j["scenario"] = run.spec().name;
  j["seed"] = run.spec().seed;
  j["planner"] = m.planner;
  j["motion_mode"] = m.motion_mode;
  j["success"] = m.success;
  j["outcome"] = m.outcome;
  if (!m.reason.empty()) j["reason"] = m.reason;
  j["time_to_goal_s"] = m.time_to_goal_s;
  j["duration_s"] = m.duration_s;
  j["distance_m"] = m.distance_m;
  j["goal_distance_m"] = m.goal_distance_m;
  j["plans"] = m.plans;
  j["replans"] = m.replans;
  j["expanded_total"] = m.expanded_total;
  j["replan_expanded"] = m.replan_expanded;
  if (run.navigator().config().compare_astar) {
    j["astar_replan_expanded"] = m.astar_replan_expanded;
    j["astar_backward_replan_expanded"] = m.astar_backward_replan_expanded;
    j["costs_match_astar"] = m.costs_match;
  }
  j["collisions"] = m.collisions;
  j["deviation_mean_m"] = m.deviation_mean_m;
  j["deviation_max_m"] = m.deviation_max_m;
  const Navigator& nav = run.navigator();
  j["map"] = {{"width", nav.map().width()},
              {"height", nav.map().height()},
              {"resolution_m", nav.map().geometry().resolution},
              {"barrier_distance_m", nav.config().map.barrier_distance_m}};
  nlohmann::ordered_json sim = nlohmann::ordered_json::parse(metrics_json(run.simulation()));
  j["sim"] = sim;
  return j.dump(2) + "\n";
}

std::string paths_csv(const NavigationRun& run) {
  std::string out = "plan_id,t_s,x_m,y_m\n";
  for (const NavPlan& p : run.navigator().plans())
    for (const Vec2& v : p.points)
      out += std::to_string(p.id) + ',' + format_fixed6(p.t_s) + ',' + format_fixed6(v.x()) + ',' + format_fixed6(v.y()) + '\n';
  return out;
}

namespace {

std::string replans_csv(const NavigationRun& run) {
  const bool compare = run.navigator().config().compare_astar;
  std::string out = "plan_id,t_s,cause,status,expanded,cost_m,time_ms";
  if (compare) out += ",astar_status,astar_expanded,astar_cost_m,astar_backward_expanded,astar_backward_cost_m";
  out += '\n';
  for (const NavPlan& p : run.navigator().plans()) {
    char ms[32];
    std::snprintf(ms, sizeof ms, "%.3f", p.time_ms);
    out += std::to_string(p.id) + ',' + format_fixed6(p.t_s) + ',' + p.cause + ',' + p.status + ',' +
           std::to_string(p.expanded) + ',' + format_fixed6(p.cost_m) + ',' + ms;
    if (compare)
      out += ',' + p.astar_status + ',' + std::to_string(p.astar_expanded) + ',' + format_fixed6(p.astar_cost_m) + ',' +
             std::to_string(p.astar_backward_expanded) + ',' + format_fixed6(p.astar_backward_cost_m);
    out += '\n';
  }
  return out;
}

// Millimetres for poses and paths, centimetres for LiDAR hits (the map's cells are 5-10 cm):
// enough for a viewer, a fraction of the bytes of six decimals.
double mm(double v) { return unsigned_zero(std::round(v * 1000.0) / 1000.0); }
double cm(double v) { return unsigned_zero(std::round(v * 100.0) / 100.0); }

std::string steps_jsonl(const NavigationRun& run) {
  std::string out;
  const auto& plans = run.navigator().plans();
  for (const NavStepRecord& r : run.steps()) {
    nlohmann::ordered_json j;
    j["t_s"] = mm(r.t_s);
    const Vec3 rpy = r.pose.rpy();
    j["pose"] = {mm(r.pose.position.x()), mm(r.pose.position.y()), mm(r.pose.position.z()),
                 mm(rpy.x()),             mm(rpy.y()),             mm(rpy.z())};
    j["returns"] = r.returns;
    nlohmann::ordered_json hits = nlohmann::ordered_json::array();
    for (const Vec3& p : r.hits) hits.push_back({cm(p.x()), cm(p.y()), cm(p.z())});
    j["hits"] = std::move(hits);
    nlohmann::ordered_json changed = nlohmann::ordered_json::array();
    for (const auto& [c, v] : r.changed) changed.push_back({c.x, c.y, static_cast<int>(v)});
    j["changed"] = std::move(changed);
    j["path_id"] = r.path_id;
    if (r.new_path && r.path_id > 0) {
      nlohmann::ordered_json path = nlohmann::ordered_json::array();
      for (const Vec2& v : plans[static_cast<std::size_t>(r.path_id - 1)].points) path.push_back({mm(v.x()), mm(v.y())});
      j["path"] = std::move(path);
    }
    out += j.dump() + '\n';
  }
  return out;
}

}  // namespace

void write_navigation_records(const NavigationRun& run, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path d(dir);
  write_simulation_records(run.simulation(), dir);  // trajectory.csv, events.csv, sensors; metrics.json replaced below
  write_file_bytes((d / "metrics.json").string(), navigation_metrics_json(run));
  write_file_bytes((d / "paths.csv").string(), paths_csv(run));
  write_file_bytes((d / "replans.csv").string(), replans_csv(run));
  if (run.options().record_steps) write_file_bytes((d / "steps.jsonl").string(), steps_jsonl(run));
  write_ros_map(run.navigator().map().occupancy(), (d / "map.yaml").string());

  const SimulationMetrics s = run.simulation().metrics();
  nlohmann::ordered_json t;
  t["wall_s"] = run.wall_s();
  t["setup_s"] = run.setup_s();
  t["sim_s"] = s.duration_s;
  t["real_time_factor"] = run.wall_s() > 0.0 ? s.duration_s / run.wall_s() : 0.0;
  t["steps"] = s.steps;
  t["lidar_rays"] = s.lidar_rays;
  double plan_ms = 0.0;
  for (const NavPlan& p : run.navigator().plans()) plan_ms += p.time_ms;
  t["planning_ms"] = plan_ms;
  write_file_bytes((d / "timing.json").string(), t.dump(2) + "\n");
}

}  // namespace starnav
