#pragma once
// The robot placed in a World: the actuator chain of robot/robot_model.hpp drives a rigid body
// over the world's surface (terrain and obstacle tops). x, y, yaw are integrated from the
// achieved twist; z, roll and pitch come from the surface under the wheel contacts. A move that
// would make the body overlap an obstacle or a wheel climb a step taller than max_step_m is not
// taken (the robot stops where it is and an event is recorded). See docs/simulator.md, "Robots
// and proprioceptive sensors", for the equations.
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/robot/robot_model.hpp"
#include "starnav/sim/world.hpp"
#include "starnav/core/plane_fit.hpp"

namespace starnav {

struct VehicleConfig {
  RobotConfig robot;
  double friction = 0.6;          // slide down slopes whose tan(slope) exceeds this
  double rough_slip_sigma = 0.0;  // random slip (fraction of speed, std dev) scaled by local roughness; 0 = off
  // Throws Error naming the field ("vehicle." or "robot." prefix).
  void validate() const;
};

struct VehicleState {
  double t_s = 0.0;
  Pose3 pose;      // base_link in the world: x, y from integration; z, roll, pitch from the terrain under the wheels
  BodyTwist twist;  // mean body velocity over the last step (base_link): driven twist plus slide drift
  // Integrated actuator angles (Mecanum/diff wheels; Ackermann: [rear wheel angle, steering angle]).
  std::vector<double> wheel_angle_rad;
  // Actuator state at the end of the step (Ackermann: [rear wheel speed, steering angle]).
  std::vector<double> wheel_speed_radps;
};

struct VehicleEvent {
  double t_s = 0.0;
  // "collision" (body meets an obstacle), "step" (step taller than max_step_m), "slide" (slipping
  // down a slope), "off_terrain" (a wheel has no surface under it)
  std::string kind;
  std::string detail;         // obstacle name etc.
  Vec2 where = Vec2::Zero();  // world x, y of the contact
};

class Vehicle {
 public:
  // Keeps a reference to `world`, which must outlive the vehicle. Throws Error for an invalid
  // configuration (field named) or when the start has no ground under a wheel (field "start").
  Vehicle(const World& world, const VehicleConfig& config, const Pose2& start, Rng rng, double t0 = 0.0);
  // Advance by dt under `command`. A move that would make the body overlap an obstacle or climb a
  // step taller than max_step_m is NOT taken (the robot stops there: never passes through); an
  // event is appended instead. The move is taken up to the last admissible point of the step
  // (found by bisection to 1/32 of a sub-step), the wheels are brought to rest and the step
  // counts as blocked. Events are appended when something starts (a block whose kind or obstacle
  // differs from the last step's, a slide beginning), not on every step it lasts. dt > 0.
  void step(const BodyTwist& command, double dt, std::vector<VehicleEvent>& events);
  // Moves the robot to `to` at time t without turning its wheels (the kidnapped robot: encoders
  // and IMU see nothing); actuators and drift to rest. Throws Error (field "teleport") when the
  // target has no ground under a wheel or the body would overlap an obstacle there.
  void teleport(const Pose2& to, double t);
  // True when the last step was cut short by a collision, a step or the edge of the terrain.
  bool blocked() const { return !last_block_.empty(); }
  // Downhill drift velocity (world frame, m/s) of the slide model.
  Vec2 slide_velocity() const { return slide_velocity_; }
  const VehicleState& state() const { return state_; }
  const RobotModel& model() const { return drive_.model(); }
  const VehicleConfig& config() const { return config_; }
  // True while the front of the body touches an obstacle below the LiDAR plane (last step).
  bool bumper_contact() const { return bumper_; }

 private:
  // The robot posed on the surface at a candidate (x, y, yaw).
  struct Placement {
    Pose2 planar;
    Pose3 pose;
    PlaneFit plane;                    // contact heights fitted in the heading frame (x forward, y left)
    std::array<double, 4> wheel_z{};   // surface height under each contact
  };
  // What stopped a move.
  struct Block {
    std::string kind;
    std::string detail;
    Vec2 where = Vec2::Zero();
    std::string key;  // kind and obstacle or wheel: the same key on consecutive steps is one event
  };
  struct Segment {
    Vec3 origin;   // base_link
    Vec3 dir;      // unit, base_link
    double length;
  };
  // Surface under every contact; false (and `block` set) when a contact has no ground.
  bool place(const Pose2& planar, double t, Placement& out, Block& block) const;
  // The first obstacle overlapping the body box at `pose` (false when none).
  bool body_overlap(const Pose3& pose, double t, Block& block);
  bool front_contact(const Pose3& pose, double t);
  // Candidate (stepping from `from`) is admissible: no step, no overlap.
  bool admissible(const Placement& from, const Placement& to, double t, Block& block);
  void refresh_moving(double t);
  double ground(double x, double y, double t) const;

  const World* world_;
  VehicleConfig config_;
  RobotDrive drive_;
  Rng rng_;
  VehicleState state_;
  Placement here_;
  Vec2 slide_velocity_ = Vec2::Zero();  // world-frame downhill drift (m/s)
  bool bumper_ = false;
  std::string last_block_;              // kind and detail of the block of the last step ("" = moved freely)
  std::vector<Vec2> contacts_;          // wheel contacts in base_link
  double reach_m_ = 0.0;                // largest distance of a body corner or contact from base_link (xy)
  std::array<Vec3, 8> corners_{};       // body box corners in base_link
  std::vector<Segment> body_segments_;  // edges and face lines of the body box
  std::vector<Segment> bumper_segments_;
  std::vector<PosedPrimitive> static_parts_;
  std::vector<int> moving_obstacles_;
  std::vector<PosedPrimitive> moving_parts_;
  double moving_time_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<const PosedPrimitive*> candidates_;
};

}  // namespace starnav
