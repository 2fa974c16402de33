#include "starnav/sim/obstacles.hpp"

#include <cmath>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/sim/terrain_surface.hpp"

namespace starnav {

namespace {

void finite(const Vec3& v, const char* field) {
  if (!v.allFinite()) throw Error("must be finite", {}, 0, field);
}
void finite(double v, const char* field) {
  if (!std::isfinite(v)) throw Error("must be finite", {}, 0, field);
}

// A point of the composite's frame (x along yaw, y left, z up from position) in the world.
Vec3 place(const Vec3& position, double yaw, double x, double y, double z) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return position + Vec3(c * x - s * y, s * x + c * y, z);
}

}  // namespace

Vec3 Obstacle::anchor_at(double t) const {
  if (!waypoints.empty()) {
    if (t <= waypoints.front().time) return waypoints.front().position;
    if (t >= waypoints.back().time) return waypoints.back().position;
    std::size_t i = 1;
    while (waypoints[i].time < t) ++i;  // waypoints[i-1].time < t <= waypoints[i].time
    const Waypoint& a = waypoints[i - 1];
    const Waypoint& b = waypoints[i];
    const double u = (t - a.time) / (b.time - a.time);
    return a.position + u * (b.position - a.position);
  }
  if (velocity != Vec3::Zero()) return anchor + velocity * (t - appear);
  return anchor;
}

void validate(const Obstacle& o) {
  if (o.parts.empty()) throw Error("an obstacle needs at least one part", {}, 0, "parts");
  for (const auto& p : o.parts) validate(p);
  finite(o.anchor, "anchor");
  finite(o.appear, "appear");
  if (std::isnan(o.disappear) || !(o.disappear > o.appear))
    throw Error("must be later than appear", {}, 0, "disappear");
  finite(o.velocity, "velocity");
  if (!o.waypoints.empty() && o.velocity != Vec3::Zero())
    throw Error("give either a velocity or waypoints, not both", {}, 0, "waypoints");
  for (std::size_t i = 0; i < o.waypoints.size(); ++i) {
    finite(o.waypoints[i].time, "waypoints");
    finite(o.waypoints[i].position, "waypoints");
    if (i > 0 && !(o.waypoints[i].time > o.waypoints[i - 1].time))
      throw Error("waypoint times must increase strictly", {}, 0, "waypoints");
  }
}

Obstacle make_slope_step(const SlopeStep& s) {
  finite(s.position, "position");
  finite(s.yaw, "yaw");
  require_positive(s.width, "width");
  require_positive(s.ramp_length, "ramp_length");
  require_positive(s.ramp_height, "ramp_height");
  require_positive(s.platform_length, "platform_length");
  require_positive(s.step_height, "step_height");
  require_positive(s.step_length, "step_length");
  require_non_negative(s.depth, "depth");
  Obstacle o;
  o.name = "slope_step";
  o.anchor = s.position;
  const double total = 2.0 * s.ramp_length + 2.0 * s.platform_length + s.step_length;
  double x = -0.5 * total;
  const double h = s.ramp_height;
  // A flat box from z = -depth to z = top over [x0, x0 + len].
  auto flat = [&](double x0, double len, double top) {
    Box b;
    b.center = place(s.position, s.yaw, x0 + 0.5 * len, 0.0, 0.5 * (top - s.depth));
    b.size = Vec3(len, s.width, top + s.depth);
    b.yaw = s.yaw;
    o.parts.emplace_back(b);
  };
  // A ramp whose top face runs from height z_a at x0 to z_b at x0 + ramp_length: a box pitched
  // so its top face is that slope, thick enough that its sides reach depth below the ground.
  auto ramp = [&](double x0, double z_a, double z_b) {
    const double theta = std::atan2(z_b - z_a, s.ramp_length);  // rise along +x
    const double len = std::hypot(s.ramp_length, z_b - z_a);
    const double thick = (h + s.depth) * std::cos(theta);
    const Vec3 n_top(-std::sin(theta), 0.0, std::cos(theta));  // top-face normal in the x-z plane
    const Vec3 top_centre(x0 + 0.5 * s.ramp_length, 0.0, 0.5 * (z_a + z_b));
    const Vec3 c = top_centre - 0.5 * thick * n_top;
    Box b;
    b.center = place(s.position, s.yaw, c.x(), 0.0, c.z());
    b.size = Vec3(len, s.width, thick);
    b.pitch = -theta;  // Ry(-theta) turns +x up by theta
    b.yaw = s.yaw;
    o.parts.emplace_back(b);
  };
  ramp(x, 0.0, h);
  x += s.ramp_length;
  flat(x, s.platform_length, h);
  x += s.platform_length;
  flat(x, s.step_length, h + s.step_height);
  x += s.step_length;
  flat(x, s.platform_length, h);
  x += s.platform_length;
  ramp(x, h, 0.0);
  return o;
}

Obstacle make_undulating_ground(const UndulatingGround& u) {
  finite(u.position, "position");
  finite(u.yaw, "yaw");
  if (u.count < 1) throw Error("must be at least 1", {}, 0, "count");
  require_positive(u.base_width, "base_width");
  require_positive(u.height, "height");
  require_positive(u.width, "width");
  Obstacle o;
  o.name = "undulating_ground";
  o.anchor = u.position;
  for (int i = 0; i < u.count; ++i) {
    Prism p;
    const double x = -0.5 * u.count * u.base_width + (i + 0.5) * u.base_width;
    p.base = place(u.position, u.yaw, x, 0.0, 0.0);
    p.yaw = u.yaw;
    p.base_width = u.base_width;
    p.height = u.height;
    p.length = u.width;
    o.parts.emplace_back(p);
  }
  return o;
}

Obstacle make_round_convex(const RoundConvex& r) {
  finite(r.position, "position");
  finite(r.yaw, "yaw");
  require_positive(r.box_size.x(), "box_size");
  require_positive(r.box_size.y(), "box_size");
  require_positive(r.box_size.z(), "box_size");
  require_positive(r.radius, "radius");
  require_positive(r.cylinder_height, "cylinder_height");
  require_non_negative(r.depth, "depth");
  Obstacle o;
  o.name = "round_convex";
  o.anchor = r.position;
  Box b;
  b.center = r.position + Vec3(0.0, 0.0, 0.5 * (r.box_size.z() - r.depth));
  b.size = Vec3(r.box_size.x(), r.box_size.y(), r.box_size.z() + r.depth);
  b.yaw = r.yaw;
  o.parts.emplace_back(b);
  Cylinder c;
  c.base = r.position + Vec3(0.0, 0.0, r.box_size.z());
  c.radius = r.radius;
  c.height = r.cylinder_height;
  o.parts.emplace_back(c);
  return o;
}

Obstacle make_gravel(const Gravel& g, const TerrainSurface* ground) {
  finite(g.position, "position");
  finite(g.yaw, "yaw");
  require_positive(g.length, "length");
  require_positive(g.width, "width");
  if (g.count < 1) throw Error("must be at least 1", {}, 0, "count");
  require_positive(g.size_min, "size_min");
  require_positive(g.size_max, "size_max");
  if (g.size_max < g.size_min) throw Error("must be >= size_min", {}, 0, "size_max");
  if (!(g.sphere_fraction >= 0.0 && g.sphere_fraction <= 1.0)) throw Error("must be in [0, 1]", {}, 0, "sphere_fraction");
  if (!(g.embed >= 0.0 && g.embed < 1.0)) throw Error("must be in [0, 1)", {}, 0, "embed");
  Obstacle o;
  o.name = "gravel";
  o.anchor = g.position;
  Rng rng(g.seed);
  for (int i = 0; i < g.count; ++i) {
    const double x = rng.uniform(-0.5 * g.length, 0.5 * g.length);
    const double y = rng.uniform(-0.5 * g.width, 0.5 * g.width);
    const double size = rng.uniform(g.size_min, g.size_max);
    const bool sphere = rng.uniform() < g.sphere_fraction;
    const double piece_yaw = rng.uniform(0.0, 0.5 * kPi);
    Vec3 p = place(g.position, g.yaw, x, y, 0.0);
    if (ground && g.follow_terrain) {
      const double hz = ground->height(p.x(), p.y());
      if (!std::isnan(hz)) p.z() = hz;
    }
    const double zc = p.z() + 0.5 * size - g.embed * size;
    if (sphere) {
      Sphere s;
      s.center = Vec3(p.x(), p.y(), zc);
      s.radius = 0.5 * size;
      o.parts.emplace_back(s);
    } else {
      Box b;
      b.center = Vec3(p.x(), p.y(), zc);
      b.size = Vec3::Constant(size);
      b.yaw = g.yaw + piece_yaw;
      o.parts.emplace_back(b);
    }
  }
  return o;
}

}  // namespace starnav
