// The world: broad phase against brute force, lifetimes and motions, composite obstacles, surface
// height, validation, and a LiDAR scan of a box room built from obstacles.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sim/sim_test_support.hpp"
#include "starnav/core/error.hpp"
#include "starnav/sense/lidar.hpp"
#include "starnav/sim/world.hpp"

namespace starnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

ElevationMap flat_map(double size, double res, double z, double x0, double y0) {
  GridGeometry g;
  g.width = g.height = static_cast<int>(std::lround(size / res));
  g.resolution = res;
  g.origin = Pose2(x0, y0, 0.0);
  ElevationMap m(g);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) m.set_height(ix, iy, z);
  return m;
}

Obstacle named(const std::string& name, std::vector<Primitive> parts) {
  Obstacle o;
  o.name = name;
  o.parts = std::move(parts);
  return o;
}

Primitive random_part(Rng& rng, const Vec3& c) {
  const double s = rng.uniform(0.1, 1.5);
  switch (rng.uniform_int(0, 3)) {
    case 0: return Box{c, Vec3(s, rng.uniform(0.1, 1.5), rng.uniform(0.1, 1.5)), 0.0, rng.uniform(-0.3, 0.3), rng.uniform(-kPi, kPi)};
    case 1: return Cylinder{c, 0.5 * s, rng.uniform(0.2, 2.0)};
    case 2: return Prism{c, rng.uniform(-kPi, kPi), s, rng.uniform(0.1, 1.0), 0.0, rng.uniform(0.2, 2.0)};
    default: return Sphere{c, 0.5 * s};
  }
}

WorldDescription random_world(Rng& rng, int count) {
  WorldDescription d;
  GridGeometry g;
  g.width = 120;
  g.height = 100;
  g.resolution = 0.25;
  g.origin = Pose2(-15, -12, 0.1);
  ElevationMap m(g);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) m.set_height(ix, iy, 0.3 * std::sin(0.2 * ix) * std::cos(0.15 * iy));
  d.terrain = m;
  for (int i = 0; i < count; ++i) {
    Obstacle o;
    const Vec3 c(rng.uniform(-14, 14), rng.uniform(-9, 13), rng.uniform(-0.5, 1.5));
    o.anchor = c;
    const int parts = rng.uniform() < 0.2 ? 3 : 1;
    for (int k = 0; k < parts; ++k) o.parts.push_back(random_part(rng, c + Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 0)));
    const double u = rng.uniform();
    if (u < 0.15) {
      o.appear = rng.uniform(0.0, 5.0);
      o.disappear = o.appear + rng.uniform(1.0, 5.0);
    }
    if (u > 0.8) o.velocity = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 0);
    if (u > 0.92) {
      o.velocity = Vec3::Zero();
      o.waypoints = {{1.0, c}, {4.0, c + Vec3(3, -2, 0)}, {6.0, c + Vec3(0, 2, 0.5)}};
    }
    d.obstacles.push_back(std::move(o));
  }
  return d;
}

TEST(World, BroadPhaseMatchesTestingEveryObject) {
  Rng rng(11);
  const World w(random_world(rng, 400));
  int hits = 0, obstacle_hits = 0;
  for (double t : {0.0, 0.5, 2.5, 4.0, 7.0}) {
    const std::vector<PosedPrimitive> posed = w.primitives_at(t);
    for (int k = 0; k < 1500; ++k) {
      const Vec3 o(rng.uniform(-16, 16), rng.uniform(-13, 15), rng.uniform(-0.5, 3.0));
      const Vec3 d = test::random_unit(rng);
      const double range = rng.uniform(1.0, 40.0);
      const RayHit a = w.cast(o, d, range, t);
      const RayHit b = w.cast_brute_force(posed, o, d, range);
      ASSERT_EQ(a.kind, b.kind) << k << " t " << t;
      if (!a.hit()) continue;
      ++hits;
      if (a.kind == HitKind::obstacle) ++obstacle_hits;
      EXPECT_EQ(a.distance, b.distance);
      EXPECT_EQ(a.obstacle, b.obstacle);
      EXPECT_EQ(a.part, b.part);
      EXPECT_EQ(a.inside, b.inside);
      EXPECT_NEAR((a.normal - b.normal).norm(), 0.0, 1e-15);
    }
  }
  EXPECT_GT(obstacle_hits, 1000);
  EXPECT_GT(hits, obstacle_hits + 500);
}

TEST(World, DegenerateRaysHitNothing) {
  Rng rng(13);
  const World w(random_world(rng, 50));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(w.cast(Vec3(nan, 0, 1), Vec3(0, 0, -1), 10, 0).hit());
  EXPECT_FALSE(w.cast(Vec3(0, 0, 1), Vec3(nan, 0, -1), 10, 0).hit());
  EXPECT_FALSE(w.cast(Vec3(0, 0, 1), Vec3(0, 0, -1), nan, 0).hit());
  EXPECT_FALSE(w.cast(Vec3(kInf, 0, 1), Vec3(-1, 0, 0), 10, 0).hit());
  EXPECT_FALSE(w.cast(Vec3(0, 0, 1), Vec3::Zero(), 10, 0).hit());
  EXPECT_FALSE(w.cast(Vec3(0, 0, 5), Vec3(0, 0, -1), -1.0, 0).hit());
  // An unbounded range is fine: the terrain and the obstacles bound the search.
  EXPECT_TRUE(w.cast(Vec3(0, 0, 5), Vec3(0, 0, -1), kInf, 0).hit());
}

TEST(World, BvhOverThousandsOfSmallPieces) {
  Rng rng(12);
  std::vector<PosedPrimitive> prims;
  for (int i = 0; i < 3000; ++i) {
    PosedPrimitive p = pose_primitive(random_part(rng, Vec3(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(0, 2))));
    p.obstacle = i;
    prims.push_back(p);
  }
  const PrimitiveSet set(prims);
  EXPECT_LT(set.node_count(), 2 * prims.size());
  for (int k = 0; k < 3000; ++k) {
    const Vec3 o(rng.uniform(-25, 25), rng.uniform(-25, 25), rng.uniform(-1, 4));
    const Vec3 d = test::random_unit(rng);
    SetHit a, b;
    const bool ga = set.cast(o, d, 60.0, 0.0, a), gb = set.cast_brute_force(o, d, 60.0, 0.0, b);
    ASSERT_EQ(ga, gb) << k;
    if (ga) {
      EXPECT_EQ(a.distance, b.distance);
      EXPECT_EQ(a.index, b.index);
    }
  }
}

TEST(World, LifetimesAndMotion) {
  WorldDescription d;
  Obstacle late;  // a wall at x = 5 from t = 2 to t = 4
  late.parts.emplace_back(Box{Vec3(5.5, 0, 0), Vec3(1, 4, 4)});
  late.appear = 2.0;
  late.disappear = 4.0;
  Obstacle mover;  // a sphere at y = 10 moving +x at 1 m/s from t = 0
  mover.parts.emplace_back(Sphere{Vec3(0, 10, 0), 0.5});
  mover.anchor = Vec3(0, 10, 0);
  mover.velocity = Vec3(1, 0, 0);
  Obstacle tour;  // a cylinder following waypoints along y = -10
  tour.parts.emplace_back(Cylinder{Vec3(0, -10, -1), 0.5, 2.0});
  tour.anchor = Vec3(0, -10, -1);
  tour.waypoints = {{1.0, Vec3(2, -10, -1)}, {3.0, Vec3(6, -10, -1)}};
  d.obstacles = {late, mover, tour};
  const World w(d);
  const Vec3 x(1, 0, 0);
  EXPECT_FALSE(w.cast(Vec3::Zero(), x, 100, 1.999).hit());
  EXPECT_NEAR(w.cast(Vec3::Zero(), x, 100, 2.0).distance, 5.0, 1e-12);
  EXPECT_EQ(w.cast(Vec3::Zero(), x, 100, 3.0).obstacle, 0);
  EXPECT_FALSE(w.cast(Vec3::Zero(), x, 100, 4.0).hit());
  // The sphere's centre is at x = t: a ray from x = -10 along +x meets it at 10 + t - 0.5.
  for (double t : {0.0, 1.5, 7.25}) EXPECT_NEAR(w.cast(Vec3(-10, 10, 0), x, 100, t).distance, 9.5 + t, 1e-12) << t;
  // Waypoints: held at (2, -10) before t = 1, linear to (6, -10) at t = 3, held after.
  auto tour_x = [&](double t) { return -10 + w.cast(Vec3(-10, -10, 0), x, 100, t).distance + 0.5; };
  EXPECT_NEAR(tour_x(0.0), 2.0, 1e-12);
  EXPECT_NEAR(tour_x(2.0), 4.0, 1e-12);
  EXPECT_NEAR(tour_x(2.5), 5.0, 1e-12);
  EXPECT_NEAR(tour_x(9.0), 6.0, 1e-12);
  EXPECT_NEAR((d.obstacles[2].anchor_at(1.5) - Vec3(3, -10, -1)).norm(), 0.0, 1e-12);
  // Alternating times (the moving set is rebuilt each time the time changes).
  for (int k = 0; k < 6; ++k) {
    const double t = (k % 2) ? 1.0 : 3.0;
    EXPECT_NEAR(w.cast(Vec3(-10, 10, 0), x, 100, t).distance, 9.5 + t, 1e-12);
  }
  EXPECT_EQ(w.primitives_at(3.0).size(), 3u);
  EXPECT_EQ(w.primitives_at(5.0).size(), 2u);
}

TEST(World, ValidationNamesTheObstacleAndField) {
  auto message_of = [](const Obstacle& o) {
    WorldDescription d;
    d.obstacles = {named("ok", {Sphere{}}), o};
    try {
      World w(d);
    } catch (const Error& e) {
      return e.field() + ": " + e.message();
    }
    return std::string("(none)");
  };
  Obstacle empty = named("nothing", {});
  EXPECT_EQ(message_of(empty), "parts: obstacle 1 (nothing): an obstacle needs at least one part");
  Obstacle both = named("b", {Sphere{}});
  both.velocity = Vec3(1, 0, 0);
  both.waypoints = {{0.0, Vec3::Zero()}};
  EXPECT_EQ(message_of(both).substr(0, 10), "waypoints:");
  Obstacle order = named("o", {Sphere{}});
  order.waypoints = {{1.0, Vec3::Zero()}, {1.0, Vec3::Ones()}};
  EXPECT_EQ(message_of(order).substr(0, 10), "waypoints:");
  Obstacle life = named("l", {Sphere{}});
  life.appear = 3.0;
  life.disappear = 2.0;
  EXPECT_EQ(message_of(life).substr(0, 10), "disappear:");
  Obstacle bad_part = named("p", {Box{Vec3::Zero(), Vec3(1, -1, 1)}});
  EXPECT_EQ(message_of(bad_part).substr(0, 5), "size:");
  EXPECT_THROW(make_undulating_ground(UndulatingGround{.count = 0}), Error);
  EXPECT_THROW(make_gravel(Gravel{.size_min = 0.05, .size_max = 0.01}), Error);
}

// Heights along the composite's centre line, sampled from above.
double height_on_line(const World& w, const Vec3& pos, double yaw, double x) {
  return w.surface_height(pos.x() + std::cos(yaw) * x, pos.y() + std::sin(yaw) * x, 0.0) - pos.z();
}

TEST(World, SlopeStepProfile) {
  SlopeStep s;
  s.position = Vec3(3, 1, 0.2);
  s.yaw = 0.6;
  WorldDescription d;
  d.terrain = flat_map(20, 0.1, 0.2, -7, -9);
  d.obstacles = {make_slope_step(s)};
  ASSERT_EQ(d.obstacles[0].parts.size(), 5u);
  const World w(d);
  const double total = 2 * s.ramp_length + 2 * s.platform_length + s.step_length, x0 = -0.5 * total;
  const double h = s.ramp_height, grade = h / s.ramp_length;
  // Up-ramp: linear from 0 to h; platforms at h; the step at h + step_height; down-ramp.
  for (double u : {0.1, 0.5, 0.9})
    EXPECT_NEAR(height_on_line(w, s.position, s.yaw, x0 + u * s.ramp_length), grade * u * s.ramp_length, 1e-9) << u;
  EXPECT_NEAR(height_on_line(w, s.position, s.yaw, x0 + s.ramp_length + 0.3), h, 1e-9);
  EXPECT_NEAR(height_on_line(w, s.position, s.yaw, 0.0), h + s.step_height, 1e-9);
  EXPECT_NEAR(height_on_line(w, s.position, s.yaw, -x0 - s.ramp_length - 0.3), h, 1e-9);
  EXPECT_NEAR(height_on_line(w, s.position, s.yaw, -x0 - 0.25 * s.ramp_length), grade * 0.25 * s.ramp_length, 1e-9);
  EXPECT_NEAR(height_on_line(w, s.position, s.yaw, -x0 + 0.2), 0.0, 1e-9);  // the ground beyond
  // Drivable defaults: slope <= 15 deg, steps <= 0.05 m.
  EXPECT_LE(std::atan(grade), deg_to_rad(15.0));
  EXPECT_LE(s.step_height, 0.05);
  // Across the width the sides are vertical: just outside the width there is only ground.
  EXPECT_NEAR(w.surface_height(3 - std::sin(0.6) * (0.5 * s.width + 0.01), 1 + std::cos(0.6) * (0.5 * s.width + 0.01), 0.0), 0.2, 1e-9);
}

TEST(World, UndulatingGroundAndRoundConvexProfiles) {
  UndulatingGround u;
  u.position = Vec3(0, 0, 0);
  RoundConvex r;
  r.position = Vec3(0, 5, 0);
  WorldDescription d;
  d.obstacles = {make_undulating_ground(u), make_round_convex(r)};
  const World w(d);
  const double b = u.base_width;
  for (int i = 0; i < u.count; ++i) {
    const double ridge = -0.5 * u.count * b + (i + 0.5) * b;
    EXPECT_NEAR(w.surface_height(ridge, 0.2, 0.0), u.height, 1e-9);
    EXPECT_NEAR(w.surface_height(ridge + 0.25 * b, 0.2, 0.0), 0.5 * u.height, 1e-9);
  }
  EXPECT_LE(std::atan(u.height / (0.5 * b)), deg_to_rad(15.0));
  EXPECT_NEAR(w.surface_height(0.0, 5.0, 0.0), r.box_size.z() + r.cylinder_height, 1e-12);
  EXPECT_NEAR(w.surface_height(0.5, 5.0, 0.0), r.box_size.z(), 1e-12);
  EXPECT_TRUE(std::isnan(w.surface_height(0.0, 20.0, 0.0)));  // no terrain, nothing there
}

TEST(World, GravelIsSeededAndFollowsTheTerrain) {
  GridGeometry g;
  g.width = g.height = 40;
  g.resolution = 0.1;
  ElevationMap m(g);
  for (int iy = 0; iy < 40; ++iy)
    for (int ix = 0; ix < 40; ++ix) m.set_height(ix, iy, 0.05 * ix * 0.1);  // 5 % grade along x
  const TerrainSurface ground(m);
  Gravel gr;
  gr.position = Vec3(2, 2, 0);
  gr.count = 200;
  gr.seed = 42;
  const Obstacle a = make_gravel(gr, &ground), b = make_gravel(gr, &ground);
  ASSERT_EQ(a.parts.size(), 200u);
  int spheres = 0;
  for (std::size_t i = 0; i < a.parts.size(); ++i) {
    EXPECT_EQ(bounds(a.parts[i]).lo, bounds(b.parts[i]).lo);
    const Aabb box = bounds(a.parts[i]);
    const Vec3 c = box.center();
    EXPECT_LE(std::abs(c.x() - 2), 0.5 * gr.length + 1e-12);
    EXPECT_LE(std::abs(c.y() - 2), 0.5 * gr.width + 1e-12);
    if (std::holds_alternative<Sphere>(a.parts[i])) {
      ++spheres;
      const Sphere& s = std::get<Sphere>(a.parts[i]);
      // Sunk by embed * size below the terrain under its centre.
      EXPECT_NEAR(s.center.z() - s.radius, ground.height(c.x(), c.y()) - gr.embed * 2 * s.radius, 1e-12);
      EXPECT_GE(2 * s.radius, gr.size_min);
      EXPECT_LE(2 * s.radius, gr.size_max);
    }
  }
  EXPECT_GT(spheres, 70);
  EXPECT_LT(spheres, 130);
  gr.seed = 43;
  EXPECT_NE(bounds(make_gravel(gr, &ground).parts[0]).lo, bounds(a.parts[0]).lo);
}

TEST(World, LidarInABoxRoomGivesClosedFormRanges) {
  // Walls (inner faces) at x = -3 and 4, y = -2 and 5; flat ground at z = 0; sensor 0.5 m up.
  WorldDescription d;
  d.terrain = flat_map(12, 0.1, 0.0, -5, -5);
  const double wall_h = 2.0;
  d.obstacles = {named("w1", {Box{Vec3(-3.5, 1.5, 1), Vec3(1, 9, wall_h)}}),
                 named("w2", {Box{Vec3(4.5, 1.5, 1), Vec3(1, 9, wall_h)}}),
                 named("w3", {Box{Vec3(0.5, -2.5, 1), Vec3(9, 1, wall_h)}}),
                 named("w4", {Box{Vec3(0.5, 5.5, 1), Vec3(9, 1, wall_h)}})};
  const World w(d);
  Lidar lidar(lidar_preset("generic_360"));
  const Pose3 robot = Pose3::from_rpy(Vec3(0, 0, 0.5), 0, 0, 0.3);
  const LidarScan scan = lidar.scan(w, robot, 0.0);
  ASSERT_EQ(scan.ranges.size(), 360u);
  for (int i = 0; i < 360; ++i) {
    const double a = scan.azimuths[static_cast<std::size_t>(i)] + 0.3;  // world bearing
    const double c = std::cos(a), s = std::sin(a);
    double want = kInf;
    if (c > 0) want = std::min(want, 4.0 / c);
    if (c < 0) want = std::min(want, -3.0 / c);
    if (s > 0) want = std::min(want, 5.0 / s);
    if (s < 0) want = std::min(want, -2.0 / s);
    EXPECT_NEAR(scan.range(0, i), want, 1e-9) << i;
    const Vec3 p = scan.points_world[static_cast<std::size_t>(i)];
    EXPECT_NEAR(p.z(), 0.5, 1e-12);
  }
  // A VLP-16 sees the floor on its downward lines: the floor point of the -15 deg line lies at
  // 0.5 / tan(15 deg) from the sensor.
  Lidar vlp(lidar_preset("vlp16", deg_to_rad(1.0)));
  const LidarScan s3 = vlp.scan(w, Pose3::from_rpy(Vec3(0, 0, 0.5), 0, 0, 0), 0.0);
  EXPECT_NEAR(s3.range(15, 0), 0.5 / std::sin(deg_to_rad(15.0)), 1e-9);
  for (std::size_t k = 0; k < s3.point_ray.size(); ++k)
    if (s3.point_ray[k] / 360 == 15) {
      EXPECT_NEAR(s3.points_world[k].z(), 0.0, 1e-9);
    }
}

}  // namespace
}  // namespace starnav
