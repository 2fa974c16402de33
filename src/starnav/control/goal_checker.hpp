#pragma once
// The goal-checker role (Nav2's GoalChecker): whether the robot has reached its goal, from its
// pose and velocity. The navigator asks it at every control step; a checker may keep state (a
// position reached at low speed stays reached while the robot turns to the goal's heading) until
// reset() for a new goal or after a recovery moved the robot. Built by name from the registry
// (navigation.goal_checker) with its declared parameters; the tolerances are the navigation
// section's (the controller reads the same ones).
#include <optional>
#include <string>
#include <string_view>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"

namespace starnav {

struct GoalCheckInput {
  double t_s = 0.0;
  Pose2 pose;                       // map frame (the localizer's)
  BodyTwist velocity;               // current body twist
  Vec2 goal = Vec2::Zero();
  std::optional<double> goal_yaw;   // rad, when the goal has a heading
  double xy_tolerance_m = 0.15;
  double yaw_tolerance_rad = 0.0872664626;
};

class GoalChecker {
 public:
  virtual ~GoalChecker() = default;
  virtual std::string_view name() const = 0;
  // A new goal, or the robot was moved away from it (a recovery): forget what was latched.
  virtual void reset() = 0;
  // True when the goal is reached.
  virtual bool reached(const GoalCheckInput& in) = 0;
  // The position is reached and held: only the heading is left (controllers then turn in place).
  virtual bool position_reached() const = 0;
};

struct GoalCheckerContext {
  std::string file;
};
using GoalCheckerDef = ComponentDef<GoalChecker, GoalCheckerContext>;

}  // namespace starnav
