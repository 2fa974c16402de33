#pragma once
// Robot kinematic models behind one interface (docs/papers/li2019.md, ren2022 section 1) and the
// actuator chain that turns a commanded body twist into an achieved one (limits and lag).
//
// Models (base_link: x forward, y left, z up; wheels FL, FR, RL, RR):
//   Mecanum      roller angle alpha, half track L1 (wheel y = +-L1), half wheelbase L2 (wheel x = +-L2),
//                k = (L1 + L2 tan(alpha)) ... see docs/simulator.md "Robots and proprioceptive sensors";
//                at alpha = 45 deg the inverse is w = (vx -/+ vy -/+ (L1 + L2) wz) / r.
//   Differential wheels at y = +-L1: wL = (vx - L1 wz) / r, wR = (vx + L1 wz) / r; vy is not realisable.
//   Ackermann    bicycle model about the rear axle, wheelbase b = 2 L2: actuators (rear wheel speed,
//                steering angle); vx = r w, wz = vx tan(steer) / b; cannot turn in place.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"

namespace starnav {

enum class DriveKind : std::uint8_t { Mecanum, Differential, Ackermann };

// "mecanum", "differential", "ackermann".
const char* drive_kind_name(DriveKind kind);
// Throws Error naming `field` for any other name.
DriveKind parse_drive_kind(const std::string& s, const std::string& field);

struct RobotConfig {
  DriveKind drive = DriveKind::Mecanum;
  // Defaults: the paper's Mecanum robot (docs/papers/li2019.md). The body box spans z in
  // [ground_clearance, ground_clearance + body_height] in base_link (base_link on the wheel plane).
  double half_track_m = 0.225;       // L1: wheel contact y = +-L1
  double half_wheelbase_m = 0.200;   // L2: wheel contact x = +-L2
  double wheel_radius_m = 0.076;
  double roller_angle_rad = 0.7853981633974483;  // Mecanum roller angle alpha
  double body_length_m = 0.55;
  double body_width_m = 0.50;
  double body_height_m = 0.25;
  double ground_clearance_m = 0.06;
  double max_wheel_speed_radps = 10.0;   // |wheel speed| limit (all wheels scaled together to keep the direction)
  double max_wheel_accel_radps2 = 20.0;  // per-wheel acceleration limit
  double actuator_lag_s = 0.1;           // first-order lag time constant (0 = none)
  double max_steer_rad = 0.5;            // Ackermann only: steering limit (wheelbase = 2*half_wheelbase)
  double max_steer_rate_radps = 1.0;     // Ackermann only
  double max_step_m = 0.05;              // tallest step the wheels can climb
  // Throws Error naming the field (prefix "robot.").
  void validate() const;
};

// Kinematics only; knows nothing of the world.
class RobotModel {
 public:
  explicit RobotModel(const RobotConfig& config) : config_(config) {}
  virtual ~RobotModel() = default;
  virtual DriveKind kind() const = 0;
  virtual bool holonomic() const = 0;       // can translate sideways
  virtual bool turns_in_place() const = 0;
  // Mecanum 4 (FL, FR, RL, RR wheel speeds, rad/s), differential 2 (L, R), Ackermann 2 (rear wheel
  // speed rad/s, steering angle rad).
  virtual int actuator_count() const = 0;
  // Unlimited inverse kinematics; `actuators` has actuator_count() elements.
  virtual void inverse(const BodyTwist& twist, std::span<double> actuators) const = 0;
  // Forward kinematics (the exact inverse of inverse() where the model can realise the twist).
  virtual BodyTwist forward(std::span<const double> actuators) const = 0;
  // Wheel contact points in base_link (x forward, y left), for the terrain attitude.
  virtual std::vector<Vec2> wheel_contacts() const = 0;
  // Centre of the body box's footprint in base_link: the origin, except for Ackermann, whose
  // base_link is on the rear axle and whose body is centred between the axles at (L2, 0).
  virtual Vec2 body_center() const { return Vec2::Zero(); }
  const RobotConfig& config() const { return config_; }

 protected:
  RobotConfig config_;
};

// Validates the configuration.
std::unique_ptr<RobotModel> make_robot_model(const RobotConfig& config);

// Actuators with limits and lag: command twist -> actuator targets (inverse, speed-limited by
// uniform scaling, Ackermann steering clamped) -> per-step acceleration/rate limit -> first-order
// lag; then forward() gives the achieved twist.
class RobotDrive {
 public:
  explicit RobotDrive(const RobotConfig& config);
  // Returns the achieved body twist after this step (dt > 0).
  BodyTwist step(const BodyTwist& command, double dt);
  std::span<const double> actuator_state() const { return state_; }
  // Mean of each actuator over the last step: exact for the lag alone, (start + end) / 2 where
  // the acceleration or steering-rate limit bound (the state then moves linearly). Integrating
  // it gives the wheel angles; its forward() is the body twist to integrate over the step.
  std::span<const double> actuator_mean() const { return mean_; }
  const RobotModel& model() const { return *model_; }
  // All actuators to rest.
  void reset();
  // Wheel speeds to rest, the steering angle (Ackermann) kept: what an impact does.
  void stop_wheels();
  // The actuator targets of `command` after the speed / steering limits (what the lag chases).
  void limited_targets(const BodyTwist& command, std::span<double> targets) const;

 private:
  std::unique_ptr<RobotModel> model_;
  std::vector<double> state_;
  std::vector<double> target_;
  std::vector<double> mean_;
};

}  // namespace starnav
