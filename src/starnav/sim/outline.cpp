#include "starnav/sim/outline.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

namespace starnav {

std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  if (p.size() < 3) return p;
  std::vector<Vec2> h(2 * p.size());
  std::size_t k = 0;
  const auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

PrimitiveOutline primitive_outline(const Primitive& part, const Vec3& offset) {
  PrimitiveOutline f;
  if (const auto* b = std::get_if<Box>(&part)) {
    const Eigen::Matrix3d r = Pose3::from_rpy(Vec3::Zero(), b->roll, b->pitch, b->yaw).rotation();
    std::vector<Vec2> pts;
    for (int i = 0; i < 8; ++i) {
      const Vec3 c(((i & 1) ? 0.5 : -0.5) * b->size.x(), ((i & 2) ? 0.5 : -0.5) * b->size.y(), ((i & 4) ? 0.5 : -0.5) * b->size.z());
      pts.push_back((b->center + offset + r * c).head<2>());
    }
    f.polygon = convex_hull(pts);
  } else if (const auto* p = std::get_if<Prism>(&part)) {
    const double c = std::cos(p->yaw), s = std::sin(p->yaw);
    std::vector<Vec2> pts;
    for (const double lx : {-0.5 * p->base_width, 0.5 * p->base_width, p->apex_offset})
      for (const double ly : {-0.5 * p->length, 0.5 * p->length})
        pts.emplace_back(p->base.x() + offset.x() + c * lx - s * ly, p->base.y() + offset.y() + s * lx + c * ly);
    f.polygon = convex_hull(pts);
  } else if (const auto* cy = std::get_if<Cylinder>(&part)) {
    f.centre = (cy->base + offset).head<2>();
    f.radius = cy->radius;
  } else if (const auto* sp = std::get_if<Sphere>(&part)) {
    f.centre = (sp->center + offset).head<2>();
    f.radius = sp->radius;
  }
  if (!f.polygon.empty()) f.polygon.push_back(f.polygon.front());
  return f;
}

}  // namespace starnav
