// Ray casting against the four primitives: random rays against an independent march + bisection
// on each primitive's inside predicate, closed-form cases, grazing rays, rays starting inside.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim_test_support.hpp"
#include "starnav/core/error.hpp"
#include "starnav/sim/primitives.hpp"

namespace starnav {
namespace {

using test::inside;
using test::march_bisect;
using test::random_unit;

Primitive random_primitive(Rng& rng, int kind) {
  const Vec3 c(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-1, 2));
  switch (kind) {
    case 0:
      return Box{c, Vec3(rng.uniform(0.2, 3), rng.uniform(0.2, 3), rng.uniform(0.2, 3)), rng.uniform(-1, 1),
                 rng.uniform(-1, 1), rng.uniform(-kPi, kPi)};
    case 1: return Cylinder{c, rng.uniform(0.1, 1.5), rng.uniform(0.2, 3)};
    case 2: {
      const double b = rng.uniform(0.3, 3);
      return Prism{c, rng.uniform(-kPi, kPi), b, rng.uniform(0.2, 2), rng.uniform(-0.5, 0.5) * b, rng.uniform(0.3, 3)};
    }
    default: return Sphere{c, rng.uniform(0.1, 2)};
  }
}

struct Tally {
  int rays = 0, hits = 0, thin = 0, normal_ok = 0, inside_starts = 0;
};

// One ray against one primitive, checked against the march; returns false on a mismatch.
void check_ray(const Primitive& prim, const Vec3& o, const Vec3& d, double range, Tally& tally) {
  const PosedPrimitive posed = pose_primitive(prim);
  PrimitiveHit hit;
  const bool got = intersect(posed, o, d, range, hit);
  const auto pred = [&](const Vec3& p) { return inside(prim, p); };
  // March only where the ray is inside the (slightly grown) bounds: the solid lies within them.
  const Aabb b = bounds(prim);
  const auto [s0, s1] = test::ray_box(b.lo - Vec3::Constant(1e-6), b.hi + Vec3::Constant(1e-6), o, d);
  std::optional<double> ref;
  if (s0 <= s1 && s0 <= range) ref = march_bisect(pred, o, d, std::min(range, s1), 1e-3, s0);
  ++tally.rays;
  const bool starts_inside = inside(prim, o);
  if (starts_inside) ++tally.inside_starts;
  if (!ref && !got) {
    return;  // both miss
  } else if (ref && got && std::abs(*ref - hit.distance) < 1e-9) {
    // Both agree.
  } else if (got && (!ref || hit.distance < *ref)) {
    // A chord thinner than the march step (grazing an edge or a curved side): the reported point
    // must still lie on the boundary.
    const Vec3 p = o + hit.distance * d;
    const bool before = pred(o + (hit.distance - 1e-7) * d), after = pred(o + std::min(hit.distance + 1e-7, range) * d);
    EXPECT_TRUE(before == starts_inside || after != starts_inside || test::inside(prim, p))
        << "hit off the boundary at " << hit.distance;
    ++tally.thin;
  } else {
    ADD_FAILURE() << primitive_kind_name(prim) << ": cast " << (got ? std::to_string(hit.distance) : "miss")
                  << " vs march " << (ref ? std::to_string(*ref) : "miss") << " origin " << o.transpose()
                  << " dir " << d.transpose();
    return;
  }
  if (!got) return;
  ++tally.hits;
  EXPECT_EQ(hit.inside, starts_inside);
  EXPECT_NEAR(hit.normal.norm(), 1.0, 1e-12);
  // Outward normal: just outside along it, just inside against it.
  const Vec3 p = o + hit.distance * d;
  if (!pred(p + 1e-6 * hit.normal) && pred(p - 1e-6 * hit.normal)) ++tally.normal_ok;
}

class PrimitiveRays : public ::testing::TestWithParam<int> {};

TEST_P(PrimitiveRays, RandomRaysMatchMarchAndBisection) {
  Rng rng(100 + static_cast<std::uint64_t>(GetParam()));
  Tally tally;
  for (int shape = 0; shape < 40; ++shape) {
    const Primitive prim = random_primitive(rng, GetParam());
    const Aabb b = bounds(prim);
    for (int k = 0; k < 60; ++k) {
      const Vec3 o(rng.uniform(b.lo.x() - 2, b.hi.x() + 2), rng.uniform(b.lo.y() - 2, b.hi.y() + 2),
                   rng.uniform(b.lo.z() - 2, b.hi.z() + 2));
      Vec3 d;
      if (k % 3 == 0) {
        d = random_unit(rng);
      } else {
        const Vec3 target(rng.uniform(b.lo.x(), b.hi.x()), rng.uniform(b.lo.y(), b.hi.y()), rng.uniform(b.lo.z(), b.hi.z()));
        d = (target - o).normalized();
      }
      check_ray(prim, o, d, 12.0, tally);
    }
  }
  RecordProperty("rays", tally.rays);
  EXPECT_GT(tally.hits, tally.rays / 4);
  EXPECT_LT(tally.thin, tally.rays / 50);
  EXPECT_GE(tally.normal_ok, tally.hits * 99 / 100);
  EXPECT_GT(tally.inside_starts, 10);
}

std::string kind_name(const ::testing::TestParamInfo<int>& info) {
  static const char* names[] = {"box", "cylinder", "prism", "sphere"};
  return names[info.param];
}
INSTANTIATE_TEST_SUITE_P(Kinds, PrimitiveRays, ::testing::Values(0, 1, 2, 3), kind_name);

PrimitiveHit cast1(const Primitive& p, const Vec3& o, const Vec3& d, double range = 100.0) {
  PrimitiveHit h;
  if (!intersect(pose_primitive(p), o, d, range, h)) h.distance = std::numeric_limits<double>::infinity();
  return h;
}

TEST(Primitives, SphereClosedForm) {
  const Sphere s{Vec3(1, 2, 3), 1.5};
  // Offset b from the centre line: distance = |oc| - sqrt(r^2 - b^2).
  for (double b : {0.0, 0.3, 1.0, 1.49}) {
    const PrimitiveHit h = cast1(s, Vec3(-9, 2 + b, 3), Vec3(1, 0, 0));
    EXPECT_NEAR(h.distance, 10.0 - std::sqrt(1.5 * 1.5 - b * b), 1e-12) << b;
    const Vec3 p = Vec3(-9, 2 + b, 3) + h.distance * Vec3(1, 0, 0);
    EXPECT_NEAR((h.normal - (p - s.center) / 1.5).norm(), 0.0, 1e-12);
  }
  // From the centre: the exit at r, flagged inside, normal along the ray.
  const Vec3 d = Vec3(1, -2, 0.5).normalized();
  const PrimitiveHit h = cast1(s, s.center, d);
  EXPECT_NEAR(h.distance, 1.5, 1e-12);
  EXPECT_TRUE(h.inside);
  EXPECT_NEAR((h.normal - d).norm(), 0.0, 1e-12);
  // Far away (1 km) the stable form keeps full precision.
  EXPECT_NEAR(cast1(s, Vec3(1001, 2.5, 3), Vec3(-1, 0, 0), 2000).distance, 1000 - std::sqrt(1.5 * 1.5 - 0.25), 1e-9);
  // Behind the origin, or beyond the range: no hit.
  EXPECT_TRUE(std::isinf(cast1(s, Vec3(5, 2, 3), Vec3(1, 0, 0)).distance));
  EXPECT_TRUE(std::isinf(cast1(s, Vec3(-9, 2, 3), Vec3(1, 0, 0), 8.0).distance));
}

TEST(Primitives, SphereGrazing) {
  const Sphere s{Vec3::Zero(), 1.0};
  // Just inside the tangent: hits near the tangent point; just outside: misses.
  const PrimitiveHit in = cast1(s, Vec3(-5, 1 - 1e-9, 0), Vec3(1, 0, 0));
  EXPECT_NEAR(in.distance, 5.0, 1e-4);
  EXPECT_TRUE(std::isinf(cast1(s, Vec3(-5, 1 + 1e-9, 0), Vec3(1, 0, 0)).distance));
}

TEST(Primitives, BoxClosedForm) {
  // Rotated box: a ray along its own x axis from outside meets the -x face at distance - half.
  const double yaw = 0.5, pitch = 0.2, roll = -0.3;
  const Box b{Vec3(1, -1, 2), Vec3(2, 4, 6), roll, pitch, yaw};
  const Eigen::Matrix3d r = test::rpy_rotation(roll, pitch, yaw);
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 u = r.col(axis);
    const PrimitiveHit h = cast1(b, b.center - 10.0 * u, u);
    EXPECT_NEAR(h.distance, 10.0 - 0.5 * b.size[axis], 1e-12) << axis;
    EXPECT_NEAR((h.normal + u).norm(), 0.0, 1e-12);
    EXPECT_FALSE(h.inside);
    // From the centre: exit through the +axis face.
    const PrimitiveHit e = cast1(b, b.center, u);
    EXPECT_NEAR(e.distance, 0.5 * b.size[axis], 1e-12);
    EXPECT_TRUE(e.inside);
    EXPECT_NEAR((e.normal - u).norm(), 0.0, 1e-12);
  }
  // Oblique ray into an axis-aligned box: the x face at x = -1 from (-4, 0, 0) towards (1, 0.2, 0.1).
  const Box a{Vec3::Zero(), Vec3(2, 2, 2)};
  const Vec3 d = Vec3(1, 0.2, 0.1).normalized();
  EXPECT_NEAR(cast1(a, Vec3(-4, 0, 0), d).distance, 3.0 / d.x(), 1e-12);
}

TEST(Primitives, BoxGrazingFacePlane) {
  const Box a{Vec3::Zero(), Vec3(2, 2, 2)};
  // In the plane of the top face: the closed box is touched (enters through the -x face).
  EXPECT_NEAR(cast1(a, Vec3(-3, 0, 1), Vec3(1, 0, 0)).distance, 2.0, 1e-12);
  // Just above it: a miss.
  EXPECT_TRUE(std::isinf(cast1(a, Vec3(-3, 0, 1 + 1e-12), Vec3(1, 0, 0)).distance));
  // Along an edge direction with zero components: the slab test needs no division by zero.
  EXPECT_NEAR(cast1(a, Vec3(0.5, 0.5, 5), Vec3(0, 0, -1)).distance, 4.0, 1e-12);
}

TEST(Primitives, CylinderClosedForm) {
  const Cylinder c{Vec3(2, 1, -0.5), 0.8, 2.0};
  // Horizontal ray at offset b inside the height: side hit at dist - sqrt(r^2 - b^2).
  for (double b : {0.0, 0.5, 0.79}) {
    const PrimitiveHit h = cast1(c, Vec3(2 + b, -9, 0.3), Vec3(0, 1, 0));
    EXPECT_NEAR(h.distance, 10.0 - std::sqrt(0.64 - b * b), 1e-12);
    EXPECT_NEAR(h.normal.z(), 0.0, 1e-15);
  }
  // Vertical rays: onto the top cap, up into the bottom cap, and from inside to the top.
  PrimitiveHit h = cast1(c, Vec3(2.3, 1.2, 5), Vec3(0, 0, -1));
  EXPECT_NEAR(h.distance, 5 - 1.5, 1e-12);
  EXPECT_NEAR((h.normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-15);
  h = cast1(c, Vec3(2.3, 1.2, -3), Vec3(0, 0, 1));
  EXPECT_NEAR(h.distance, 2.5, 1e-12);
  EXPECT_NEAR((h.normal - Vec3(0, 0, -1)).norm(), 0.0, 1e-15);
  h = cast1(c, Vec3(2, 1, 0), Vec3(0, 0, 1));
  EXPECT_NEAR(h.distance, 1.5, 1e-12);
  EXPECT_TRUE(h.inside);
  // A vertical ray outside the radius misses; a horizontal ray above the top misses.
  EXPECT_TRUE(std::isinf(cast1(c, Vec3(2.81, 1, 5), Vec3(0, 0, -1)).distance));
  EXPECT_TRUE(std::isinf(cast1(c, Vec3(2, -9, 1.5 + 1e-9), Vec3(0, 1, 0)).distance));
  // A slanted ray through the top rim: the cap or the side, whichever the geometry says.
  const Vec3 o(2 - 3, 1, 3), d = Vec3(1, 0, -1).normalized();  // reaches z = 1.5 at x = 2 - 1.5
  h = cast1(c, o, d);
  // Side at x = 2 - 0.8 would be at z = 3 - 2.2 = 0.8 (< 1.5): so the cap is first, at x = 0.5?
  // x = 0.5 is outside the radius (|0.5 - 2| = 1.5 > 0.8), so the side is hit, at x = 1.2.
  EXPECT_NEAR(h.distance, 2.2 * std::sqrt(2.0), 1e-12);
}

TEST(Primitives, PrismClosedForm) {
  // Isosceles ridge: base 1 along x, height 0.5, apex at x = 0; vertical rays land on the side
  // at z = h (1 - |x| / (b/2)).
  const Prism p{Vec3(0, 0, 0), 0.0, 1.0, 0.5, 0.0, 2.0};
  for (double x : {-0.4, -0.1, 0.05, 0.3}) {
    const PrimitiveHit h = cast1(p, Vec3(x, 0.3, 4), Vec3(0, 0, -1));
    EXPECT_NEAR(h.distance, 4 - 0.5 * (1 - std::abs(x) / 0.5), 1e-12) << x;
    const Vec3 n_expected = Vec3(x > 0 ? 0.5 : -0.5, 0, 0.5).normalized();
    EXPECT_NEAR((h.normal - n_expected).norm(), 0.0, 1e-12);
  }
  // Along the ridge axis: the end face at y = -1.
  EXPECT_NEAR(cast1(p, Vec3(0, -5, 0.1), Vec3(0, 1, 0)).distance, 4.0, 1e-12);
  // Yawed by 90 deg: the ridge runs along x now.
  const Prism q{Vec3(1, 1, 0), kPi / 2, 1.0, 0.5, 0.0, 2.0};
  EXPECT_NEAR(cast1(q, Vec3(1.5, 1.2, 4), Vec3(0, 0, -1)).distance, 4 - 0.5 * (1 - 0.2 / 0.5), 1e-12);
  // Right-angled prism (a ramp): apex over the +x base corner.
  const Prism ramp{Vec3::Zero(), 0.0, 2.0, 0.5, 1.0, 1.0};
  EXPECT_NEAR(cast1(ramp, Vec3(0, 0, 3), Vec3(0, 0, -1)).distance, 3 - 0.25, 1e-12);
  EXPECT_NEAR(cast1(ramp, Vec3(3, 0, 0.2), Vec3(-1, 0, 0)).distance, 2.0, 1e-12);  // vertical back face
  // From inside: up through the slanted face.
  const PrimitiveHit h = cast1(ramp, Vec3(0.5, 0, 0.1), Vec3(0, 0, 1));
  EXPECT_TRUE(h.inside);
  EXPECT_NEAR(h.distance, 0.5 * 1.5 / 2.0 - 0.1, 1e-12);
}

TEST(Primitives, BoundsContainTheSolid) {
  Rng rng(5);
  for (int kind = 0; kind < 4; ++kind)
    for (int n = 0; n < 20; ++n) {
      const Primitive prim = random_primitive(rng, kind);
      const Aabb b = bounds(prim);
      int in = 0;
      for (int k = 0; k < 2000; ++k) {
        const Vec3 p(rng.uniform(b.lo.x() - 0.1, b.hi.x() + 0.1), rng.uniform(b.lo.y() - 0.1, b.hi.y() + 0.1),
                     rng.uniform(b.lo.z() - 0.1, b.hi.z() + 0.1));
        if (!inside(prim, p)) continue;
        ++in;
        EXPECT_TRUE((p.array() >= b.lo.array() - 1e-12).all() && (p.array() <= b.hi.array() + 1e-12).all());
        EXPECT_TRUE(contains(pose_primitive(prim), p, 1e-12));
      }
      EXPECT_GT(in, 0);
    }
}

TEST(Primitives, ValidationNamesTheField) {
  auto field_of = [](const Primitive& p) {
    try {
      validate(p);
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("(none)");
  };
  EXPECT_EQ(field_of(Box{Vec3::Zero(), Vec3(1, 0, 1)}), "size");
  EXPECT_EQ(field_of(Cylinder{Vec3::Zero(), -1.0, 1.0}), "radius");
  EXPECT_EQ(field_of(Prism{Vec3::Zero(), 0.0, 1.0, 0.5, 0.6, 1.0}), "apex_offset");
  EXPECT_EQ(field_of(Sphere{Vec3(NAN, 0, 0), 1.0}), "center");
  EXPECT_EQ(field_of(Sphere{Vec3::Zero(), 1.0}), "(none)");
}

}  // namespace
}  // namespace starnav
