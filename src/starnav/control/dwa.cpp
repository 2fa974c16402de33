#include "starnav/control/dwa.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/planar_motion.hpp"

namespace starnav {

namespace {

void dwa_require(bool ok, const char* field, const char* what) {
  if (!ok) throw Error(what, "", 0, field);
}

}  // namespace

void DwaConfig::validate() const {
  dwa_require(vx_samples >= 1 && vx_samples <= 201, "vx_samples", "must be in [1, 201]");
  dwa_require(vy_samples >= 1 && vy_samples <= 201, "vy_samples", "must be in [1, 201]");
  dwa_require(wz_samples >= 1 && wz_samples <= 201, "wz_samples", "must be in [1, 201]");
  dwa_require(static_cast<double>(vx_samples) * vy_samples * wz_samples <= 1e5, "vx_samples",
          "vx_samples x vy_samples x wz_samples must be at most 100,000");
  dwa_require(std::isfinite(sim_time_s) && sim_time_s > 0.0 && sim_time_s <= 10.0, "sim_time_s", "must be in (0, 10] s");
  dwa_require(std::isfinite(sim_step_s) && sim_step_s > 0.0 && sim_step_s <= sim_time_s, "sim_step_s",
          "must be > 0 and at most sim_time_s");
  dwa_require(sim_time_s / sim_step_s <= 1000.0, "sim_step_s", "sim_time_s / sim_step_s must be at most 1,000");
  dwa_require(std::isfinite(control_period_s) && control_period_s > 0.0 && control_period_s <= 1.0, "control_period_s",
          "must be in (0, 1] s");
  dwa_require(std::isfinite(max_vx_mps) && max_vx_mps > 0.0, "max_vx_mps", "must be > 0");
  dwa_require(std::isfinite(min_vx_mps) && min_vx_mps <= 0.0 && -min_vx_mps <= max_vx_mps, "min_vx_mps",
          "must be in [-max_vx_mps, 0]");
  dwa_require(std::isfinite(max_vy_mps) && max_vy_mps >= 0.0, "max_vy_mps", "must be >= 0");
  dwa_require(std::isfinite(max_speed_xy_mps) && max_speed_xy_mps > 0.0, "max_speed_xy_mps", "must be > 0");
  dwa_require(std::isfinite(max_yaw_rate_radps) && max_yaw_rate_radps > 0.0, "max_yaw_rate_degps", "must be > 0");
  dwa_require(std::isfinite(acc_x_mps2) && acc_x_mps2 > 0.0, "acc_x_mps2", "must be > 0");
  dwa_require(std::isfinite(acc_y_mps2) && acc_y_mps2 > 0.0, "acc_y_mps2", "must be > 0");
  dwa_require(std::isfinite(acc_yaw_radps2) && acc_yaw_radps2 > 0.0, "acc_yaw_degps2", "must be > 0");
  dwa_require(footprint == "rectangle" || footprint == "circle", "footprint", "must be rectangle or circle");
  dwa_require(std::isfinite(footprint_radius_m) && footprint_radius_m >= 0.0 && footprint_radius_m <= 10.0,
          "footprint_radius_m", "must be in [0, 10] m");
  dwa_require(std::isfinite(safety_margin_m) && safety_margin_m >= 0.0 && safety_margin_m <= 1.0, "safety_margin_m",
          "must be in [0, 1] m");
  dwa_require(std::isfinite(forward_point_m) && forward_point_m >= 0.0 && forward_point_m <= 5.0, "forward_point_m",
          "must be in [0, 5] m");
  dwa_require(align == "auto" || align == "heading" || align == "motion", "align", "must be auto, heading or motion");
  dwa_require(std::isfinite(holonomic_approach_m) && holonomic_approach_m >= 0.0 && holonomic_approach_m <= 100.0,
              "holonomic_approach_m", "must be in [0, 100] m");
  dwa_require(std::isfinite(window_m) && window_m >= 0.0 && window_m <= 50.0, "window_m", "must be in [0, 50] m");
  dwa_require(std::isfinite(inflation_radius_m) && inflation_radius_m >= 0.0 && inflation_radius_m <= 10.0,
          "inflation_radius_m", "must be in [0, 10] m");
  dwa_require(std::isfinite(cost_scaling_per_m) && cost_scaling_per_m >= 0.0, "cost_scaling_per_m", "must be >= 0");
  dwa_require(std::isfinite(oscillation_reset_m) && oscillation_reset_m > 0.0, "oscillation_reset_m", "must be > 0");
  dwa_require(std::isfinite(oscillation_reset_rad) && oscillation_reset_rad > 0.0, "oscillation_reset_deg", "must be > 0");
  for (const auto& [w, field] : {std::pair{path_align_weight, "path_align_weight"}, {path_dist_weight, "path_dist_weight"},
                                 {goal_align_weight, "goal_align_weight"}, {goal_dist_weight, "goal_dist_weight"},
                                 {obstacle_weight, "obstacle_weight"}, {velocity_weight, "velocity_weight"},
                                 {twirling_weight, "twirling_weight"}, {path_angle_weight, "path_angle_weight"},
                                 {prefer_forward_weight, "prefer_forward_weight"},
                                 {oscillation_weight, "oscillation_weight"}, {rotate_to_goal_weight, "rotate_to_goal_weight"}})
    dwa_require(std::isfinite(w) && w >= 0.0 && w <= 1e6, field, "must be in [0, 1e6]");
}

const ParamTable<DwaConfig>& dwa_params() {
  static const ParamTable<DwaConfig> table = [] {
    using C = DwaConfig;
    ParamTable<C> t;
    const double deg = kPi / 180.0;
    t.integer("vx_samples", &C::vx_samples, closed(1, 201), "", "forward velocities sampled across the window");
    t.integer("vy_samples", &C::vy_samples, closed(1, 201), "", "sideways velocities sampled (holonomic robots; others: 1)");
    t.integer("wz_samples", &C::wz_samples, closed(1, 201), "", "yaw rates sampled across the window");
    t.real("sim_time_s", &C::sim_time_s, open(0.0, 10.0), "s", "horizon each sample is rolled out over and scored");
    t.real("sim_step_s", &C::sim_step_s, positive(), "s", "time between the rollout's poses");
    t.real("control_period_s", &C::control_period_s, open(0.0, 1.0), "s",
           "time until the next command: the dynamic window's reach");
    t.real("max_vx_mps", &C::max_vx_mps, positive(), "m/s", "forward speed limit (also the robot's)");
    t.real("min_vx_mps", &C::min_vx_mps, closed(-10.0, 0.0), "m/s", "slowest forward speed; < 0 drives backwards");
    t.real("max_vy_mps", &C::max_vy_mps, non_negative(), "m/s", "sideways speed limit (holonomic robots)");
    t.real("max_speed_xy_mps", &C::max_speed_xy_mps, positive(), "m/s", "limit of the translation's speed");
    t.real("max_yaw_rate_degps", &C::max_yaw_rate_radps, positive(), "deg/s", "yaw rate limit", deg);
    t.real("acc_x_mps2", &C::acc_x_mps2, positive(), "m/s^2", "forward acceleration and braking limit");
    t.real("acc_y_mps2", &C::acc_y_mps2, positive(), "m/s^2", "sideways acceleration and braking limit");
    t.real("acc_yaw_degps2", &C::acc_yaw_radps2, positive(), "deg/s^2", "yaw acceleration limit", deg);
    t.choice("footprint", {"rectangle", "circle"}, [](C& c, const std::string& v) { c.footprint = v; },
             [](const C& c) { return c.footprint; }, "rectangle: the robot's body; circle: footprint_radius_m");
    t.real("footprint_radius_m", &C::footprint_radius_m, closed(0.0, 10.0), "m",
           "circle footprint radius; 0: the body's circumscribed radius");
    t.real("safety_margin_m", &C::safety_margin_m, closed(0.0, 1.0), "m", "the footprint grown by this for collision tests");
    t.real("forward_point_m", &C::forward_point_m, closed(0.0, 5.0), "m", "look-ahead of the alignment critics");
    t.choice("align", {"auto", "heading", "motion"}, [](C& c, const std::string& v) { c.align = v; },
             [](const C& c) { return c.align; },
             "alignment critics look along the heading or the motion; auto: the motion for a holonomic robot, the "
             "heading otherwise");
    t.real("holonomic_approach_m", &C::holonomic_approach_m, closed(0.0, 100.0), "m",
           "path_angle: within this of a goal with a heading the body turns to that heading, not along the path");
    t.real("window_m", &C::window_m, closed(0.0, 50.0), "m", "side of the local window; 0: what the rollouts need");
    t.real("inflation_radius_m", &C::inflation_radius_m, closed(0.0, 10.0), "m",
           "obstacle critic: proximity costs nothing beyond this distance");
    t.real("cost_scaling_per_m", &C::cost_scaling_per_m, non_negative(), "1/m", "obstacle critic: decay of the cost");
    t.real("oscillation_reset_m", &C::oscillation_reset_m, positive(), "m",
           "an axis may reverse again after the robot moved this far");
    t.real("oscillation_reset_deg", &C::oscillation_reset_rad, positive(), "deg", "or turned this far", deg);
    t.real("path_align_weight", &C::path_align_weight, closed(0.0, 1e6), "1/m", "weight of the path_align critic");
    t.real("path_dist_weight", &C::path_dist_weight, closed(0.0, 1e6), "1/m", "weight of the path_dist critic");
    t.real("goal_align_weight", &C::goal_align_weight, closed(0.0, 1e6), "1/m", "weight of the goal_align critic");
    t.real("goal_dist_weight", &C::goal_dist_weight, closed(0.0, 1e6), "1/m", "weight of the goal_dist critic");
    t.real("obstacle_weight", &C::obstacle_weight, closed(0.0, 1e6), "", "weight of the obstacle critic");
    t.real("velocity_weight", &C::velocity_weight, closed(0.0, 1e6), "", "weight of the velocity critic");
    t.real("twirling_weight", &C::twirling_weight, closed(0.0, 1e6), "", "weight of the twirling critic (holonomic robots)");
    t.real("path_angle_weight", &C::path_angle_weight, closed(0.0, 1e6), "1/rad", "weight of the path_angle critic");
    t.real("prefer_forward_weight", &C::prefer_forward_weight, closed(0.0, 1e6), "", "weight of the prefer_forward critic");
    t.real("oscillation_weight", &C::oscillation_weight, closed(0.0, 1e6), "", "cost of reversing an axis twice");
    t.real("rotate_to_goal_weight", &C::rotate_to_goal_weight, closed(0.0, 1e6), "1/rad",
           "weight of the rotate_to_goal critic");
    return t;
  }();
  return table;
}

DwaLimits dwa_limits(const DwaConfig& c, const VelocityLimits& robot, bool holonomic) {
  DwaLimits l;
  l.max_vx = std::min(c.max_vx_mps, robot.max_vx_mps);
  l.min_vx = std::max(c.min_vx_mps, -robot.max_vx_mps);
  l.max_vy = holonomic ? std::min(c.max_vy_mps, robot.max_vy_mps) : 0.0;
  l.max_wz = std::min(c.max_yaw_rate_radps, robot.max_yaw_rate_radps);
  l.max_speed_xy = std::min(c.max_speed_xy_mps, robot.max_speed_mps);
  l.acc_x = c.acc_x_mps2;
  l.acc_y = c.acc_y_mps2;
  l.acc_yaw = c.acc_yaw_radps2;
  return l;
}

DynamicWindow dynamic_window(const BodyTwist& v, const DwaLimits& l, double period_s) {
  const auto axis = [period_s](double v0, double a, double lo, double hi) {
    return std::pair{std::clamp(v0 - a * period_s, lo, hi), std::clamp(v0 + a * period_s, lo, hi)};
  };
  DynamicWindow w;
  std::tie(w.vx_lo, w.vx_hi) = axis(v.vx, l.acc_x, l.min_vx, l.max_vx);
  std::tie(w.vy_lo, w.vy_hi) = axis(v.vy, l.acc_y, -l.max_vy, l.max_vy);
  std::tie(w.wz_lo, w.wz_hi) = axis(v.wz, l.acc_yaw, -l.max_wz, l.max_wz);
  return w;
}

std::vector<double> window_samples(double lo, double hi, int n) {
  std::vector<double> out;
  if (n <= 1 || hi <= lo) {
    out.push_back(std::clamp(0.0, lo, hi));
    return out;
  }
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out.push_back(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1));
  if (lo <= 0.0 && hi >= 0.0) {
    auto nearest = std::min_element(out.begin(), out.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    *nearest = 0.0;
  }
  return out;
}

double dwa_check_time(const BodyTwist& t, const DwaLimits& l, double sim_time_s, double period_s, double lag_s) {
  const double braking = std::max({std::abs(t.vx) / l.acc_x, std::abs(t.vy) / l.acc_y, std::abs(t.wz) / l.acc_yaw});
  return std::max(sim_time_s, period_s + lag_s + 0.5 * braking);
}

void dwa_rollout(const Pose2& start, const BodyTwist& t, double step_s, int n, std::vector<Pose2>& out,
                 std::vector<Vec2>* headings) {
  const std::size_t count = static_cast<std::size_t>(std::max(n, 0));
  out.resize(count);
  if (headings) headings->resize(count);
  const Pose2 step = advance_on_arc(Pose2(), t.vx, t.vy, t.wz, step_s);
  const double cd = std::cos(step.yaw), sd = std::sin(step.yaw);
  double x = start.x, y = start.y, yaw = start.yaw, c = std::cos(start.yaw), s = std::sin(start.yaw);
  for (std::size_t k = 0; k < count; ++k) {
    x += c * step.x - s * step.y;
    y += s * step.x + c * step.y;
    yaw += step.yaw;
    if (yaw > kPi) yaw -= 2.0 * kPi;
    else if (yaw <= -kPi) yaw += 2.0 * kPi;
    const double c_next = c * cd - s * sd;
    s = s * cd + c * sd;
    c = c_next;
    out[k] = Pose2(x, y, yaw);
    if (headings) (*headings)[k] = Vec2(c, s);
  }
}

}  // namespace starnav
