#include "starnav/sim/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {


Eigen::Matrix3d rpy_matrix(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
          Eigen::AngleAxisd(roll, Vec3::UnitX()))
      .toRotationMatrix();
}

void check_finite(double v, const char* field) {
  if (!std::isfinite(v)) throw Error("must be finite", {}, 0, field);
}
void check_finite(const Vec3& v, const char* field) {
  if (!v.allFinite()) throw Error("must be finite", {}, 0, field);
}

// Picks the reported crossing from a solid's entry/exit interval along the ray.
bool finish(double t_enter, const Vec3& n_enter, double t_exit, const Vec3& n_exit, double max_range,
            PrimitiveHit& hit) {
  if (!(t_enter <= t_exit)) return false;
  if (t_enter >= 0.0) {
    if (t_enter > max_range) return false;
    hit.distance = t_enter;
    hit.normal = n_enter;
    hit.inside = false;
    return true;
  }
  if (t_exit >= 0.0 && t_exit <= max_range) {
    hit.distance = t_exit;
    hit.normal = n_exit;
    hit.inside = true;
    return true;
  }
  return false;
}

// Roots of the ray against a circle/sphere of radius r, f = origin - centre, d the direction
// (not necessarily unit), a = d.d. Stable form (no cancellation for far or grazing rays):
// the discriminant comes from the perpendicular offset, the small root from c / q.
bool circle_roots(const double* f, const double* d, int dims, double r, double& t0, double& t1) {
  double a = 0.0, b = 0.0, ff = 0.0;
  for (int i = 0; i < dims; ++i) {
    a += d[i] * d[i];
    b += f[i] * d[i];
    ff += f[i] * f[i];
  }
  double perp2 = 0.0;
  const double k = b / a;
  for (int i = 0; i < dims; ++i) {
    const double v = f[i] - k * d[i];
    perp2 += v * v;
  }
  const double disc = r * r - perp2;  // times a: the quadratic's reduced discriminant
  if (disc < 0.0) return false;
  const double s = std::sqrt(a * disc);
  const double q = -(b + std::copysign(s, b));
  const double c = ff - r * r;
  if (q == 0.0) {
    t0 = t1 = 0.0;
    return true;
  }
  t0 = c / q;
  t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

bool intersect_box(const PosedPrimitive& p, const Vec3& origin, const Vec3& dir, double max_range, PrimitiveHit& hit) {
  const Vec3 o = p.rotation.transpose() * (origin - p.origin);
  const Vec3 d = p.rotation.transpose() * dir;
  double t_enter = -kInfinity, t_exit = kInfinity;
  int ax_enter = -1, ax_exit = -1;
  double sg_enter = 0.0, sg_exit = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double h = p.half[i];
    if (d[i] == 0.0) {
      if (o[i] < -h || o[i] > h) return false;
      continue;
    }
    const double inv = 1.0 / d[i];
    double ta = (-h - o[i]) * inv, tb = (h - o[i]) * inv;
    // Entering through the face the ray moves into: -h when d > 0, +h when d < 0.
    const double sg = d[i] > 0.0 ? -1.0 : 1.0;
    if (ta > tb) std::swap(ta, tb);
    if (ta > t_enter) {
      t_enter = ta;
      ax_enter = i;
      sg_enter = sg;
    }
    if (tb < t_exit) {
      t_exit = tb;
      ax_exit = i;
      sg_exit = -sg;
    }
  }
  if (ax_enter < 0 || ax_exit < 0) return false;  // zero direction
  const Vec3 n_enter = p.rotation.col(ax_enter) * sg_enter;
  const Vec3 n_exit = p.rotation.col(ax_exit) * sg_exit;
  return finish(t_enter, n_enter, t_exit, n_exit, max_range, hit);
}

bool intersect_cylinder(const PosedPrimitive& p, const Vec3& origin, const Vec3& dir, double max_range,
                        PrimitiveHit& hit) {
  const double f[2] = {origin.x() - p.origin.x(), origin.y() - p.origin.y()};
  const double dxy[2] = {dir.x(), dir.y()};
  const double fz = origin.z() - p.origin.z();
  const double r = p.radius, h = p.half.z();
  double s_enter = -kInfinity, s_exit = kInfinity;  // side (infinite cylinder)
  if (dxy[0] * dxy[0] + dxy[1] * dxy[1] == 0.0) {
    if (f[0] * f[0] + f[1] * f[1] > r * r) return false;
  } else if (!circle_roots(f, dxy, 2, r, s_enter, s_exit)) {
    return false;
  }
  double z_enter = -kInfinity, z_exit = kInfinity;
  double zn_enter = 0.0, zn_exit = 0.0;
  if (dir.z() == 0.0) {
    if (fz < 0.0 || fz > h) return false;
  } else {
    const double ta = -fz / dir.z(), tb = (h - fz) / dir.z();
    if (dir.z() > 0.0) {
      z_enter = ta, zn_enter = -1.0;
      z_exit = tb, zn_exit = 1.0;
    } else {
      z_enter = tb, zn_enter = 1.0;
      z_exit = ta, zn_exit = -1.0;
    }
  }
  auto side_normal = [&](double t) {
    Vec3 n(f[0] + t * dxy[0], f[1] + t * dxy[1], 0.0);
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : Vec3(1.0, 0.0, 0.0);
  };
  double t_enter, t_exit;
  Vec3 n_enter, n_exit;
  if (z_enter > s_enter) {
    t_enter = z_enter;
    n_enter = Vec3(0.0, 0.0, zn_enter);
  } else {
    t_enter = s_enter;
    n_enter = std::isfinite(s_enter) ? side_normal(s_enter) : Vec3::Zero();
  }
  if (z_exit < s_exit) {
    t_exit = z_exit;
    n_exit = Vec3(0.0, 0.0, zn_exit);
  } else {
    t_exit = s_exit;
    n_exit = std::isfinite(s_exit) ? side_normal(s_exit) : Vec3::Zero();
  }
  return finish(t_enter, n_enter, t_exit, n_exit, max_range, hit);
}

bool intersect_prism(const PosedPrimitive& p, const Vec3& origin, const Vec3& dir, double max_range,
                     PrimitiveHit& hit) {
  const Vec3 o = p.rotation.transpose() * (origin - p.origin);
  const Vec3 d = p.rotation.transpose() * dir;
  double t_enter = -kInfinity, t_exit = kInfinity;
  int i_enter = -1, i_exit = -1;
  for (int i = 0; i < 5; ++i) {
    const double denom = p.plane_n[i].dot(d);
    const double dist = p.plane_d[i] - p.plane_n[i].dot(o);  // >= 0: inside this half-space
    if (denom == 0.0) {
      if (dist < 0.0) return false;
      continue;
    }
    const double t = dist / denom;
    if (denom < 0.0) {
      if (t > t_enter) t_enter = t, i_enter = i;
    } else {
      if (t < t_exit) t_exit = t, i_exit = i;
    }
  }
  if (i_enter < 0 || i_exit < 0) return false;  // a bounded solid always has both
  return finish(t_enter, p.rotation * p.plane_n[i_enter], t_exit, p.rotation * p.plane_n[i_exit], max_range, hit);
}

bool intersect_sphere(const PosedPrimitive& p, const Vec3& origin, const Vec3& dir, double max_range,
                      PrimitiveHit& hit) {
  const Vec3 f = origin - p.origin;
  double t0, t1;
  if (!circle_roots(f.data(), dir.data(), 3, p.radius, t0, t1)) return false;
  auto normal = [&](double t) {
    const Vec3 n = f + t * dir;
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : Vec3(0.0, 0.0, 1.0);
  };
  if (t0 >= 0.0) {
    if (t0 > max_range) return false;
    hit.distance = t0;
    hit.normal = normal(t0);
    hit.inside = false;
    return true;
  }
  if (t1 >= 0.0 && t1 <= max_range) {
    hit.distance = t1;
    hit.normal = normal(t1);
    hit.inside = true;
    return true;
  }
  return false;
}

}  // namespace

void validate(const Primitive& prim) {
  std::visit(
      [](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, Box>) {
          check_finite(p.center, "center");
          require_positive(p.size.x(), "size");
          require_positive(p.size.y(), "size");
          require_positive(p.size.z(), "size");
          check_finite(p.roll, "roll");
          check_finite(p.pitch, "pitch");
          check_finite(p.yaw, "yaw");
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          check_finite(p.base, "base");
          require_positive(p.radius, "radius");
          require_positive(p.height, "height");
        } else if constexpr (std::is_same_v<T, Prism>) {
          check_finite(p.base, "base");
          check_finite(p.yaw, "yaw");
          require_positive(p.base_width, "base_width");
          require_positive(p.height, "height");
          require_positive(p.length, "length");
          check_finite(p.apex_offset, "apex_offset");
          if (std::abs(p.apex_offset) > 0.5 * p.base_width)
            throw Error("apex must lie over the base (|apex_offset| <= base_width/2)", {}, 0, "apex_offset");
        } else {
          check_finite(p.center, "center");
          require_positive(p.radius, "radius");
        }
      },
      prim);
}

Primitive translated(const Primitive& prim, const Vec3& offset) {
  Primitive out = prim;
  std::visit(
      [&](auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, Box> || std::is_same_v<T, Sphere>)
          p.center += offset;
        else
          p.base += offset;
      },
      out);
  return out;
}

const char* primitive_kind_name(const Primitive& p) {
  static constexpr const char* names[] = {"box", "cylinder", "prism", "sphere"};
  return names[p.index()];
}

PosedPrimitive pose_primitive(const Primitive& prim) {
  validate(prim);
  PosedPrimitive out;
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, Box>) {
          out.kind = PosedPrimitive::Kind::box;
          out.origin = p.center;
          out.rotation = rpy_matrix(p.roll, p.pitch, p.yaw);
          out.half = 0.5 * p.size;
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          out.kind = PosedPrimitive::Kind::cylinder;
          out.origin = p.base;
          out.radius = p.radius;
          out.half = Vec3(p.radius, p.radius, p.height);
        } else if constexpr (std::is_same_v<T, Prism>) {
          out.kind = PosedPrimitive::Kind::prism;
          out.origin = p.base;
          out.rotation = rpy_matrix(0.0, 0.0, p.yaw);
          const double b2 = 0.5 * p.base_width, a = p.apex_offset, h = p.height, l2 = 0.5 * p.length;
          out.plane_n[0] = Vec3(0, 0, -1);
          out.plane_d[0] = 0.0;
          out.plane_n[1] = Vec3(0, 1, 0);
          out.plane_d[1] = l2;
          out.plane_n[2] = Vec3(0, -1, 0);
          out.plane_d[2] = l2;
          // Left side through (-b/2, 0) and (a, h); right side through (b/2, 0) and (a, h).
          out.plane_n[3] = Vec3(-h, 0.0, a + b2).normalized();
          out.plane_d[3] = out.plane_n[3].dot(Vec3(-b2, 0, 0));
          out.plane_n[4] = Vec3(h, 0.0, b2 - a).normalized();
          out.plane_d[4] = out.plane_n[4].dot(Vec3(b2, 0, 0));
        } else {
          out.kind = PosedPrimitive::Kind::sphere;
          out.origin = p.center;
          out.radius = p.radius;
        }
      },
      prim);
  out.box = bounds(prim);
  return out;
}

Aabb bounds(const Primitive& prim) {
  Aabb b;
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, Box>) {
          const Eigen::Matrix3d r = rpy_matrix(p.roll, p.pitch, p.yaw);
          const Vec3 ext = r.cwiseAbs() * (0.5 * p.size);
          b.lo = p.center - ext;
          b.hi = p.center + ext;
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          b.lo = p.base - Vec3(p.radius, p.radius, 0.0);
          b.hi = p.base + Vec3(p.radius, p.radius, p.height);
        } else if constexpr (std::is_same_v<T, Prism>) {
          const Eigen::Matrix3d r = rpy_matrix(0.0, 0.0, p.yaw);
          const double b2 = 0.5 * p.base_width, l2 = 0.5 * p.length;
          for (double y : {-l2, l2}) {
            b.extend(p.base + r * Vec3(-b2, y, 0.0));
            b.extend(p.base + r * Vec3(b2, y, 0.0));
            b.extend(p.base + r * Vec3(p.apex_offset, y, p.height));
          }
        } else {
          b.lo = p.center - Vec3::Constant(p.radius);
          b.hi = p.center + Vec3::Constant(p.radius);
        }
      },
      prim);
  return b;
}

bool intersect(const PosedPrimitive& p, const Vec3& origin, const Vec3& dir, double max_range, PrimitiveHit& hit) {
  switch (p.kind) {
    case PosedPrimitive::Kind::box: return intersect_box(p, origin, dir, max_range, hit);
    case PosedPrimitive::Kind::cylinder: return intersect_cylinder(p, origin, dir, max_range, hit);
    case PosedPrimitive::Kind::prism: return intersect_prism(p, origin, dir, max_range, hit);
    case PosedPrimitive::Kind::sphere: return intersect_sphere(p, origin, dir, max_range, hit);
  }
  return false;
}

bool contains(const PosedPrimitive& p, const Vec3& point, double tol) {
  switch (p.kind) {
    case PosedPrimitive::Kind::box: {
      const Vec3 l = p.rotation.transpose() * (point - p.origin);
      return std::abs(l.x()) <= p.half.x() + tol && std::abs(l.y()) <= p.half.y() + tol &&
             std::abs(l.z()) <= p.half.z() + tol;
    }
    case PosedPrimitive::Kind::cylinder: {
      const Vec3 l = point - p.origin;
      return std::hypot(l.x(), l.y()) <= p.radius + tol && l.z() >= -tol && l.z() <= p.half.z() + tol;
    }
    case PosedPrimitive::Kind::prism: {
      const Vec3 l = p.rotation.transpose() * (point - p.origin);
      for (int i = 0; i < 5; ++i)
        if (p.plane_n[i].dot(l) > p.plane_d[i] + tol) return false;
      return true;
    }
    case PosedPrimitive::Kind::sphere: return (point - p.origin).norm() <= p.radius + tol;
  }
  return false;
}

}  // namespace starnav
