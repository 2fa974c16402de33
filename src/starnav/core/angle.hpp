#pragma once
// Angle helpers. Radians everywhere inside starnav; degrees only at the edges.
#include <cmath>
#include <numbers>

namespace starnav {

inline constexpr double kPi = std::numbers::pi;

// Wraps an angle into (-pi, pi].
inline double wrap_angle(double a) {
  if (!std::isfinite(a)) return a;
  if (a > -kPi && a <= kPi) return a;
  double r = std::remainder(a, 2.0 * kPi);  // in [-pi, pi]
  if (r <= -kPi) r += 2.0 * kPi;
  return r;
}

// Shortest signed rotation that takes `from` to `to`, in (-pi, pi].
inline double angle_diff(double to, double from) { return wrap_angle(to - from); }

inline constexpr double deg_to_rad(double deg) { return deg * (kPi / 180.0); }
inline constexpr double rad_to_deg(double rad) { return rad * (180.0 / kPi); }

}  // namespace starnav
