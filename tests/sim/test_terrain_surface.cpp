// Ray casting against the heightfield: planes (flat, tilted, on a rotated map), a paraboloid
// against march + bisection on an independently written interpolant, rough terrain with holes
// against a brute-force test of every triangle, rays leaving and entering the map, rays from
// below the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "sim/sim_test_support.hpp"
#include "starnav/core/error.hpp"
#include "starnav/sim/terrain_surface.hpp"

namespace starnav {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ElevationMap make_map(int w, int h, double res, const Pose2& origin, const std::function<double(double, double)>& f) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = origin;
  ElevationMap m(g);
  for (int iy = 0; iy < h; ++iy)
    for (int ix = 0; ix < w; ++ix) {
      const Vec2 c = g.cell_center(ix, iy);
      m.set_height(ix, iy, f(c.x(), c.y()));
    }
  return m;
}

// The documented interpolant, written independently: heights at cell centres, two triangles per
// square of four centres split from (i, j) to (i+1, j+1), clamped to the centres' span in the
// half-cell border, NaN outside the map or where a vertex is unobserved.
struct ReferenceSurface {
  const ElevationMap& m;
  double operator()(double x, double y) const {
    const GridGeometry& g = m.geometry();
    const double c = std::cos(g.origin.yaw), s = std::sin(g.origin.yaw);
    const double dx = x - g.origin.x, dy = y - g.origin.y;
    const double gx = c * dx + s * dy, gy = -s * dx + c * dy;
    if (gx < 0 || gy < 0 || gx > g.width * g.resolution || gy > g.height * g.resolution) return kNaN;
    const double u = std::clamp(gx / g.resolution - 0.5, 0.0, g.width - 1.0);
    const double v = std::clamp(gy / g.resolution - 0.5, 0.0, g.height - 1.0);
    const int i = std::min(static_cast<int>(u), std::max(g.width - 2, 0));
    const int j = std::min(static_cast<int>(v), std::max(g.height - 2, 0));
    const double fx = u - i, fy = v - j;
    auto at = [&](int a, int b) {
      a = std::min(a, g.width - 1);
      b = std::min(b, g.height - 1);
      return m.observed_at(a, b) ? m.height_at(a, b) : kNaN;
    };
    const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
    if (fx >= fy) return h00 + (h10 - h00) * fx + (h11 - h10) * fy;
    return h00 + (h11 - h01) * fx + (h01 - h00) * fy;
  }
};

TerrainHit cast(const TerrainSurface& t, const Vec3& o, const Vec3& d, double range = 1000.0) {
  TerrainHit h;
  if (!t.cast(o, d, range, h)) h.distance = std::numeric_limits<double>::infinity();
  return h;
}

TEST(TerrainSurface, HeightIsTheDocumentedInterpolant) {
  Rng rng(1);
  const ElevationMap m = make_map(17, 11, 0.25, Pose2(-1.0, 2.0, 0.7), [&](double, double) { return rng.uniform(-1, 1); });
  const TerrainSurface t(m);
  const ReferenceSurface ref{m};
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    const double x = rng.uniform(-6, 5), y = rng.uniform(-1, 7);
    const double a = t.height(x, y), b = ref(x, y);
    if (std::isnan(b)) {
      EXPECT_TRUE(std::isnan(a)) << x << " " << y;
      continue;
    }
    ++inside;
    EXPECT_NEAR(a, b, 1e-12) << x << " " << y;
  }
  EXPECT_GT(inside, 2000);
  // At a cell centre the surface passes through the cell's height.
  const Vec2 c = m.geometry().cell_center(5, 4);
  EXPECT_NEAR(t.height(c.x(), c.y()), m.height_at(5, 4), 1e-12);
}

TEST(TerrainSurface, FlatPlane) {
  const double z0 = 0.7;
  const ElevationMap m = make_map(40, 30, 0.5, Pose2(-10, -5, 0.0), [&](double, double) { return z0; });
  const TerrainSurface t(m);
  Rng rng(2);
  int hits = 0;
  for (int k = 0; k < 5000; ++k) {
    const Vec3 o(rng.uniform(-15, 15), rng.uniform(-10, 15), rng.uniform(z0 + 0.01, z0 + 10));
    Vec3 d = test::random_unit(rng);
    if (d.z() > 0) d.z() = -d.z();
    const double s = (z0 - o.z()) / d.z();
    const Vec3 p = o + s * d;
    const bool on_map = p.x() >= -10 && p.x() <= 10 && p.y() >= -5 && p.y() <= 10;
    const TerrainHit h = cast(t, o, d);
    if (!on_map) {
      EXPECT_TRUE(std::isinf(h.distance)) << k;
      continue;
    }
    ++hits;
    EXPECT_NEAR(h.distance, s, 1e-9 * (1 + s)) << k;
    EXPECT_NEAR((h.normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-12);
    EXPECT_FALSE(h.from_below);
  }
  EXPECT_GT(hits, 1000);
}

TEST(TerrainSurface, TiltedPlaneOnRotatedMap) {
  // h = a x + b y + c is reproduced exactly between the outermost cell centres.
  const double a = 0.3, b = -0.2, c = 1.0;
  const Pose2 origin(-3.0, 2.0, 0.4);
  const ElevationMap m = make_map(50, 40, 0.2, origin, [&](double x, double y) { return a * x + b * y + c; });
  const TerrainSurface t(m);
  const Vec3 n_expected = Vec3(-a, -b, 1).normalized();
  Rng rng(3);
  auto interior = [&](double u, double v) {  // grid metres -> world point within the centres' span
    const Vec2 w = m.geometry().grid_to_world({0.1 + u * (50 * 0.2 - 0.2), 0.1 + v * (40 * 0.2 - 0.2)});
    return w;
  };
  for (int k = 0; k < 5000; ++k) {
    const Vec2 target = interior(rng.uniform(), rng.uniform());
    const Vec2 from = interior(rng.uniform(), rng.uniform());
    const double zt = a * target.x() + b * target.y() + c;
    const double zo = a * from.x() + b * from.y() + c + rng.uniform(0.05, 3.0);
    const Vec3 o(from.x(), from.y(), zo);
    const Vec3 d = (Vec3(target.x(), target.y(), zt) - o).normalized();
    // Closed form: the plane z = a x + b y + c along the ray.
    const double s = (a * o.x() + b * o.y() + c - o.z()) / (d.z() - a * d.x() - b * d.y());
    const TerrainHit h = cast(t, o, d);
    ASSERT_TRUE(std::isfinite(h.distance)) << k;
    EXPECT_NEAR(h.distance, s, 1e-9 * (1 + s)) << k;
    EXPECT_NEAR((h.normal - n_expected).norm(), 0.0, 1e-9);
  }
  // The same from below: the ray meets the surface from under it.
  const Vec2 p = interior(0.5, 0.5);
  const double zp = a * p.x() + b * p.y() + c;
  const TerrainHit h = cast(t, Vec3(p.x(), p.y(), zp - 2.0), Vec3(0, 0, 1));
  EXPECT_NEAR(h.distance, 2.0, 1e-12);
  EXPECT_TRUE(h.from_below);
  EXPECT_NEAR((h.normal - n_expected).norm(), 0.0, 1e-9);
}

TEST(TerrainSurface, ParaboloidAgainstBisectionOnTheInterpolant) {
  const ElevationMap m = make_map(200, 160, 0.1, Pose2(-10, -8, 0.0), [](double x, double y) {
    return 0.05 * ((x - 1) * (x - 1) + (y + 0.5) * (y + 0.5));
  });
  const TerrainSurface t(m);
  const ReferenceSurface ref{m};
  const auto below = [&](const Vec3& p) {
    const double h = ref(p.x(), p.y());
    return !std::isnan(h) && p.z() < h;
  };
  Rng rng(4);
  int hits = 0, thin = 0;
  for (int k = 0; k < 300; ++k) {
    const double ox = rng.uniform(-9, 9), oy = rng.uniform(-7, 7);
    const Vec3 o(ox, oy, ref(ox, oy) + rng.uniform(0.2, 3.0));  // above the surface
    Vec3 d = test::random_unit(rng);
    if (k % 2 == 0) d = Vec3(d.x(), d.y(), -std::abs(d.z()) * 0.2).normalized();  // shallow rays
    const double range = 30.0;
    const auto want = test::march_bisect(below, o, d, range, 2e-3);
    const TerrainHit h = cast(t, o, d, range);
    if (!want) {
      if (std::isfinite(h.distance)) {
        ++thin;  // a crossing thinner than the march step: must lie on the surface
        const Vec3 p = o + h.distance * d;
        EXPECT_NEAR(p.z(), ref(p.x(), p.y()), 1e-9);
      }
      continue;
    }
    ++hits;
    ASSERT_TRUE(std::isfinite(h.distance)) << k << " o " << o.transpose() << " d " << d.transpose() << " want " << *want;
    EXPECT_NEAR(h.distance, *want, 1e-9) << k;
    const Vec3 p = o + h.distance * d;
    EXPECT_NEAR(p.z(), ref(p.x(), p.y()), 1e-9);
    // Normal: the paraboloid's to within the triangles' approximation (0.1 m cells).
    const Vec3 n_smooth = Vec3(-0.1 * (p.x() - 1), -0.1 * (p.y() + 0.5), 1).normalized();
    EXPECT_GT(h.normal.dot(n_smooth), std::cos(0.02));
  }
  EXPECT_GT(hits, 150);
  EXPECT_LE(thin, 3);
}

// Moller-Trumbore against one triangle; +inf on a miss.
double ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return std::numeric_limits<double>::infinity();
  const Vec3 tv = o - a;
  const double u = tv.dot(p) / det;
  if (u < -1e-12 || u > 1 + 1e-12) return std::numeric_limits<double>::infinity();
  const Vec3 q = tv.cross(e1);
  const double v = d.dot(q) / det;
  if (v < -1e-12 || u + v > 1 + 1e-12) return std::numeric_limits<double>::infinity();
  return e2.dot(q) / det;
}

// Every triangle of the surface in world coordinates, the border strips included (their outer
// vertices sit on the map's edge: the strip surface is constant across it, so this is the same
// surface as replicating the edge samples half a cell out).
std::vector<std::array<Vec3, 3>> all_triangles(const ElevationMap& m) {
  const GridGeometry& g = m.geometry();
  auto coord = [](int p, int n) { return std::clamp(p - 1.0, -0.5, n - 0.5) + 0.5; };  // in cells from the corner
  auto sample = [&](int p, int q) {
    const int ix = std::clamp(p - 1, 0, g.width - 1), iy = std::clamp(q - 1, 0, g.height - 1);
    const double h = m.observed_at(ix, iy) ? m.height_at(ix, iy) : kNaN;
    const Vec2 w = g.grid_to_world({coord(p, g.width) * g.resolution, coord(q, g.height) * g.resolution});
    return Vec3(w.x(), w.y(), h);
  };
  std::vector<std::array<Vec3, 3>> out;
  for (int q = 0; q <= g.height; ++q)
    for (int p = 0; p <= g.width; ++p) {
      const Vec3 a = sample(p, q), b = sample(p + 1, q), c = sample(p, q + 1), d = sample(p + 1, q + 1);
      if (std::isnan(a.z() + b.z() + c.z() + d.z())) continue;
      out.push_back({a, b, d});
      out.push_back({a, d, c});
    }
  return out;
}

struct TriangleCheck {
  int hits = 0, disagreements = 0;
};

// Casts `rays` rays (half random, half aimed at the surface; shallow ones skim just above it)
// and compares with the nearest of all triangles.
TriangleCheck check_against_triangles(const ElevationMap& m, Rng& rng, int rays, bool shallow) {
  const TerrainSurface t(m);
  const auto tris = all_triangles(m);
  Aabb box;
  for (const auto& tr : tris)
    for (const Vec3& v : tr) box.extend(v);
  TriangleCheck out;
  for (int k = 0; k < rays; ++k) {
    Vec3 o(rng.uniform(box.lo.x() - 2, box.hi.x() + 2), rng.uniform(box.lo.y() - 2, box.hi.y() + 2),
           rng.uniform(box.lo.z() - 0.5, box.hi.z() + 0.5));
    Vec3 d;
    if (shallow) {
      const double h = t.height(o.x(), o.y());
      if (!std::isnan(h)) o.z() = h + rng.uniform(0.01, 0.3);
      const double a = rng.uniform(-kPi, kPi);
      d = Vec3(std::cos(a), std::sin(a), rng.uniform(-0.05, 0.02)).normalized();
    } else if (k % 2 == 0) {
      d = test::random_unit(rng);
    } else {
      const Vec3 target(rng.uniform(box.lo.x(), box.hi.x()), rng.uniform(box.lo.y(), box.hi.y()),
                        rng.uniform(box.lo.z(), box.hi.z()));
      d = (target - o).normalized();
    }
    const double range = shallow ? 1000.0 : rng.uniform(3.0, 20.0);
    double want = std::numeric_limits<double>::infinity();
    for (const auto& tr : tris) {
      const double s = ray_triangle(o, d, tr[0], tr[1], tr[2]);
      if (s >= 0 && s <= range) want = std::min(want, s);
    }
    const TerrainHit h = cast(t, o, d, range);
    if (std::isinf(want) != std::isinf(h.distance)) {
      ++out.disagreements;  // only possible for a ray through a shared edge within rounding
      ADD_FAILURE() << "ray " << k << ": triangles " << want << " cast " << h.distance;
      continue;
    }
    if (std::isinf(want)) continue;
    ++out.hits;
    EXPECT_NEAR(h.distance, want, 1e-9 * (1 + want)) << k;
    const Vec3 p = o + h.distance * d;
    const double below = t.height(p.x(), p.y());
    if (!std::isnan(below)) {
      EXPECT_NEAR(p.z(), below, 1e-9);
    }
    EXPECT_EQ(h.from_below, d.dot(h.normal) > 0);
  }
  return out;
}

TEST(TerrainSurface, RoughTerrainWithHolesMatchesEveryTriangle) {
  Rng rng(5);
  ElevationMap m = make_map(37, 23, 0.3, Pose2(2.0, -1.0, -0.9), [&](double x, double y) {
    return 0.5 * std::sin(1.3 * x) * std::cos(0.7 * y) + rng.uniform(-0.2, 0.2);
  });
  for (int k = 0; k < 15; ++k) m.clear_cell(static_cast<int>(rng.uniform_int(0, 36)), static_cast<int>(rng.uniform_int(0, 22)));
  const TriangleCheck c = check_against_triangles(m, rng, 1500, false);
  EXPECT_GT(c.hits, 300);
  EXPECT_EQ(c.disagreements, 0);
}

TEST(TerrainSurface, LongShallowRaysOverManyPyramidLevels) {
  // 300 x 170 cells (9 pyramid levels): skimming rays travel far before they hit, so every level
  // of the pyramid is stepped through and skipped.
  Rng rng(6);
  const ElevationMap m = make_map(300, 170, 0.1, Pose2(-5.0, 3.0, 0.25), [&](double x, double y) {
    return 0.3 * std::sin(0.9 * x) + 0.2 * std::cos(1.7 * y + 0.3 * x) + 0.01 * rng.uniform();
  });
  const TriangleCheck c = check_against_triangles(m, rng, 160, true);
  EXPECT_GT(c.hits, 60);
  EXPECT_EQ(c.disagreements, 0);
}

TEST(TerrainSurface, RaysLeavingAndEnteringTheMap) {
  const ElevationMap m = make_map(100, 100, 0.1, Pose2(0, 0, 0), [](double, double) { return 0.0; });  // 10 m x 10 m
  const TerrainSurface t(m);
  // Descending slowly: would meet z = 0 at x = 5 + 100 m, far outside the map.
  EXPECT_TRUE(std::isinf(cast(t, Vec3(5, 5, 1), Vec3(1, 0, -0.01).normalized()).distance));
  // From outside, descending onto the map at x = 5.
  const Vec3 d = Vec3(25, 0, -1).normalized();
  EXPECT_NEAR(cast(t, Vec3(-20, 5, 1), d).distance, std::sqrt(25.0 * 25.0 + 1.0), 1e-9);
  // Passing over the map and out the other side.
  EXPECT_TRUE(std::isinf(cast(t, Vec3(-20, 5, 1), Vec3(1, 0, 0.001).normalized()).distance));
  // Outside the map and below its level: there is no ground out there.
  EXPECT_TRUE(std::isinf(cast(t, Vec3(-3, 5, 1), Vec3(0, 0, -1)).distance));
  // A long shallow ray over the pyramid's levels: from (0.05, 0.05, 0.01) falling 1 mm per metre.
  const Vec3 shallow = Vec3(1, 1, -0.001 * std::sqrt(2.0)).normalized();
  EXPECT_NEAR(cast(t, Vec3(0.05, 0.05, 0.01), shallow).distance, 0.01 / -shallow.z(), 1e-9);
  // Exactly on the map's edge lines.
  EXPECT_NEAR(cast(t, Vec3(0, 0, 2), Vec3(0, 0, -1)).distance, 2.0, 1e-12);
  EXPECT_NEAR(cast(t, Vec3(10, 10, 2), Vec3(0, 0, -1)).distance, 2.0, 1e-12);
  EXPECT_TRUE(std::isinf(cast(t, Vec3(10 + 1e-9, 5, 2), Vec3(0, 0, -1)).distance));
  // Range limits.
  EXPECT_TRUE(std::isinf(cast(t, Vec3(5, 5, 2), Vec3(0, 0, -1), 1.999).distance));
  EXPECT_NEAR(cast(t, Vec3(5, 5, 2), Vec3(0, 0, -1), 2.0).distance, 2.0, 1e-12);
}

TEST(TerrainSurface, HolesLetRaysThrough) {
  ElevationMap m = make_map(20, 20, 1.0, Pose2(0, 0, 0), [](double, double) { return 0.0; });
  for (int y = 8; y < 12; ++y)
    for (int x = 8; x < 12; ++x) m.clear_cell(x, y);
  const TerrainSurface t(m);
  EXPECT_TRUE(std::isinf(cast(t, Vec3(10, 10, 1), Vec3(0, 0, -1)).distance));
  EXPECT_TRUE(std::isnan(t.height(10, 10)));
  EXPECT_NEAR(cast(t, Vec3(3, 3, 1), Vec3(0, 0, -1)).distance, 1.0, 1e-12);
  // A map with no observed cell cannot be a terrain.
  GridGeometry g;
  g.width = g.height = 4;
  EXPECT_THROW(TerrainSurface{ElevationMap(g)}, Error);
}

TEST(TerrainSurface, CopiesOutliveTheOriginal) {
  std::unique_ptr<TerrainSurface> original = std::make_unique<TerrainSurface>(
      make_map(64, 64, 0.5, Pose2(0, 0, 0), [](double x, double y) { return 0.1 * x - 0.05 * y; }));
  const TerrainSurface copy = *original;
  original.reset();
  const TerrainHit h = cast(copy, Vec3(10, 10, 5), Vec3(0, 0, -1));
  EXPECT_NEAR(h.distance, 5 - (1.0 - 0.5), 1e-12);
  EXPECT_EQ(copy.pyramid_levels(), 7);  // 65 x 65 triangle pairs: blocks of 2 ... 128
}

TEST(TerrainSurface, SingleCellAndThinMaps) {
  const ElevationMap one = make_map(1, 1, 2.0, Pose2(0, 0, 0), [](double, double) { return 0.5; });
  const TerrainSurface t1(one);
  EXPECT_NEAR(cast(t1, Vec3(0.1, 1.9, 3), Vec3(0, 0, -1)).distance, 2.5, 1e-12);
  const ElevationMap row = make_map(50, 1, 0.1, Pose2(0, 0, 0), [](double x, double) { return x; });
  const TerrainSurface t2(row);
  EXPECT_NEAR(t2.height(2.0, 0.07), 2.0, 1e-12);
  EXPECT_NEAR(cast(t2, Vec3(2.0, 0.05, 5), Vec3(0, 0, -1)).distance, 3.0, 1e-12);
}

}  // namespace
}  // namespace starnav
