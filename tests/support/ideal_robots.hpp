#pragma once
// Robots without actuator lag, for controller tests that compare commands with closed forms.
#include "starnav/robot/robot_model.hpp"

namespace starnav::test {

inline RobotConfig mecanum() {
  RobotConfig r;
  r.drive = DriveKind::Mecanum;
  r.actuator_lag_s = 0.0;
  return r;
}

inline RobotConfig differential() {
  RobotConfig r = mecanum();
  r.drive = DriveKind::Differential;
  return r;
}

}  // namespace starnav::test
