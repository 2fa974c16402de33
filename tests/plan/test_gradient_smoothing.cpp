// Gradient smoothing beyond Ou 2022 (plan/gradient_smoothing.hpp): the segment test against a
// brute-force segment/box intersection, resampling, closed-form cases, and properties over
// random maps (collision-free, clearance kept, energy never higher, endpoints fixed).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "plan/plan_test_maps.hpp"
#include "starnav/core/error.hpp"
#include "starnav/plan/gradient_smoothing.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/plan/inflation.hpp"
#include "starnav/plan/path_metrics.hpp"

namespace starnav {
namespace {

using plantest::Map;

// Liang-Barsky: does the closed segment a-b meet the closed box [x0, x1] x [y0, y1]?
bool segment_meets_box(Vec2 a, Vec2 b, double x0, double x1, double y0, double y1) {
  double t0 = 0.0, t1 = 1.0;
  const double d[2] = {b.x() - a.x(), b.y() - a.y()};
  const double lo[2] = {x0, y0}, hi[2] = {x1, y1}, p[2] = {a.x(), a.y()};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (p[k] < lo[k] || p[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - p[k]) / d[k], tb = (hi[k] - p[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Brute force: every blocked cell's closed square, and the map's bounds (resolution 1, origin 0).
bool brute_clear(const Map& m, Vec2 a, Vec2 b) {
  for (const Vec2& p : {a, b})
    if (p.x() < 0 || p.y() < 0 || p.x() > m.w || p.y() > m.h) return false;
  for (int y = 0; y < m.h; ++y)
    for (int x = 0; x < m.w; ++x)
      if (!m.free(x, y) && segment_meets_box(a, b, x, x + 1, y, y + 1)) return false;
  return true;
}

GridGeometry unit_geometry(const Map& m, double resolution = 1.0) {
  GridGeometry g;
  g.width = m.w;
  g.height = m.h;
  g.resolution = resolution;
  return g;
}

TEST(GradientSmoothing, SegmentTestEqualsBruteForceOnRandomSegments) {
  Rng rng(9101);
  int blocked = 0, clear = 0;
  for (int iter = 0; iter < 4000; ++iter) {
    const Map m = plantest::random_obstacles(rng, 4 + static_cast<int>(rng.uniform_int(0, 12)),
                                             4 + static_cast<int>(rng.uniform_int(0, 12)), rng.uniform(0.0, 0.2));
    const GridSearchMap sm(m.w, m.h, m.blocked);
    // Random endpoints inside (mostly) the map: ties with grid lines have probability zero.
    const Vec2 a(rng.uniform(-0.5, m.w + 0.5), rng.uniform(-0.5, m.h + 0.5));
    const Vec2 b(rng.uniform(-0.5, m.w + 0.5), rng.uniform(-0.5, m.h + 0.5));
    const bool expected = brute_clear(m, a, b);
    ASSERT_EQ(segment_clear(sm, unit_geometry(m), a, b), expected) << iter;
    (expected ? clear : blocked)++;
  }
  EXPECT_GT(clear, 300);
  EXPECT_GT(blocked, 300);
}

TEST(GradientSmoothing, SegmentThroughACornerOrAlongAGridLineTouchesBothSides) {
  Map m{4, 4, std::vector<std::uint8_t>(16, 0)};
  m.set(1, 2, true);  // beside the diagonal from (1, 1)'s centre to (2, 2)'s, touching its corner
  const GridSearchMap sm(m.w, m.h, m.blocked);
  const GridGeometry g = unit_geometry(m);
  EXPECT_FALSE(segment_clear(sm, g, {1.5, 1.5}, {2.5, 2.5}));  // passes exactly through (2, 2)
  EXPECT_TRUE(segment_clear(sm, g, {1.5, 1.5}, {3.5, 1.5}));
  EXPECT_FALSE(segment_clear(sm, g, {0.5, 2.0}, {3.5, 2.0}));  // along the line y = 2, row 2's edge
  EXPECT_TRUE(segment_clear(sm, g, {0.5, 1.9}, {3.5, 1.9}));
  EXPECT_FALSE(segment_clear(sm, g, {0.5, 0.5}, {4.5, 0.5}));  // leaves the map
  EXPECT_FALSE(segment_clear(sm, g, {0.5, 0.5}, {std::nan(""), 0.5}));
}

TEST(GradientSmoothing, ResampleKeepsVerticesLengthAndSpacing) {
  const std::vector<Vec2> path{{0, 0}, {3, 0}, {3, 0}, {3, 2.5}, {0.2, 2.5}};
  const std::vector<Vec2> r = resample_polyline(path, 0.7);
  double length = 0.0;
  for (std::size_t i = 1; i < r.size(); ++i) {
    const double s = (r[i] - r[i - 1]).norm();
    EXPECT_GT(s, 0.0);
    EXPECT_LE(s, 0.7 + 1e-12);
    length += s;
  }
  EXPECT_NEAR(length, 3.0 + 2.5 + 2.8, 1e-12);
  for (const Vec2& v : {Vec2(0, 0), Vec2(3, 0), Vec2(3, 2.5), Vec2(0.2, 2.5)})
    EXPECT_TRUE(std::any_of(r.begin(), r.end(), [&](const Vec2& p) { return p == v; }));
  EXPECT_EQ(r.front(), path.front());
  EXPECT_EQ(r.back(), path.back());
  EXPECT_THROW(resample_polyline(path, 0.0), Error);
}

TEST(GradientSmoothing, StraightPathStaysAndAnOpenCornerIsRoundedSymmetrically) {
  Map m{30, 30, std::vector<std::uint8_t>(900, 0)};
  const GridSearchMap sm(m.w, m.h, m.blocked);
  const GridGeometry g = unit_geometry(m, 0.1);
  // Straight: already optimal (E = 0).
  const std::vector<Vec2> line{{0.55, 1.05}, {2.45, 1.05}};
  const GradientSmoothingResult s = smooth_path_gradient(line, sm, g, nullptr);
  EXPECT_EQ(s.energy_input, 0.0);
  for (const Vec2& p : s.points) EXPECT_NEAR(p.y(), 1.05, 1e-12);
  // An L with legs of 1 m on open ground: the right-angle corner becomes a curve, symmetric about
  // the corner's bisector, with no turn of more than 45 deg at any sample.
  const std::vector<Vec2> corner{{0.55, 1.55}, {1.55, 1.55}, {1.55, 2.55}};
  GradientSmoothingOptions converged;
  converged.tolerance_m = 1e-12;
  converged.max_iterations = 100000;
  const GradientSmoothingResult c = smooth_path_gradient(corner, sm, g, nullptr, converged);
  ASSERT_EQ(c.points.size(), 21u);
  EXPECT_LT(c.energy_output, c.energy_input);
  EXPECT_LT(compute_path_metrics(c.points).turn_max_rad, std::numbers::pi / 4);
  const Vec2 k(1.55, 1.55);
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const Vec2 p = c.points[i] - k, q = c.points[c.points.size() - 1 - i] - k;  // mirror: (x, y) -> (-y, -x)
    EXPECT_NEAR(p.x(), -q.y(), 1e-6) << i;
    EXPECT_NEAR(p.y(), -q.x(), 1e-6) << i;
  }
  // The corner sample moved inside the turn (towards (0.55, 2.55)), 3.5 cm each way with the
  // default weights.
  EXPECT_LT(c.points[10].x(), 1.55 - 0.02);
  EXPECT_GT(c.points[10].y(), 1.55 + 0.02);
}

TEST(GradientSmoothing, ValidationNamesTheField) {
  auto field_of = [](const GradientSmoothingOptions& o) {
    try {
      validate_gradient_smoothing(o);
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("(none)");
  };
  GradientSmoothingOptions o;
  EXPECT_EQ(field_of(o), "(none)");
  o.weight_data = 0.0;
  EXPECT_EQ(field_of(o), "smooth_weight_data");
  o = {};
  o.weight_smooth = std::nan("");
  EXPECT_EQ(field_of(o), "smooth_weight_smooth");
  o = {};
  o.spacing_m = -1;
  EXPECT_EQ(field_of(o), "smooth_spacing");
  o = {};
  o.min_clearance_m = INFINITY;
  EXPECT_EQ(field_of(o), "smooth_clearance");
  o = {};
  o.max_iterations = -1;
  EXPECT_EQ(field_of(o), "smooth_iterations");
  o = {};
  o.tolerance_m = -1e-3;
  EXPECT_EQ(field_of(o), "smooth_tolerance");
  // A clearance floor needs a clearance field.
  Map m{5, 5, std::vector<std::uint8_t>(25, 0)};
  o = {};
  o.min_clearance_m = 0.1;
  const std::vector<Vec2> path{{0.5, 0.5}, {2.5, 2.5}};
  EXPECT_THROW(smooth_path_gradient(path, GridSearchMap(5, 5, m.blocked), unit_geometry(m), nullptr, o), Error);
}

// Over random maps: A* + line-of-sight pruning on the inflated map, then the smoother.
TEST(GradientSmoothing, RandomMapsStayCollisionFreeKeepClearanceAndNeverRaiseTheEnergy) {
  Rng rng(9102);
  int smoothed = 0;
  double turn_in = 0.0, turn_out = 0.0;
  for (int iter = 0; iter < 300; ++iter) {
    SCOPED_TRACE(iter);
    const Map raw = plantest::any_map(rng, iter, 14 + static_cast<int>(rng.uniform_int(0, 10)));
    const double res = 0.1;
    const OccupancyGrid grid = raw.grid(res);
    GridPlannerOptions po;
    po.ou2022.inflation.radius_m = rng.bernoulli(0.5) ? 0.0 : res;
    po.ou2022.smoothing = PathSmoothing::LineOfSight;
    const InflatedMap inflated = inflate_obstacles(grid, {}, false, po.ou2022.inflation);
    Map infl{raw.w, raw.h, inflated.blocked};
    const Cell s = plantest::random_free_cell(rng, infl), t = plantest::random_free_cell(rng, infl);
    if (s.x < 0 || t.x < 0) continue;
    const PlanResult r = make_grid_planner("astar", grid, po)->plan(s, t);
    if (!r.found() || r.path_world.size() < 3) continue;
    const GridSearchMap sm(raw.w, raw.h, inflated.blocked);
    const ClearanceField field(grid.geometry(), inflated.clearance_m);
    GradientSmoothingOptions o;
    o.min_clearance_m = rng.bernoulli(0.5) ? 0.0 : rng.uniform(0.05, 0.4);
    o.spacing_m = rng.uniform(0.3, 1.5) * res;
    // Weights from the default up to a strong pull to curvature (moves of several cells).
    o.weight_data = rng.uniform(0.02, 0.3);
    o.weight_smooth = rng.uniform(0.3, 3.0);
    const GradientSmoothingResult out = smooth_path_gradient(r.path_world, sm, grid.geometry(), &field, o);
    ++smoothed;
    ASSERT_EQ(out.points.front(), r.path_world.front());
    ASSERT_EQ(out.points.back(), r.path_world.back());
    ASSERT_LE(out.energy_output, out.energy_input * (1 + 1e-12) + 1e-12);
    // Collision-free on the inflated map (brute force, in cells).
    for (std::size_t i = 1; i < out.points.size(); ++i)
      ASSERT_TRUE(brute_clear(infl, out.points[i - 1] / res, out.points[i] / res)) << "segment " << i;
    // Clearance: each sample keeps min(floor, its input sample's), a point on a cell edge or
    // corner counting its least neighbouring cell.
    auto least_clearance = [&](const Vec2& w) {
      const Vec2 c = w / res;
      double least = kInfinity;
      for (const double dy : {-1e-7, 1e-7})
        for (const double dx : {-1e-7, 1e-7}) least = std::min(least, field.at(Vec2((c.x() + dx) * res, (c.y() + dy) * res)));
      return least;
    };
    const std::vector<Vec2> input = resample_polyline(r.path_world, o.spacing_m);
    ASSERT_EQ(input.size(), out.points.size());
    for (std::size_t i = 0; i < input.size(); ++i)
      ASSERT_GE(field.at(out.points[i]), std::min(o.min_clearance_m, least_clearance(input[i])) - 1e-12) << i;
    turn_in += compute_path_metrics(input).turn_max_rad;
    turn_out += compute_path_metrics(out.points).turn_max_rad;
  }
  EXPECT_GT(smoothed, 100);
  RecordProperty("turn_max_sum_in", std::to_string(turn_in));
  RecordProperty("turn_max_sum_out", std::to_string(turn_out));
  // It does smooth: the largest turn per path falls on average.
  EXPECT_LT(turn_out, 0.8 * turn_in);
}

}  // namespace
}  // namespace starnav
