#include "starnav/core/plane_fit.hpp"

#include <algorithm>
#include <cmath>

namespace starnav {

double Footprint::circumscribed_radius_m() const { return 0.5 * std::hypot(length_m, width_m); }
double Footprint::inscribed_radius_m() const { return 0.5 * std::min(length_m, width_m); }

PlaneFit fit_plane(std::span<const Vec3> points) {
  PlaneFit f;
  if (points.size() < 3) return f;
  const double n = static_cast<double>(points.size());
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= n;
  double sxx = 0.0, syy = 0.0, sxy = 0.0, sxz = 0.0, syz = 0.0;
  for (const Vec3& p : points) {
    const double x = p.x() - mean.x(), y = p.y() - mean.y(), z = p.z() - mean.z();
    sxx += x * x;
    syy += y * y;
    sxy += x * y;
    sxz += x * z;
    syz += y * z;
  }
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 1e-12 * (sxx * syy)) || !(sxx > 0.0) || !(syy > 0.0)) return f;
  f.px = (sxz * syy - syz * sxy) / det;
  f.py = (syz * sxx - sxz * sxy) / det;
  f.z0 = mean.z() - f.px * mean.x() - f.py * mean.y();
  double ss = 0.0;
  for (const Vec3& p : points) {
    const double r = p.z() - f.height(p.x(), p.y());
    ss += r * r;
  }
  f.rms_residual = std::sqrt(ss / n);
  f.valid = true;
  return f;
}

Attitude attitude_from_slopes(double px, double py) {
  Attitude att;
  att.pitch = -std::atan(px);
  att.roll = std::atan2(py, std::sqrt(1.0 + px * px));
  att.tilt = std::atan(std::hypot(px, py));
  att.valid = true;
  return att;
}

}  // namespace starnav
