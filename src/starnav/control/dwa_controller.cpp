#include "starnav/control/dwa_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {

constexpr double kNoCost = std::numeric_limits<double>::infinity();

// Exit parameter s in [0, 1] of the segment a -> b from the box [lo, hi]^2 (a inside).
double box_exit(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi) {
  double s = 1.0;
  for (int k = 0; k < 2; ++k) {
    const double d = b[k] - a[k];
    if (d > 0.0 && b[k] > hi[k]) s = std::min(s, (hi[k] - a[k]) / d);
    if (d < 0.0 && b[k] < lo[k]) s = std::min(s, (lo[k] - a[k]) / d);
  }
  return std::clamp(s, 0.0, 1.0);
}

bool inside_box(const Vec2& p, const Vec2& lo, const Vec2& hi) {
  return p.x() >= lo.x() && p.y() >= lo.y() && p.x() <= hi.x() && p.y() <= hi.y();
}

Vec2 projection_on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return a + s * d;
}

}  // namespace

DwaController::DwaController(const DwaConfig& config, const RobotConfig& robot) : config_(config), robot_(robot) {
  config_.validate();
  model_ = make_robot_model(robot_);
  if (!model_->turns_in_place())
    throw Error("the DWA controller needs a robot that turns in place (mecanum or differential)", "", 0, "controller");
  holonomic_ = model_->holonomic();
  limits_ = dwa_limits(config_, velocity_limits_of(robot_), holonomic_);
  FootprintModel fm;
  if (config_.footprint == "circle") {
    fm.circle = true;
    fm.radius_m = config_.footprint_radius_m > 0.0 ? config_.footprint_radius_m : footprint_of(robot_).circumscribed_radius_m();
  } else {
    fm.circle = false;
    fm.half_length_m = 0.5 * robot_.body_length_m;
    fm.half_width_m = 0.5 * robot_.body_width_m;
  }
  checker_ = FootprintChecker(fm, config_.safety_margin_m);
  critics_ = make_dwa_critics(config_, holonomic_);
  wheel_scratch_.resize(static_cast<std::size_t>(model_->actuator_count()));
}

DwaController::~DwaController() = default;

void DwaController::set_path(std::span<const Vec2> points) {
  if (points.empty()) throw Error("empty path", {}, 0, "path");
  for (const Vec2& p : points)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) throw Error("non-finite path point", {}, 0, "path");
  path_.clear();
  for (const Vec2& p : points)
    if (path_.empty() || (p - path_.back()).norm() > 1e-9) path_.push_back(p);
  segment_ = 0;
  in_goal_window_ = false;
  for (auto& c : critics_) c->reset();
}

void DwaController::clear() {
  path_.clear();
  segment_ = 0;
  in_goal_window_ = false;
  for (auto& c : critics_) c->reset();
}

bool DwaController::swept_footprint_collides(double extra_m) {
  // The quick test over every pose first: a certain collision anywhere settles the sample before
  // any exact test runs.
  unsure_.clear();
  for (std::size_t k = 0; k < poses_.size(); ++k) {
    switch (checker_.quick_test(map_, poses_[k], headings_[k], extra_m)) {
      case FootprintTest::Clear: break;
      case FootprintTest::Collides: return true;
      case FootprintTest::Unsure: unsure_.push_back(k); break;
    }
  }
  for (const std::size_t k : unsure_)
    if (checker_.exact_test(map_, poses_[k], headings_[k], extra_m)) return true;
  return false;
}

void DwaController::update_progress(const Vec2& p) {
  if (path_.size() < 2) return;
  // The nearest segment within a stretch ahead (progress never goes back, so a path that passes
  // the robot twice is followed in order).
  const double stretch = 4.0 + config_.window_m;
  double best = kNoCost, ahead = 0.0;
  std::size_t best_i = segment_;
  for (std::size_t i = segment_; i + 1 < path_.size() && ahead <= stretch; ++i) {
    const double d = (p - projection_on_segment(p, path_[i], path_[i + 1])).norm();
    if (d < best - 1e-12) {
      best = d;
      best_i = i;
    }
    ahead += (path_[i + 1] - path_[i]).norm();
  }
  segment_ = best_i;
}

void DwaController::build_local_path(DwaScene& s) const {
  s.local_path.clear();
  const Vec2 p = s.pose.translation();
  if (path_.size() == 1) {
    s.local_path.push_back(path_[0]);
  } else {
    s.local_path.push_back(projection_on_segment(p, path_[segment_], path_[segment_ + 1]));
  }
  // The window's interior in cell coordinates, one cell in from its edge.
  const GridGeometry& g = map_.geometry();
  const Vec2 lo(1.0, 1.0), hi(g.width - 1.0, g.height - 1.0);
  bool reached_end = path_.size() == 1;
  if (!reached_end && inside_box(g.world_to_cell_continuous(s.local_path[0]), lo, hi)) {
    reached_end = true;
    for (std::size_t i = segment_ + 1; i < path_.size(); ++i) {
      const Vec2 a = g.world_to_cell_continuous(s.local_path.back());
      const Vec2 b = g.world_to_cell_continuous(path_[i]);
      if (inside_box(b, lo, hi)) {
        s.local_path.push_back(path_[i]);
        continue;
      }
      const double t = box_exit(a, b, lo, hi);
      s.local_path.push_back(s.local_path.back() + t * (path_[i] - s.local_path.back()));
      reached_end = false;
      break;
    }
  } else if (path_.size() > 1) {
    reached_end = false;
  }
  // A local goal inside an obstacle (something stands on the path): back along the path to the
  // last point the wavefront can reach.
  const double step = 0.5 * map_.resolution();
  const auto passable = [&](const Vec2& q) {
    const Cell c = map_.cell_of(q);
    return map_.contains(c.x, c.y) && map_.clearance_m(map_.index(c.x, c.y)) >= s.pass_clearance_m;
  };
  while (s.local_path.size() > 1 && !passable(s.local_path.back())) {
    const Vec2 a = s.local_path[s.local_path.size() - 2];
    Vec2& b = s.local_path.back();
    const double len = (b - a).norm();
    reached_end = false;
    if (len <= step) {
      s.local_path.pop_back();
      continue;
    }
    b = a + (b - a) * ((len - step) / len);
  }
  s.local_goal = s.local_path.back();
  s.local_goal_is_goal = reached_end;
  s.align_path = s.local_path;
  if (reached_end && path_.size() >= 2) {
    const Vec2 d = path_.back() - path_[path_.size() - 2];
    s.align_path.push_back(path_.back() + config_.forward_point_m * d.normalized());
  }
  s.align_goal = s.align_path.back();
  // The body's heading: along the path where the robot is, or the goal's on the final approach.
  s.path_heading.reset();
  if (s.goal_yaw && s.distance_to_goal_m <= config_.holonomic_approach_m) {
    s.path_heading = s.goal_yaw;
  } else if (s.local_path.size() >= 2) {
    const Vec2 d = s.local_path[1] - s.local_path[0];
    if (d.norm() > 1e-9) s.path_heading = std::atan2(d.y(), d.x());
  } else if (path_.size() >= 2 && segment_ + 1 < path_.size()) {
    const Vec2 d = path_[segment_ + 1] - path_[segment_];
    if (d.norm() > 1e-9) s.path_heading = std::atan2(d.y(), d.x());
  }
}

ControlOutput DwaController::compute(const ControlInput& in) {
  last_ = DwaStepRecord{};
  last_.t_s = in.t_s;
  last_.pose = in.pose;
  if (path_.empty()) return {};
  if (!in.local_map) throw Error("the DWA controller needs a local obstacle map", "", 0, "local_map");
  DwaScene& s = scene_;
  s.pose = in.pose;
  s.velocity = in.velocity;
  s.goal = path_.back();
  s.goal_yaw = in.goal_yaw;
  s.distance_to_goal_m = (in.pose.translation() - s.goal).norm();
  // Within the tolerance (or once the navigator has latched it) only the heading is left.
  in_goal_window_ = in.goal_xy_reached || s.distance_to_goal_m <= in.goal_tolerance_m;
  s.in_goal_window = in_goal_window_;
  if (in_goal_window_ && (!s.goal_yaw || std::abs(wrap_angle(*s.goal_yaw - in.pose.yaw)) <= in.goal_yaw_tolerance_rad)) {
    last_.status = ControlStatus::Arrived;
    return {{}, ControlStatus::Arrived};
  }
  s.align_by_motion = config_.align == "motion" || (config_.align == "auto" && holonomic_);
  // The step's limits (a speed-limit zone lowers them); the window's extent keeps the robot's own.
  const DwaLimits limits = dwa_limits(config_, in.limits, holonomic_);
  s.limits = limits;
  s.period_s = config_.control_period_s;

  // The window: everything a rollout, its forward point and its footprint can reach.
  const double res = in.local_map->resolution();
  const FootprintModel& fm = checker_.model();
  const WindowExtent window = window_extent(res);
  if (in.clearance) map_.build(*in.clearance, in.pose.translation(), window.half_m, window.pad_m);
  else map_.build(*in.local_map, in.pose.translation(), window.half_m, window.pad_m);
  s.map = &map_;
  s.pass_clearance_m = 0.5 * fm.inscribed_radius_m();

  update_progress(in.pose.translation());
  build_local_path(s);
  last_.local_goal = s.local_goal;
  const Cell goal_cell = map_.cell_of(s.local_goal);
  map_.wavefront(std::span<const Cell>(&goal_cell, 1), s.pass_clearance_m, s.goal_distance);
  s.obstacle_cost.resize(static_cast<std::size_t>(map_.width()) * static_cast<std::size_t>(map_.height()));
  const double r_in = fm.inscribed_radius_m();
  for (std::size_t i = 0; i < s.obstacle_cost.size(); ++i) {
    const double d = map_.clearance_m(i);
    s.obstacle_cost[i] = d >= config_.inflation_radius_m ? 0.0 : (d <= r_in ? 1.0 : std::exp(-config_.cost_scaling_per_m * (d - r_in)));
  }
  for (auto& c : critics_) c->prepare(s);

  // A robot already inside its safety margin (pushed there, or the margin grew with the map) may
  // still move, but never closer: the margin shrinks to what it has now for this step.
  double margin_cut = 0.0;
  if (checker_.collides(map_, in.pose)) {
    const double full = checker_.grow_m() + res * std::sqrt(0.5);
    if (checker_.collides(map_, in.pose, -full)) {
      last_.status = ControlStatus::Blocked;  // touching: nothing is safe
      return {{}, ControlStatus::Blocked};
    }
    double lo = 0.0, hi = full;  // collides at -lo, clear at -hi
    for (int k = 0; k < 12; ++k) {
      const double mid = 0.5 * (lo + hi);
      (checker_.collides(map_, in.pose, -mid) ? lo : hi) = mid;
    }
    margin_cut = hi;
  }
  last_.margin_cut_m = margin_cut;

  // The samples.
  const DynamicWindow w = dynamic_window(in.velocity, limits, config_.control_period_s);
  last_.window = w;
  std::vector<double> vxs, vys;
  if (in_goal_window_) {
    // Only turning: the translation nearest rest the window allows.
    vxs = {std::clamp(0.0, w.vx_lo, w.vx_hi)};
    vys = {std::clamp(0.0, w.vy_lo, w.vy_hi)};
  } else {
    vxs = window_samples(w.vx_lo, w.vx_hi, config_.vx_samples);
    vys = window_samples(w.vy_lo, w.vy_hi, holonomic_ ? config_.vy_samples : 1);
  }
  const std::vector<double> wzs = window_samples(w.wz_lo, w.wz_hi, config_.wz_samples);
  const int n_score = std::max(1, static_cast<int>(std::lround(config_.sim_time_s / config_.sim_step_s)));
  const double wheel_limit = robot_.max_wheel_speed_radps * (1.0 + 1e-9);

  // Every sample is scored first; the footprint is then tested in the order of cost, and the first
  // sample that is clear is the cheapest valid one (ties to the sampling order), exactly as if
  // all had been tested. With keep_samples every sample is tested (for the pictures).
  double best = kNoCost;
  BodyTwist best_twist;
  int best_index = -1, index = -1;
  candidates_.clear();
  for (const double vx : vxs)
    for (const double vy : vys)
      for (const double wz : wzs) {
        ++index;
        const BodyTwist t{vx, vy, wz};
        DwaSample rec;
        rec.twist = t;
        // Inside the wheels' speed limit and the translation's.
        model_->inverse(t, wheel_scratch_);
        bool feasible = std::hypot(vx, vy) <= limits.max_speed_xy * (1.0 + 1e-9);
        for (const double a : wheel_scratch_) feasible = feasible && std::abs(a) <= wheel_limit;
        if (!feasible) {
          if (keep_samples_) last_.samples.push_back(rec);
          continue;
        }
        const double t_check = dwa_check_time(t, limits, config_.sim_time_s, config_.control_period_s, robot_.actuator_lag_s);
        const int n_check = std::max(n_score, static_cast<int>(std::ceil(t_check / config_.sim_step_s - 1e-9)));
        dwa_rollout(in.pose, t, config_.sim_step_s, n_check, poses_, &headings_);
        rec.end = poses_[static_cast<std::size_t>(n_score - 1)];
        // Between two tested poses no point of the footprint moves more than `step`; growing the
        // footprint by half of it covers the swept area.
        const double extra =
            0.5 * (std::hypot(vx, vy) + std::abs(wz) * fm.bounding_radius_m()) * config_.sim_step_s - margin_cut;
        const DwaRollout r{t, std::span<const Pose2>(poses_.data(), static_cast<std::size_t>(n_score))};
        double cost = 0.0;
        for (const auto& c : critics_) {
          const double v = c->score(s, r);
          if (!std::isfinite(v)) {
            cost = kNoCost;
            break;
          }
          cost += c->weight() * v;
        }
        if (keep_samples_) {
          rec.collides = swept_footprint_collides(extra);
          rec.valid = !rec.collides && std::isfinite(cost);
          rec.cost = cost;
          if (rec.valid && cost < best) {
            best = cost;
            best_twist = t;
            best_index = index;
          }
          last_.samples.push_back(rec);
        } else if (std::isfinite(cost)) {
          candidates_.push_back({cost, index, t, n_check, extra});
        }
      }
  if (!keep_samples_) {
    std::sort(candidates_.begin(), candidates_.end(),
              [](const Candidate& a, const Candidate& b) { return a.cost < b.cost || (a.cost == b.cost && a.index < b.index); });
    for (const Candidate& c : candidates_) {
      dwa_rollout(in.pose, c.twist, config_.sim_step_s, c.n_check, poses_, &headings_);
      if (swept_footprint_collides(c.extra)) continue;
      best = c.cost;
      best_twist = c.twist;
      best_index = c.index;
      break;
    }
  }
  last_.chosen = best_index;
  if (best_index < 0) {
    last_.status = ControlStatus::Blocked;
    return {{}, ControlStatus::Blocked};
  }
  for (auto& c : critics_) c->chosen(s, best_twist);
  last_.status = ControlStatus::Tracking;
  return {best_twist, ControlStatus::Tracking};
}

DwaController::WindowExtent DwaController::window_extent(double res) const {
  const FootprintModel& fm = checker_.model();
  const BodyTwist fastest{limits_.max_vx, limits_.max_vy, limits_.max_wz};
  const double check_max = dwa_check_time(fastest, limits_, config_.sim_time_s, config_.control_period_s, robot_.actuator_lag_s);
  const double max_step = (limits_.max_speed_xy + limits_.max_wz * fm.bounding_radius_m()) * config_.sim_step_s;
  const double outer = fm.bounding_radius_m() + checker_.grow_m() + 0.5 * max_step + res;
  WindowExtent w;
  w.half_m = config_.window_m > 0.0 ? 0.5 * config_.window_m : limits_.max_speed_xy * check_max + config_.forward_point_m + outer + 2.0 * res;
  w.pad_m = std::max(outer, config_.inflation_radius_m) + res;
  return w;
}

std::optional<ControlDiagnostics> DwaController::diagnostics() const {
  if (!keep_samples_) return std::nullopt;
  ControlDiagnostics d;
  d.t_s = last_.t_s;
  d.pose = last_.pose;
  d.status = last_.status;
  const int n = std::max(1, static_cast<int>(std::lround(config_.sim_time_s / config_.sim_step_s)));
  for (const DwaSample& x : last_.samples) {
    ControlCandidate c;
    c.twist = x.twist;
    c.status = x.valid ? CandidateStatus::Valid : (x.collides ? CandidateStatus::Collides : CandidateStatus::Rejected);
    c.cost = x.cost;
    dwa_rollout(last_.pose, x.twist, config_.sim_step_s, n, c.trajectory);
    d.candidates.push_back(std::move(c));
  }
  d.chosen = last_.chosen;
  if (last_.chosen >= 0 && static_cast<std::size_t>(last_.chosen) < last_.samples.size())
    d.command = last_.samples[static_cast<std::size_t>(last_.chosen)].twist;
  d.points.emplace_back("local goal", last_.local_goal);
  d.terms.emplace_back("margin_cut_m", last_.margin_cut_m);
  return d;
}

LocalControllerDef dwa_controller() {
  LocalControllerDef d;
  d.info.role = Role::LocalController;
  d.info.name = "dwa";
  d.info.section = "dwa";
  d.info.summary = "Dynamic Window Approach (Fox et al. 1997) with Nav2 DWB's critics; samples vy on a Mecanum base";
  d.info.capabilities = {Capability::GoalHeading, Capability::ChecksFootprint, Capability::VelocitySpace};
  d.info.nav2_counterpart = "dwb_core::DWBLocalPlanner";
  d.info.params = dwa_params().specs();
  d.make = [](const LocalControllerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<LocalController> {
    const DwaConfig c = configured(dwa_params(), settings, ctx.file);
    try {
      auto controller = std::make_unique<DwaController>(c, ctx.robot);
      // The window is rebuilt at every command: its cells are judged before the first.
      if (ctx.map_resolution_m > 0.0) {
        const DwaController::WindowExtent w = controller->window_extent(ctx.map_resolution_m);
        const double cells = clearance_window_cells(w.half_m, w.pad_m, ctx.map_resolution_m);
        if (!(cells <= kMaxClearanceWindowCells)) {
          const double side = std::sqrt(cells);
          const bool padding = c.window_m <= 0.0 && c.inflation_radius_m + ctx.map_resolution_m >= w.pad_m;
          throw Error((c.window_m > 0.0 ? "window_m " + format_readable(c.window_m) + " m"
                                        : "the window the rollouts reach (window_m 0: " + format_readable(2.0 * w.half_m) + " m)") +
                          ", padded by " + format_readable(w.pad_m) + " m (the footprint, inflation_radius_m " +
                          format_readable(c.inflation_radius_m) + " m), over navigation.map.resolution_m " +
                          format_readable(ctx.map_resolution_m) + " m gives a window of " + format_number(side) + " x " +
                          format_number(side) + " cells, more than " + format_number(kMaxClearanceWindowCells) +
                          (padding ? ": lower inflation_radius_m or coarsen the map" : ": shrink window_m or coarsen the map"),
                      "", 0, padding ? "inflation_radius_m" : "window_m");
        }
      }
      return controller;
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
  };
  return d;
}

}  // namespace starnav
