#include "starnav/robot/robot_model.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/error.hpp"

namespace starnav {

const char* drive_kind_name(DriveKind kind) {
  switch (kind) {
    case DriveKind::Mecanum: return "mecanum";
    case DriveKind::Differential: return "differential";
    case DriveKind::Ackermann: return "ackermann";
  }
  return "mecanum";
}

DriveKind parse_drive_kind(const std::string& s, const std::string& field) {
  if (s == "mecanum") return DriveKind::Mecanum;
  if (s == "differential") return DriveKind::Differential;
  if (s == "ackermann") return DriveKind::Ackermann;
  throw Error("unknown drive '" + s + "' (expected mecanum, differential or ackermann)", {}, 0, field);
}

namespace {

// RobotConfig's fields are named "robot.<field>" in errors.
std::string robot_field(const char* field) { return std::string("robot.") + field; }

// Mecanum wheels FL, FR, RL, RR at (+-L2, +-L1) with rollers at alpha (docs/papers/li2019.md):
//   w_FL = (vx - vy/t - k wz) / r,  w_FR = (vx + vy/t + k wz) / r,
//   w_RL = (vx + vy/t - k wz) / r,  w_RR = (vx - vy/t + k wz) / r,   t = tan(alpha), k = L1 + L2/t.
// Each row is the roller constraint of one wheel: (vx - wz y_i) -/+ (vy + wz x_i)/t.
class MecanumModel final : public RobotModel {
 public:
  explicit MecanumModel(const RobotConfig& c)
      : RobotModel(c), t_(std::tan(c.roller_angle_rad)), k_(c.half_track_m + c.half_wheelbase_m / t_) {}
  DriveKind kind() const override { return DriveKind::Mecanum; }
  bool holonomic() const override { return true; }
  bool turns_in_place() const override { return true; }
  int actuator_count() const override { return 4; }
  void inverse(const BodyTwist& v, std::span<double> w) const override {
    const double r = config_.wheel_radius_m, a = v.vy / t_, b = k_ * v.wz;
    w[0] = (v.vx - a - b) / r;
    w[1] = (v.vx + a + b) / r;
    w[2] = (v.vx + a - b) / r;
    w[3] = (v.vx - a + b) / r;
  }
  BodyTwist forward(std::span<const double> w) const override {
    const double r = config_.wheel_radius_m;
    BodyTwist v;
    v.vx = 0.25 * r * (w[0] + w[1] + w[2] + w[3]);
    v.vy = 0.25 * r * t_ * (-w[0] + w[1] + w[2] - w[3]);
    v.wz = 0.25 * r / k_ * (-w[0] + w[1] - w[2] + w[3]);
    return v;
  }
  std::vector<Vec2> wheel_contacts() const override {
    const double x = config_.half_wheelbase_m, y = config_.half_track_m;
    return {Vec2(x, y), Vec2(x, -y), Vec2(-x, y), Vec2(-x, -y)};
  }

 private:
  double t_, k_;
};

// Two driven wheels at y = +-L1 (L, R): w_L = (vx - L1 wz) / r, w_R = (vx + L1 wz) / r. vy is ignored.
class DifferentialModel final : public RobotModel {
 public:
  using RobotModel::RobotModel;
  DriveKind kind() const override { return DriveKind::Differential; }
  bool holonomic() const override { return false; }
  bool turns_in_place() const override { return true; }
  int actuator_count() const override { return 2; }
  void inverse(const BodyTwist& v, std::span<double> w) const override {
    const double r = config_.wheel_radius_m, l = config_.half_track_m;
    w[0] = (v.vx - l * v.wz) / r;
    w[1] = (v.vx + l * v.wz) / r;
  }
  BodyTwist forward(std::span<const double> w) const override {
    const double r = config_.wheel_radius_m, l = config_.half_track_m;
    return {0.5 * r * (w[0] + w[1]), 0.0, 0.5 * r * (w[1] - w[0]) / l};
  }
  // The driven wheels plus two casters at (+-L2, 0), so the contacts span a plane.
  std::vector<Vec2> wheel_contacts() const override {
    const double x = config_.half_wheelbase_m, y = config_.half_track_m;
    return {Vec2(0.0, y), Vec2(0.0, -y), Vec2(x, 0.0), Vec2(-x, 0.0)};
  }
};

// Bicycle model about the rear axle (base_link), wheelbase b = 2 L2. Actuators: rear wheel speed
// (rad/s) and steering angle (rad). forward: vx = r w, wz = vx tan(steer) / b.
// inverse (best effort where the twist is not realisable): vy is ignored; steer = atan(b wz / vx);
// with vx = 0 and wz != 0 the wheels are steered fully (+-pi/2 clamped later to max_steer) toward
// the turn and the robot does not move.
class AckermannModel final : public RobotModel {
 public:
  using RobotModel::RobotModel;
  DriveKind kind() const override { return DriveKind::Ackermann; }
  bool holonomic() const override { return false; }
  bool turns_in_place() const override { return false; }
  int actuator_count() const override { return 2; }
  void inverse(const BodyTwist& v, std::span<double> a) const override {
    const double b = 2.0 * config_.half_wheelbase_m;
    a[0] = v.vx / config_.wheel_radius_m;
    if (v.vx != 0.0)
      a[1] = std::atan(b * v.wz / v.vx);
    else
      a[1] = v.wz > 0.0 ? 0.5 * kPi : (v.wz < 0.0 ? -0.5 * kPi : 0.0);
  }
  BodyTwist forward(std::span<const double> a) const override {
    const double vx = config_.wheel_radius_m * a[0];
    return {vx, 0.0, vx * std::tan(a[1]) / (2.0 * config_.half_wheelbase_m)};
  }
  // Front wheels at x = 2 L2, rear at 0 (base_link on the rear axle).
  std::vector<Vec2> wheel_contacts() const override {
    const double x = 2.0 * config_.half_wheelbase_m, y = config_.half_track_m;
    return {Vec2(x, y), Vec2(x, -y), Vec2(0.0, y), Vec2(0.0, -y)};
  }
  Vec2 body_center() const override { return {config_.half_wheelbase_m, 0.0}; }
};

}  // namespace

void RobotConfig::validate() const {
  require(drive == DriveKind::Mecanum || drive == DriveKind::Differential || drive == DriveKind::Ackermann, robot_field("drive"),
          "unknown drive kind");
  require_positive(half_track_m, robot_field("half_track_m"));
  require_positive(half_wheelbase_m, robot_field("half_wheelbase_m"));
  require_positive(wheel_radius_m, robot_field("wheel_radius_m"));
  require(std::isfinite(roller_angle_rad) && roller_angle_rad > 0.0 && roller_angle_rad < 0.5 * kPi,
          robot_field("roller_angle_rad"), "must lie in (0, pi/2)");
  require_positive(body_length_m, robot_field("body_length_m"));
  require_positive(body_width_m, robot_field("body_width_m"));
  require_positive(body_height_m, robot_field("body_height_m"));
  require_non_negative(ground_clearance_m, robot_field("ground_clearance_m"));
  require_positive(max_wheel_speed_radps, robot_field("max_wheel_speed_radps"));
  require_positive(max_wheel_accel_radps2, robot_field("max_wheel_accel_radps2"));
  require_non_negative(actuator_lag_s, robot_field("actuator_lag_s"));
  require(std::isfinite(max_steer_rad) && max_steer_rad > 0.0 && max_steer_rad < 0.5 * kPi, robot_field("max_steer_rad"),
          "must lie in (0, pi/2)");
  require_positive(max_steer_rate_radps, robot_field("max_steer_rate_radps"));
  require_non_negative(max_step_m, robot_field("max_step_m"));
}

std::unique_ptr<RobotModel> make_robot_model(const RobotConfig& config) {
  config.validate();
  switch (config.drive) {
    case DriveKind::Differential: return std::make_unique<DifferentialModel>(config);
    case DriveKind::Ackermann: return std::make_unique<AckermannModel>(config);
    case DriveKind::Mecanum: break;
  }
  return std::make_unique<MecanumModel>(config);
}

RobotDrive::RobotDrive(const RobotConfig& config) : model_(make_robot_model(config)) {
  state_.assign(static_cast<std::size_t>(model_->actuator_count()), 0.0);
  target_ = state_;
  mean_ = state_;
}

void RobotDrive::reset() {
  std::fill(state_.begin(), state_.end(), 0.0);
  std::fill(mean_.begin(), mean_.end(), 0.0);
}

void RobotDrive::stop_wheels() {
  const std::size_t wheels = model_->kind() == DriveKind::Ackermann ? 1 : state_.size();
  for (std::size_t i = 0; i < wheels; ++i) state_[i] = mean_[i] = 0.0;
}

void RobotDrive::limited_targets(const BodyTwist& command, std::span<double> targets) const {
  const RobotConfig& c = model_->config();
  model_->inverse(command, targets);
  if (model_->kind() == DriveKind::Ackermann) {
    targets[0] = std::clamp(targets[0], -c.max_wheel_speed_radps, c.max_wheel_speed_radps);
    targets[1] = std::clamp(targets[1], -c.max_steer_rad, c.max_steer_rad);
    return;
  }
  // One common factor for all wheels keeps the direction of motion (the twist's proportions).
  double peak = 0.0;
  for (const double w : targets) peak = std::max(peak, std::abs(w));
  if (peak > c.max_wheel_speed_radps) {
    const double s = c.max_wheel_speed_radps / peak;
    for (double& w : targets) w *= s;
  }
}

BodyTwist RobotDrive::step(const BodyTwist& command, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error("time step must be finite and > 0", {}, 0, "dt");
  const RobotConfig& c = model_->config();
  limited_targets(command, target_);
  // First-order lag, exact for a target held over the step: x += (1 - exp(-dt/tau)) (target - x).
  const double gain = c.actuator_lag_s > 0.0 ? -std::expm1(-dt / c.actuator_lag_s) : 1.0;
  const std::size_t n = state_.size();
  // Mean over the step of an unclamped lag: T + (x0 - T) (tau/dt) (1 - exp(-dt/tau)) (T when tau = 0).
  const double mean_gain = c.actuator_lag_s > 0.0 ? c.actuator_lag_s / dt * gain : 0.0;
  double delta[4];
  for (std::size_t i = 0; i < n; ++i) delta[i] = gain * (target_[i] - state_[i]);
  const auto advance = [&](std::size_t i, double change, bool clamped) {
    mean_[i] = clamped ? state_[i] + 0.5 * change : target_[i] + (state_[i] - target_[i]) * mean_gain;
    state_[i] += change;
  };
  if (model_->kind() == DriveKind::Ackermann) {
    const double limit[2] = {c.max_wheel_accel_radps2 * dt, c.max_steer_rate_radps * dt};
    for (std::size_t i = 0; i < 2; ++i)
      advance(i, std::clamp(delta[i], -limit[i], limit[i]), std::abs(delta[i]) > limit[i]);
  } else {
    // Acceleration limit per wheel, applied as one common factor so the wheels stay in proportion.
    double peak = 0.0;
    for (std::size_t i = 0; i < n; ++i) peak = std::max(peak, std::abs(delta[i]));
    const double limit = c.max_wheel_accel_radps2 * dt;
    const bool clamped = peak > limit;
    const double s = clamped ? limit / peak : 1.0;
    for (std::size_t i = 0; i < n; ++i) advance(i, s * delta[i], clamped);
  }
  return model_->forward(state_);
}

}  // namespace starnav
