#pragma once
// Planar rigid-body motion under a constant body twist.
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/geometry.hpp"

namespace starnav {

// The pose reached from `p` after `t` seconds at constant body velocity (vx forward, vy left) and
// yaw rate wz: the exact arc (the SE(2) exponential), so any number of sub-steps of a constant
// twist compose to the same pose up to rounding. Below |wz t| = 1e-9 the arc is taken to second
// order in the turned angle, which is the arc to rounding.
inline Pose2 advance_on_arc(const Pose2& p, double vx, double vy, double wz, double t) {
  const double th = wz * t;
  double dx, dy;
  if (std::abs(th) > 1e-9) {
    const double s = std::sin(th), c1 = 2.0 * std::sin(0.5 * th) * std::sin(0.5 * th);  // 1 - cos
    dx = (vx * s - vy * c1) / wz;
    dy = (vx * c1 + vy * s) / wz;
  } else {
    dx = (vx - 0.5 * vy * th) * t;
    dy = (vy + 0.5 * vx * th) * t;
  }
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  return {p.x + c * dx - s * dy, p.y + s * dx + c * dy, wrap_angle(p.yaw + th)};
}

}  // namespace starnav
