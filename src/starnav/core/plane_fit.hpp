#pragma once
// A body's attitude on the ground: the least-squares plane through heights under it and the
// roll, pitch and tilt of a body resting on that plane. One definition shared by the terrain path
// metrics (the robot's footprint along a planned path) and the simulator's vehicle (its attitude
// as it drives).
#include <span>

#include "starnav/core/geometry.hpp"

namespace starnav {

// A rectangular footprint centred on the body's origin.
struct Footprint {
  double length_m = 0.6;  // along the heading
  double width_m = 0.4;   // across it
  double circumscribed_radius_m() const;
  double inscribed_radius_m() const;
};

struct Attitude {
  double roll = 0.0;   // rad
  double pitch = 0.0;  // rad
  double tilt = 0.0;   // rad, >= 0
  bool valid = false;  // false when a corner height is unknown
};

// Least-squares plane z = z0 + px x + py y through points (x, y, z): centred normal equations,
// exact (to rounding) when the points lie on a plane. `valid` is false for fewer than 3 points or
// points whose (x, y) are collinear. rms_residual: RMS of the points' heights about the plane.
struct PlaneFit {
  double z0 = 0.0;
  double px = 0.0;
  double py = 0.0;
  double rms_residual = 0.0;
  bool valid = false;
  double height(double x, double y) const { return z0 + px * x + py * y; }
};
PlaneFit fit_plane(std::span<const Vec3> points);

// Roll, pitch and tilt of a body on a plane whose slopes in the body's heading frame are
// px = dz/dx_forward and py = dz/dy_left:
//   pitch = -atan(px)                 (REP-103: positive pitch is nose down),
//   roll  = atan2(py, sqrt(1 + px^2)) (positive roll: left side up),
//   tilt  = atan(sqrt(px^2 + py^2))   (angle between the body's z axis and the vertical).
Attitude attitude_from_slopes(double px, double py);

}  // namespace starnav
