#pragma once
// The recovery role (Nav2's behaviours, run in order without a behaviour tree): what the
// navigator does when the robot is stuck (the controller blocked for a while, or no progress).
// The navigator runs its recoveries one after another (navigation.recoveries: [rotate, back_up] by
// default), each until it says it is done, then plans again. A recovery moves the robot only while
// the motion it commands stays clear of the obstacles the map knows (the shared footprint check).
// Built by name from the registry with its declared parameters.
#include <optional>
#include <string>
#include <string_view>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/robot/robot_model.hpp"

namespace starnav {

// Whether driving a constant body twist from a pose for a while keeps the robot's footprint clear
// of the known obstacles (the map-level footprint checker behind it).
class MotionCheck {
 public:
  virtual ~MotionCheck() = default;
  virtual bool clear(const Pose2& pose, const BodyTwist& twist, double duration_s) const = 0;
};

struct RecoveryInput {
  double t_s = 0.0;
  Pose2 pose;                         // map frame
  const MotionCheck* motion = nullptr;
  double look_period_s = 0.0;         // look at the map at most once per this period (0: every step)
};

class Recovery {
 public:
  virtual ~Recovery() = default;
  virtual std::string_view name() const = 0;
  // Begins at in.t_s from in.pose.
  virtual void start(const RecoveryInput& in) = 0;
  // The twist to drive now; nothing once the recovery is done (its motion finished, or no longer
  // clear).
  virtual std::optional<BodyTwist> step(const RecoveryInput& in) = 0;
};

struct RecoveryContext {
  RobotConfig robot;
  std::string file;
};
using RecoveryDef = ComponentDef<Recovery, RecoveryContext>;

}  // namespace starnav
