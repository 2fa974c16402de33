// Hybrid-A* (plan/hybrid_astar.hpp) against truths computed here: every path is re-read as a
// sequence of circular arcs from its poses alone (each pair of consecutive poses must be joined
// by one arc that starts along the first heading and ends along the second), its curvature bounded
// by 1/R and its footprint tested every centimetre by an exact rectangle-square (or circle-square)
// intersection against every obstacle cell nearby; the heuristic never exceeds the cost of an
// exhaustive uniform-cost search over the same lattice written here from scratch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <queue>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/plan/car_curves.hpp"
#include "starnav/plan/hybrid_astar.hpp"
#include "starnav/registry/components.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

constexpr double kTwoPi = 2.0 * kPi;

OccupancyGrid empty_grid(int w, int h, double res) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  return OccupancyGrid(g, kFreeOccupancy);
}

void block_rect(OccupancyGrid& grid, double x0, double y0, double x1, double y1) {
  const double res = grid.resolution();
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x) {
      const double cx = (x + 0.5) * res, cy = (y + 0.5) * res;
      if (cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1) grid(x, y) = kOccupiedOccupancy;
    }
}

// ---- the independent footprint test -------------------------------------------------------------

struct Body {
  bool circle = true;
  double radius = 0.0, half_length = 0.0, half_width = 0.0;
};

// Whether the body at `p` overlaps the closed square [x0, x1] x [y0, y1].
bool overlaps_square(const Body& b, const Pose2& p, double x0, double y0, double x1, double y1) {
  if (b.circle) {
    const double dx = std::max({x0 - p.x, 0.0, p.x - x1}), dy = std::max({y0 - p.y, 0.0, p.y - y1});
    return dx * dx + dy * dy <= b.radius * b.radius;
  }
  // Separating axes of two convex polygons: the square's two axes and the rectangle's two.
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  const double rx[4] = {b.half_length, b.half_length, -b.half_length, -b.half_length};
  const double ry[4] = {b.half_width, -b.half_width, -b.half_width, b.half_width};
  double cx[4], cy[4];
  for (int i = 0; i < 4; ++i) cx[i] = p.x + c * rx[i] - s * ry[i], cy[i] = p.y + s * rx[i] + c * ry[i];
  const double sx[4] = {x0, x1, x1, x0}, sy[4] = {y0, y0, y1, y1};
  const double axes[4][2] = {{1, 0}, {0, 1}, {c, s}, {-s, c}};
  for (const auto& a : axes) {
    double lo1 = 1e300, hi1 = -1e300, lo2 = 1e300, hi2 = -1e300;
    for (int i = 0; i < 4; ++i) {
      const double v1 = a[0] * cx[i] + a[1] * cy[i], v2 = a[0] * sx[i] + a[1] * sy[i];
      lo1 = std::min(lo1, v1), hi1 = std::max(hi1, v1), lo2 = std::min(lo2, v2), hi2 = std::max(hi2, v2);
    }
    if (hi1 < lo2 || hi2 < lo1) return false;
  }
  return true;
}

// Brute force: every occupied cell (and every cell outside the map) within reach of the body.
bool body_collides(const OccupancyGrid& grid, const Body& b, const Pose2& p) {
  const double res = grid.resolution();
  const double reach = b.circle ? b.radius : std::hypot(b.half_length, b.half_width);
  // Part of the body off the map: a corner of the rectangle, or the circle's extent.
  const double mw = grid.width() * res, mh = grid.height() * res;
  if (b.circle) {
    if (p.x - b.radius < 0.0 || p.y - b.radius < 0.0 || p.x + b.radius > mw || p.y + b.radius > mh) return true;
  } else {
    const double c = std::cos(p.yaw), s = std::sin(p.yaw);
    for (const double u : {-b.half_length, b.half_length})
      for (const double v : {-b.half_width, b.half_width}) {
        const double x = p.x + c * u - s * v, y = p.y + s * u + c * v;
        if (x < 0.0 || y < 0.0 || x > mw || y > mh) return true;
      }
  }
  const int x0 = static_cast<int>(std::floor((p.x - reach) / res)), x1 = static_cast<int>(std::floor((p.x + reach) / res));
  const int y0 = static_cast<int>(std::floor((p.y - reach) / res)), y1 = static_cast<int>(std::floor((p.y + reach) / res));
  for (int y = std::max(0, y0); y <= std::min(grid.height() - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(grid.width() - 1, x1); ++x)
      if (grid(x, y) != kFreeOccupancy && overlaps_square(b, p, x * res, y * res, (x + 1) * res, (y + 1) * res)) return true;
  return false;
}

// ---- the path re-read as arcs -------------------------------------------------------------------

struct PathCheck {
  double max_curvature = 0.0;
  double max_tangent_error = 0.0;  // how far a pose pair is from one arc (rad)
  int collisions = 0;
  int checks = 0;
  int wrong_direction = 0;  // displacement against the claimed direction
  int cusps = 0;
};

// Every consecutive pair: the arc leaving p0 along its heading (backwards when reversing) through
// p1 has travel curvature k = 2 sin(a) / chord (a: the chord's angle to the direction of travel)
// and turns the heading by 2a; p1's heading must be that. The footprint is tested every 1 cm
// along that arc.
PathCheck check_path(const OccupancyGrid& grid, const Body& body, const std::vector<Pose2>& poses,
                     const std::vector<std::uint8_t>& reversing, const std::function<void(const Pose2&)>& visit = {}) {
  PathCheck out;
  for (std::size_t i = 0; i + 1 < poses.size(); ++i) {
    const Pose2& p0 = poses[i];
    const Pose2& p1 = poses[i + 1];
    const bool rev = reversing[i] != 0;
    if (i > 0 && reversing[i] != reversing[i - 1]) ++out.cusps;
    const double dx = p1.x - p0.x, dy = p1.y - p0.y, chord = std::hypot(dx, dy);
    if (chord < 1e-12) {
      out.max_tangent_error = std::max(out.max_tangent_error, std::abs(angle_diff(p1.yaw, p0.yaw)));
      continue;
    }
    const double travel0 = rev ? p0.yaw + kPi : p0.yaw;
    const double a = angle_diff(std::atan2(dy, dx), travel0);
    if (std::abs(a) >= kPi / 2) ++out.wrong_direction;
    out.max_tangent_error = std::max(out.max_tangent_error, std::abs(angle_diff(p1.yaw, p0.yaw + 2.0 * a)));
    const double k = 2.0 * std::sin(a) / chord;  // signed, along the travel direction
    out.max_curvature = std::max(out.max_curvature, std::abs(k));
    const double len = std::abs(a) < 1e-12 ? chord : chord * a / std::sin(a);
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.01)));
    for (int j = 0; j <= n; ++j) {
      const double s = len * j / n;
      Pose2 q;
      if (std::abs(k) < 1e-12) {
        q = {p0.x + std::cos(travel0) * s, p0.y + std::sin(travel0) * s, p0.yaw};
      } else {
        q = {p0.x + (std::sin(travel0 + k * s) - std::sin(travel0)) / k,
             p0.y - (std::cos(travel0 + k * s) - std::cos(travel0)) / k, p0.yaw + k * s};
      }
      ++out.checks;
      if (visit) visit(q);
      else if (body_collides(grid, body, q)) ++out.collisions;
    }
  }
  return out;
}

HybridAStarOptions car_options(HybridMotionModel model) {
  HybridAStarOptions o;
  o.motion_model = model;
  o.minimum_turning_radius_m = 1.0;
  o.footprint_length_m = 0.6;
  o.footprint_width_m = 0.4;
  o.analytic_expansion_max_length_m = 0.0;
  o.max_iterations = 200000;
  return o;
}

Body body_of(const HybridAStarOptions& o) {
  Body b;
  b.circle = o.footprint_length_m == 0.0;
  b.radius = o.robot_radius_m;
  b.half_length = 0.5 * o.footprint_length_m;
  b.half_width = 0.5 * o.footprint_width_m;
  return b;
}

// A 10 x 8 m map at 0.1 m with random boxes, the start and goal areas kept clear.
OccupancyGrid random_map(Rng& rng, const Pose2& start, const Pose2& goal) {
  OccupancyGrid grid = empty_grid(100, 80, 0.1);
  for (int k = 0; k < 6; ++k) {
    const double x = rng.uniform(1.0, 9.0), y = rng.uniform(1.0, 7.0);
    const double w = rng.uniform(0.3, 1.5), h = rng.uniform(0.3, 1.5);
    if (std::hypot(x - start.x, y - start.y) < 2.0 || std::hypot(x - goal.x, y - goal.y) < 2.0) continue;
    block_rect(grid, x - w / 2, y - h / 2, x + w / 2, y + h / 2);
  }
  return grid;
}

TEST(HybridAStar, EveryPathIsCollisionFreeAndWithinTheTurningRadius) {
  Rng rng(45);
  int found = 0, queries = 0, reversing_paths = 0;
  for (const HybridMotionModel model : {HybridMotionModel::ReedsShepp, HybridMotionModel::Dubins}) {
    for (int q = 0; q < 6; ++q) {
      const Pose2 start(rng.uniform(1.0, 2.5), rng.uniform(1.0, 7.0), rng.uniform(-kPi, kPi));
      const Pose2 goal(rng.uniform(7.5, 9.0), rng.uniform(1.0, 7.0), rng.uniform(-kPi, kPi));
      const OccupancyGrid grid = random_map(rng, start, goal);
      HybridAStarOptions o = car_options(model);
      o.smooth = q % 2 == 0;
      HybridAStar planner(grid, o);
      const PlanResult r = planner.plan(start, goal);
      ++queries;
      if (!r.found()) continue;
      ++found;
      ASSERT_EQ(r.path_poses.size(), r.path_reversing.size());
      ASSERT_GE(r.path_poses.size(), 2u);
      EXPECT_NEAR(r.path_poses.front().x, start.x, 1e-9);
      EXPECT_NEAR(r.path_poses.front().y, start.y, 1e-9);
      EXPECT_NEAR(angle_diff(r.path_poses.front().yaw, start.yaw), 0.0, 1e-9);
      EXPECT_NEAR(r.path_poses.back().x, goal.x, 1e-6);
      EXPECT_NEAR(r.path_poses.back().y, goal.y, 1e-6);
      EXPECT_NEAR(angle_diff(r.path_poses.back().yaw, goal.yaw), 0.0, 1e-6);
      const PathCheck c = check_path(grid, body_of(o), r.path_poses, r.path_reversing);
      EXPECT_EQ(c.collisions, 0) << "query " << q << " model " << hybrid_motion_model_name(model);
      EXPECT_LE(c.max_curvature, 1.0 / o.minimum_turning_radius_m + 1e-6);
      EXPECT_LT(c.max_tangent_error, 1e-6);
      EXPECT_EQ(c.wrong_direction, 0);
      EXPECT_GT(c.checks, 0);
      if (model == HybridMotionModel::Dubins) {
        EXPECT_EQ(c.cusps, 0);
      }
      if (std::count(r.path_reversing.begin(), r.path_reversing.end(), 1) > 0) ++reversing_paths;
      if (model == HybridMotionModel::Dubins) {
        EXPECT_EQ(std::count(r.path_reversing.begin(), r.path_reversing.end(), 1), 0);
      }
      // The reported length is the arcs' (the chords are shorter, never longer).
      double chords = 0.0;
      for (std::size_t i = 0; i + 1 < r.path_poses.size(); ++i)
        chords += std::hypot(r.path_poses[i + 1].x - r.path_poses[i].x, r.path_poses[i + 1].y - r.path_poses[i].y);
      EXPECT_LE(chords, r.length + 1e-9);
      EXPECT_GE(chords, r.length * 0.99);
      EXPECT_GE(r.cost, r.length - 1e-9);
    }
  }
  EXPECT_GE(found, queries - 2);
}

// The rectangle and circle of the planner against the brute-force test: a pose the planner calls
// free is free (its rule is conservative by half a cell diagonal).
TEST(HybridAStar, ThePlannersFootprintTestNeverPassesAColliding_pose) {
  Rng rng(7);
  const Pose2 s(1, 1, 0), g(9, 7, 0);
  const OccupancyGrid grid = random_map(rng, s, g);
  for (const bool rectangle : {true, false}) {
    HybridAStarOptions o = car_options(HybridMotionModel::ReedsShepp);
    if (!rectangle) o.footprint_length_m = o.footprint_width_m = 0.0;
    HybridAStar planner(grid, o);
    int free_poses = 0;
    for (int i = 0; i < 5000; ++i) {
      const Pose2 p(rng.uniform(0.0, 10.0), rng.uniform(0.0, 8.0), rng.uniform(-kPi, kPi));
      if (planner.collides(p)) continue;
      ++free_poses;
      EXPECT_FALSE(body_collides(grid, body_of(o), p)) << p.x << " " << p.y << " " << p.yaw;
    }
    EXPECT_GT(free_poses, 1000);
  }
}

// ---- admissibility against an exhaustive search ----------------------------------------------------

// Uniform-cost search over the lattice Hybrid-A* searches, written from its definition: from a
// pose, arcs of radius R (left, straight, right; forward and for Reeds-Shepp reverse) whose length
// turns the heading by whole bins and spans at least a cell diagonal; poses merged by (cell, bin);
// every motion's footprint checked at half-cell steps; the goal reached by the obstacle-free curve
// from any pose when that curve is free. With unit penalties a cost is a length, and the search
// runs until no open pose is cheaper than the best path: the optimum on this lattice.
double exhaustive_cost(const HybridAStar& planner, const OccupancyGrid& grid, const Pose2& start, const Pose2& goal,
                       bool reeds_shepp, double r, int bins) {
  const double res = grid.resolution();
  const double bin = kTwoPi / bins;
  const double min_angle = 2.0 * std::asin(std::min(1.0, std::sqrt(2.0) * res / (2.0 * r)));
  const int turn = std::max(1, static_cast<int>(std::ceil(min_angle / bin - 1e-9)));
  const double step = r * turn * bin;
  const auto arc = [&](const Pose2& p, double k, double s) {
    if (k == 0.0) return Pose2(p.x + std::cos(p.yaw) * s, p.y + std::sin(p.yaw) * s, p.yaw);
    return Pose2(p.x + (std::sin(p.yaw + k * s) - std::sin(p.yaw)) / k, p.y - (std::cos(p.yaw + k * s) - std::cos(p.yaw)) / k,
                 p.yaw + k * s);
  };
  const auto free_along = [&](const Pose2& p, double k, double s) {
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(s) / (0.5 * res) - 1e-9)));
    for (int i = 1; i <= n; ++i)
      if (planner.collides(arc(p, k, s * i / n))) return false;
    return true;
  };
  const auto curve_free = [&](const CarPath& c) {
    double s = 0.0;
    for (std::size_t i = 0; i < c.segment_count; ++i) {
      if (!free_along(c.pose_at(s), c.curvature(c.segments[i]), c.segments[i].length)) return false;
      s += std::abs(c.segments[i].length);
    }
    return true;
  };
  const auto key = [&](const Pose2& p) {
    const long cx = static_cast<long>(std::floor(p.x / res)), cy = static_cast<long>(std::floor(p.y / res));
    long b = static_cast<long>(std::floor(wrap_angle(p.yaw) / bin + 0.5)) % bins;
    if (b < 0) b += bins;
    return (cy * grid.width() + cx) * bins + b;
  };
  struct Entry {
    double g;
    long key;
    bool operator>(const Entry& o) const { return g > o.g; }
  };
  std::map<long, std::pair<double, Pose2>> best;
  std::map<long, bool> closed;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  best[key(start)] = {0.0, start};
  open.push({0.0, key(start)});
  double answer = std::numeric_limits<double>::infinity();
  const int motions = reeds_shepp ? 6 : 3;
  while (!open.empty()) {
    const Entry e = open.top();
    open.pop();
    if (e.g >= answer) break;
    if (closed[e.key] || e.g > best[e.key].first) continue;
    closed[e.key] = true;
    const Pose2 p = best[e.key].second;
    const CarPath c = reeds_shepp ? shortest_reeds_shepp_path(p, goal, r) : shortest_dubins_path(p, goal, r);
    if (e.g + c.length < answer && curve_free(c)) answer = e.g + c.length;
    for (int m = 0; m < motions; ++m) {
      const double k = (m % 3 == 0) ? 0.0 : (m % 3 == 1 ? 1.0 / r : -1.0 / r);
      const double s = m < 3 ? step : -step;
      const Pose2 q = arc(p, k, s);
      if (q.x < 0 || q.y < 0 || q.x >= grid.width() * res || q.y >= grid.height() * res) continue;
      const long kq = key(q);
      if (closed[kq]) continue;
      if (!free_along(p, k, s)) continue;
      const double g = e.g + step;
      auto it = best.find(kq);
      if (it == best.end() || g < it->second.first) {
        best[kq] = {g, q};
        open.push({g, kq});
      }
    }
  }
  return answer;
}

TEST(HybridAStar, TheHeuristicNeverExceedsTheExhaustiveOptimum) {
  Rng rng(2024);
  int compared = 0;
  for (const bool rs : {true, false}) {
    for (int map_i = 0; map_i < 3; ++map_i) {
      OccupancyGrid grid = empty_grid(40, 30, 0.1);
      for (int k = 0; k < 4; ++k) {
        const double x = rng.uniform(0.5, 3.5), y = rng.uniform(0.5, 2.5);
        block_rect(grid, x - 0.2, y - 0.2, x + 0.2, y + 0.2);
      }
      HybridAStarOptions o;
      o.motion_model = rs ? HybridMotionModel::ReedsShepp : HybridMotionModel::Dubins;
      o.minimum_turning_radius_m = 0.5;
      o.angle_bins = 36;
      o.robot_radius_m = 0.12;
      o.non_straight_penalty = 1.0;
      o.reverse_penalty = 1.0;
      o.cost_penalty = 0.0;
      o.analytic_expansion_max_length_m = 0.0;
      HybridAStar planner(grid, o);
      for (int q = 0; q < 6; ++q) {
        Pose2 start, goal;
        do {
          start = Pose2(rng.uniform(0.2, 3.8), rng.uniform(0.2, 2.8), rng.uniform(-kPi, kPi));
        } while (planner.collides(start));
        do {
          goal = Pose2(rng.uniform(0.2, 3.8), rng.uniform(0.2, 2.8), rng.uniform(-kPi, kPi));
        } while (planner.collides(goal));
        const PlanResult r = planner.plan(start, goal);
        const double h = planner.heuristic(start);
        const double truth = exhaustive_cost(planner, grid, start, goal, rs, o.minimum_turning_radius_m, o.angle_bins);
        if (std::isinf(truth)) {
          EXPECT_FALSE(r.found());
          continue;
        }
        ++compared;
        EXPECT_LE(h, truth + 1e-9) << "rs " << rs << " map " << map_i << " query " << q;
        // Each part alone, and the curve part against the curve itself.
        EXPECT_LE(planner.obstacle_heuristic(start), truth + 1e-9);
        const double curve = (rs ? shortest_reeds_shepp_path(start, goal, 0.5) : shortest_dubins_path(start, goal, 0.5)).length;
        EXPECT_NEAR(planner.curve_heuristic(start), curve, 1e-12);
      }
    }
  }
  EXPECT_GE(compared, 20);
}

// On an open map the obstacle bound is below the straight-line distance (it is a lower bound of
// a path among obstacles, which is at least that).
TEST(HybridAStar, TheObstacleBoundIsBelowTheStraightLineOnAnOpenMap) {
  const OccupancyGrid grid = empty_grid(60, 60, 0.05);
  HybridAStarOptions o;
  o.robot_radius_m = 0.1;
  HybridAStar planner(grid, o);
  const Pose2 goal(1.52, 1.47, 0.3);
  ASSERT_TRUE(planner.plan(Pose2(0.5, 0.5, 0.0), goal).found());
  Rng rng(3);
  for (int i = 0; i < 2000; ++i) {
    const Pose2 p(rng.uniform(0.2, 2.8), rng.uniform(0.2, 2.8), 0.0);
    const double d = std::hypot(p.x - goal.x, p.y - goal.y);
    EXPECT_LE(planner.obstacle_heuristic(p), d + 1e-12);
    EXPECT_GE(planner.obstacle_heuristic(p), d / 1.0824 - 3.0 * 0.05);  // and not far below it
  }
}

// ---- parking: reversing needed ---------------------------------------------------------------------

// A dead-end corridor 1.2 m wide (less than 2R): the car faces the end wall and must come out
// backwards to the corridor's mouth, still facing the wall.
TEST(HybridAStar, ADeadEndNeedsReedsSheppAndDubinsRefuses) {
  OccupancyGrid grid = empty_grid(120, 60, 0.1);
  block_rect(grid, 0.0, 0.0, 12.0, 2.35);  // the corridor y in (2.4, 3.6), closed at x = 11
  block_rect(grid, 0.0, 3.65, 12.0, 6.0);
  block_rect(grid, 11.0, 0.0, 12.0, 6.0);
  const Pose2 start(9.0, 3.0, 0.0), goal(3.0, 3.0, 0.0);
  HybridAStarOptions o = car_options(HybridMotionModel::ReedsShepp);
  o.minimum_turning_radius_m = 2.5;
  o.max_iterations = 20000;
  HybridAStar rs(grid, o);
  const PlanResult r = rs.plan(start, goal);
  ASSERT_TRUE(r.found()) << plan_status_reason(r.status);
  EXPECT_GT(std::count(r.path_reversing.begin(), r.path_reversing.end(), 1), 0);
  EXPECT_NEAR(r.length, 6.0, 1e-6);  // straight back
  const PathCheck c = check_path(grid, body_of(o), r.path_poses, r.path_reversing);
  EXPECT_EQ(c.collisions, 0);
  o.motion_model = HybridMotionModel::Dubins;
  HybridAStar dubins(grid, o);
  const PlanResult d = dubins.plan(start, goal);
  EXPECT_FALSE(d.found());
  EXPECT_TRUE(d.status == PlanStatus::NoPath || d.status == PlanStatus::ExpansionLimit) << plan_status_reason(d.status);
}

// Reverse parking into a bay off an open lot: the goal faces out of the bay, so the car must back
// in; Dubins can only enter forwards and finds no way to end facing out.
TEST(HybridAStar, ReverseParkingIntoABay) {
  OccupancyGrid grid = empty_grid(160, 120, 0.1);
  // The bay: 1.2 m wide and 2.4 m deep at the bottom of the lot, walls either side.
  block_rect(grid, 0.0, 0.0, 7.4, 2.4);
  block_rect(grid, 8.6, 0.0, 16.0, 2.4);
  const Pose2 start(3.0, 8.0, 0.0), goal(8.0, 1.2, kPi / 2);
  HybridAStarOptions o = car_options(HybridMotionModel::ReedsShepp);
  o.minimum_turning_radius_m = 2.0;
  o.footprint_length_m = 1.6;
  o.footprint_width_m = 0.8;
  o.max_iterations = 30000;
  HybridAStar rs(grid, o);
  const PlanResult r = rs.plan(start, goal);
  ASSERT_TRUE(r.found()) << plan_status_reason(r.status);
  EXPECT_EQ(r.path_reversing.back(), 1);  // arrives backwards
  const PathCheck c = check_path(grid, body_of(o), r.path_poses, r.path_reversing);
  EXPECT_EQ(c.collisions, 0);
  EXPECT_LE(c.max_curvature, 1.0 / o.minimum_turning_radius_m + 1e-6);
  o.motion_model = HybridMotionModel::Dubins;
  HybridAStar dubins(grid, o);
  const PlanResult d = dubins.plan(start, goal);
  EXPECT_FALSE(d.found()) << d.length;
}

// The distance from `point` to the rectangle body at `p` (0 inside).
double distance_to_body(const Body& b, const Pose2& p, double x, double y) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  const double u = c * (x - p.x) + s * (y - p.y), v = -s * (x - p.x) + c * (y - p.y);
  return std::hypot(std::max(std::abs(u) - b.half_length, 0.0), std::max(std::abs(v) - b.half_width, 0.0));
}

// The nearest obstacle cell centre to the body at `p` (brute force over the map).
double nearest_cell_centre(const OccupancyGrid& grid, const Body& b, const Pose2& p) {
  const double res = grid.resolution();
  double best = 1e300;
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x)
      if (grid(x, y) != kFreeOccupancy) best = std::min(best, distance_to_body(b, p, (x + 0.5) * res, (y + 0.5) * res));
  return best;
}

// A car in a bay nearer a sensed side than the checker's rule allows (the rule grows the body by
// half a cell's diagonal) but with no obstacle cell centre under the body: it may drive out, by
// poses no nearer the cell centres than the start (to within the half collision step between the
// planner's samples), and once the rule clears it stays clear. A body that holds a cell centre
// stays blocked.
TEST(HybridAStar, AStartNearerAWallThanTheRuleMayLeaveButNotAStartOnIt) {
  const double res = 0.05, half_diagonal = 0.5 * std::sqrt(2.0) * res;
  OccupancyGrid grid = empty_grid(120, 100, res);
  // The bay's sides: cell centres up to x = 1.975 and from x = 2.725, 1.2 m deep.
  block_rect(grid, 0.0, 0.0, 2.0, 1.2);
  block_rect(grid, 2.7, 0.0, 6.0, 1.2);
  HybridAStarOptions o = car_options(HybridMotionModel::ReedsShepp);
  o.minimum_turning_radius_m = 0.85;
  const Body body = body_of(o);
  // The body's left side 3 cm from the nearest cell centres: inside the rule, outside the body.
  const Pose2 start(1.975 + 0.03 + 0.2, 0.6, kPi / 2), goal(4.0, 3.0, 0.0);
  ASSERT_NEAR(nearest_cell_centre(grid, body, start), 0.03, 1e-9);
  ASSERT_LT(nearest_cell_centre(grid, body, start), half_diagonal);
  HybridAStar planner(grid, o);
  const PlanResult r = planner.plan(start, goal);
  ASSERT_TRUE(r.found()) << plan_status_reason(r.status);
  const double start_distance = nearest_cell_centre(grid, body, start);
  const double half_step = 0.25 * res;  // the planner's samples are half a cell apart
  bool out_of_band = false;
  int band_poses = 0, reentries = 0, on_centre = 0, nearer = 0;
  const PathCheck c = check_path(grid, body, r.path_poses, r.path_reversing, [&](const Pose2& q) {
    const double d = nearest_cell_centre(grid, body, q);
    if (d <= 0.0) ++on_centre;
    if (d < start_distance - half_step - 1e-9) ++nearer;
    if (d > half_diagonal) out_of_band = true;
    else if (out_of_band) ++reentries;
    else ++band_poses;
  });
  EXPECT_GT(c.checks, 0);
  EXPECT_EQ(on_centre, 0);
  EXPECT_EQ(nearer, 0);
  EXPECT_EQ(reentries, 0);
  EXPECT_TRUE(out_of_band);
  EXPECT_GT(band_poses, 0);
  EXPECT_LE(c.max_curvature, 1.0 / o.minimum_turning_radius_m + 1e-6);
  // 1 cm nearer: the body holds the cell centres of the side.
  const Pose2 on_side(1.975 - 0.01 + 0.2, 0.6, kPi / 2);
  EXPECT_EQ(planner.plan(on_side, goal).status, PlanStatus::StartBlocked);
}

// A robot that turns on the spot (diff) turns round in a box where a forward-only car cannot.
TEST(HybridAStar, TheDiffModelTurnsOnTheSpot) {
  OccupancyGrid grid = empty_grid(40, 40, 0.05);
  block_rect(grid, 0.0, 0.0, 2.0, 0.55);
  block_rect(grid, 0.0, 1.45, 2.0, 2.0);
  block_rect(grid, 0.0, 0.0, 0.55, 2.0);
  block_rect(grid, 1.45, 0.0, 2.0, 2.0);
  HybridAStarOptions o;
  o.robot_radius_m = 0.25;
  o.motion_model = HybridMotionModel::Diff;
  o.rotation_penalty_m_per_rad = 0.1;  // cheaper than any manoeuvre of arcs
  o.max_iterations = 20000;
  const Pose2 start(1.0, 1.0, 0.0), goal(1.0, 1.0, kPi);
  HybridAStar diff(grid, o);
  const PlanResult r = diff.plan(start, goal);
  ASSERT_TRUE(r.found()) << plan_status_reason(r.status);
  EXPECT_NEAR(r.length, 0.0, 1e-9);
  EXPECT_NEAR(angle_diff(r.path_poses.back().yaw, kPi), 0.0, 1e-9);
  o.motion_model = HybridMotionModel::Dubins;
  HybridAStar car(grid, o);
  EXPECT_FALSE(car.plan(start, goal).found());
}

// An omnidirectional base slides sideways up a corridor too narrow to turn in; nothing else can.
TEST(HybridAStar, TheOmniModelSlidesSideways) {
  OccupancyGrid grid = empty_grid(40, 60, 0.05);
  block_rect(grid, 0.0, 0.0, 0.65, 3.0);  // the corridor: x in (0.65, 1.35), along y
  block_rect(grid, 1.35, 0.0, 2.0, 3.0);
  HybridAStarOptions o;
  o.footprint_length_m = 0.64;  // across the corridor: too long to turn round (diagonal 0.71 m)
  o.footprint_width_m = 0.3;
  o.motion_model = HybridMotionModel::Omni;
  o.max_iterations = 20000;
  const Pose2 start(1.0, 0.6, 0.0), goal(1.0, 2.37, 0.0);
  HybridAStar omni(grid, o);
  const PlanResult r = omni.plan(start, goal);
  ASSERT_TRUE(r.found()) << plan_status_reason(r.status);
  EXPECT_NEAR(r.length, 1.77, 1e-9);
  for (const Pose2& p : r.path_poses) {
    EXPECT_NEAR(p.x, 1.0, 1e-9);
    EXPECT_NEAR(p.yaw, 0.0, 1e-9);
    EXPECT_FALSE(body_collides(grid, body_of(o), p));
  }
  for (const HybridMotionModel m : {HybridMotionModel::Diff, HybridMotionModel::ReedsShepp}) {
    o.motion_model = m;
    HybridAStar other(grid, o);
    EXPECT_FALSE(other.plan(start, goal).found()) << hybrid_motion_model_name(m);
  }
}

// ---- statuses, parameters, determinism, the role ---------------------------------------------------

TEST(HybridAStar, StatusesOfImpossibleQueries) {
  OccupancyGrid grid = empty_grid(50, 50, 0.1);
  block_rect(grid, 2.0, 2.0, 3.0, 3.0);
  HybridAStar p(grid, HybridAStarOptions{});
  EXPECT_EQ(p.plan(Pose2(-1, 1, 0), Pose2(4, 4, 0)).status, PlanStatus::StartOutsideMap);
  EXPECT_EQ(p.plan(Pose2(1, 1, 0), Pose2(6, 4, 0)).status, PlanStatus::GoalOutsideMap);
  EXPECT_EQ(p.plan(Pose2(2.5, 2.5, 0), Pose2(4, 4, 0)).status, PlanStatus::StartBlocked);
  EXPECT_EQ(p.plan(Pose2(1, 1, 0), Pose2(2.5, 2.2, 0)).status, PlanStatus::GoalBlocked);
  EXPECT_EQ(p.plan(Pose2(1, 1, 0), Pose2(4, 4, 0), SearchLimits{1, 0.0, nullptr}).status == PlanStatus::Found ||
                p.plan(Pose2(1, 1, 0), Pose2(4, 4, 0), SearchLimits{1, 0.0, nullptr}).status == PlanStatus::ExpansionLimit,
            true);
  // Walled in: the 2D bound already says no.
  OccupancyGrid walled = empty_grid(50, 50, 0.1);
  block_rect(walled, 0.0, 2.4, 5.0, 2.6);
  HybridAStar w(walled, HybridAStarOptions{});
  const PlanResult r = w.plan(Pose2(1, 1, 0), Pose2(4, 4, 0));
  EXPECT_EQ(r.status, PlanStatus::NoPath);
  EXPECT_EQ(r.expanded, 0u);
}

TEST(HybridAStar, BadParametersGiveOneErrorNamingTheField) {
  const GlobalPlannerDef& def = find_global_planner("hybrid_astar");
  EXPECT_TRUE(def.info.has(Capability::NeedsHeadings));
  const auto error_for = [&](const std::string& key, const std::string& value) {
    const std::vector<ParamSetting> s = {{key, value, "nav.yaml", 7, "navigation.hybrid_astar." + key}};
    return test::error_of([&] { def.make({}, s); });
  };
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"angle_bins", "2"},
           {"minimum_turning_radius_m", "0"},
           {"reverse_penalty", "0.5"},
           {"non_straight_penalty", "0.9"},
           {"motion_model", "tank"},
           {"cost_penalty", "-1"},
           {"analytic_expansion_ratio", "nan"}}) {
    const std::string what = error_for(key, value);
    EXPECT_NE(what.find("nav.yaml:7"), std::string::npos) << what;
    EXPECT_NE(what.find("navigation.hybrid_astar." + key), std::string::npos) << what;
  }
  // A rectangle needs both sides: the missing one is named.
  const std::string what = error_for("footprint_length_m", "1.8");
  EXPECT_NE(what.find("footprint_width_m"), std::string::npos) << what;
}

TEST(HybridAStar, TheSameQueryGivesTheSameBytes) {
  Rng rng(11);
  const Pose2 start(1.5, 4.0, 0.3), goal(8.5, 2.0, -2.0);
  const OccupancyGrid grid = random_map(rng, start, goal);
  const HybridAStarOptions o = car_options(HybridMotionModel::ReedsShepp);
  HybridAStar a(grid, o), b(grid, o);
  const PlanResult ra = a.plan(start, goal), rb = b.plan(start, goal), rc = a.plan(start, goal);
  ASSERT_TRUE(ra.found());
  for (const PlanResult* x : {&rb, &rc}) {
    ASSERT_EQ(ra.path_poses.size(), x->path_poses.size());
    for (std::size_t i = 0; i < ra.path_poses.size(); ++i) {
      EXPECT_EQ(ra.path_poses[i].x, x->path_poses[i].x);
      EXPECT_EQ(ra.path_poses[i].y, x->path_poses[i].y);
      EXPECT_EQ(ra.path_poses[i].yaw, x->path_poses[i].yaw);
    }
    EXPECT_EQ(ra.path_reversing, x->path_reversing);
    EXPECT_EQ(ra.cost, x->cost);
    EXPECT_EQ(ra.expanded, x->expanded);
  }
}

// Smoothing only ever lowers the cost and keeps every check.
TEST(HybridAStar, SmoothingNeverRaisesTheCost) {
  Rng rng(99);
  for (int q = 0; q < 4; ++q) {
    const Pose2 start(1.5, rng.uniform(1.0, 7.0), rng.uniform(-kPi, kPi));
    const Pose2 goal(8.5, rng.uniform(1.0, 7.0), rng.uniform(-kPi, kPi));
    const OccupancyGrid grid = random_map(rng, start, goal);
    HybridAStarOptions o = car_options(HybridMotionModel::ReedsShepp);
    o.analytic_expansion_max_length_m = 3.0;  // long searches: something to smooth
    o.smooth = false;
    HybridAStar raw(grid, o);
    const PlanResult a = raw.plan(start, goal);
    o.smooth = true;
    HybridAStar smoothed(grid, o);
    const PlanResult b = smoothed.plan(start, goal);
    ASSERT_EQ(a.found(), b.found());
    if (!a.found()) continue;
    EXPECT_LE(b.cost, a.cost + 1e-9);
    const PathCheck c = check_path(grid, body_of(o), b.path_poses, b.path_reversing);
    EXPECT_EQ(c.collisions, 0);
    EXPECT_LE(c.max_curvature, 1.0 + 1e-6);
  }
}

TEST(HybridAStar, TheRoleGivesPosesAndGridPlannersIgnoreThem) {
  OccupancyGrid grid = empty_grid(80, 60, 0.1);
  block_rect(grid, 3.5, 0.0, 4.5, 3.5);
  const GlobalPlannerDef& hybrid = find_global_planner("hybrid_astar");
  std::vector<ParamSetting> s = {{"minimum_turning_radius_m", "1.0", "", 0, ""}};
  GlobalPlannerContext ctx;
  const auto planner = hybrid.make(ctx, s);
  PlanQuery q;
  q.start = {10, 10};
  q.goal = {70, 10};
  q.start_pose = Pose2(1.05, 1.05, kPi / 2);
  q.goal_pose = Pose2(7.05, 1.05, -kPi / 2);
  const PlanningLayers layers{&grid, nullptr};
  const PlanResult r = planner->plan_poses(layers, q, {});
  ASSERT_TRUE(r.found());
  EXPECT_EQ(r.path_poses.size(), r.path_world.size());
  EXPECT_EQ(r.path_cells.front().x, 10);
  EXPECT_EQ(r.path_cells.back().x, 70);
  EXPECT_THROW(planner->plan(layers, q.start, q.goal, {}), Error);
  q.goal_heading = false;
  EXPECT_NE(test::error_of([&] { planner->plan_poses(layers, q, {}); }).find("goal.yaw_deg"), std::string::npos);
  // A grid planner plans between the cells, whatever the poses.
  const auto astar = find_global_planner("astar").make(ctx, {});
  const PlanResult a = astar->plan_poses(layers, q, {}), b = astar->plan(layers, q.start, q.goal, {});
  EXPECT_EQ(a.path_cells.size(), b.path_cells.size());
  EXPECT_EQ(a.cost, b.cost);
  EXPECT_TRUE(a.path_poses.empty());
}

// The role keeps its planner while the map is unchanged, and answers for the new map once it
// changes: the same query in the same role object equals a fresh planner's answer on each map.
TEST(HybridAStar, TheRolePlansOnTheMapItIsGivenEachTime) {
  OccupancyGrid open_map = empty_grid(80, 60, 0.1);
  OccupancyGrid walled = open_map;
  block_rect(walled, 3.5, 0.0, 4.5, 4.0);
  const std::vector<ParamSetting> settings = {{"minimum_turning_radius_m", "1.0", "", 0, ""}};
  const auto role = find_global_planner("hybrid_astar").make(GlobalPlannerContext{}, settings);
  HybridAStarOptions o;
  o.minimum_turning_radius_m = 1.0;
  PlanQuery q;
  q.start_pose = Pose2(1.05, 1.05, 0.0);
  q.goal_pose = Pose2(7.05, 1.05, 0.0);
  q.start = {10, 10};
  q.goal = {70, 10};
  for (const OccupancyGrid* map : {&open_map, &walled, &walled, &open_map}) {
    const PlanResult got = role->plan_poses(PlanningLayers{map, nullptr}, q, {});
    HybridAStar fresh(*map, o);
    const PlanResult want = fresh.plan(q.start_pose, q.goal_pose);
    ASSERT_TRUE(got.found());
    EXPECT_EQ(got.length, want.length);
    EXPECT_EQ(got.path_poses.size(), want.path_poses.size());
  }
  EXPECT_GT(HybridAStar(walled, o).plan(q.start_pose, q.goal_pose).length, 6.5);  // round the wall
}

// Navigation with a planner between poses needs the goal's heading: refused before the run, naming
// the scenario's line and key.
TEST(HybridAStar, NavigationRefusesAGoalWithoutHeading) {
  test::ScratchDir dir;
  const auto r = test::run_cli({"sim", test::scenario_path("e3_three_obstacles.yaml"), "--planner", "hybrid_astar", "--out",
                                dir.file("run")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("e3_three_obstacles.yaml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("navigation.goal.yaw_deg"), std::string::npos) << r.err;
}

TEST(HybridAStar, SamplesKeepEveryMotionsEnds) {
  std::vector<HybridMotion> ms(2);
  ms[0].start = Pose2(0, 0, 0);
  ms[0].curvature = 0.5;
  ms[0].length = 1.05;
  ms[1].start = ms[0].end();
  ms[1].length = -0.3;
  std::vector<Pose2> poses;
  std::vector<std::uint8_t> rev;
  sample_hybrid_motions(ms, 0.25, poses, rev);
  ASSERT_EQ(poses.size(), 1u + 5u + 2u);  // start, 4 inside + end of the arc, 1 inside + end
  EXPECT_NEAR(poses[5].x, ms[0].end().x, 1e-12);
  EXPECT_EQ(rev, (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 1, 1, 1}));
  EXPECT_NEAR(std::hypot(poses[6].x - poses[5].x, poses[6].y - poses[5].y), 0.25, 1e-12);
  EXPECT_THROW(sample_hybrid_motions(ms, 0.0, poses, rev), Error);
}

}  // namespace
}  // namespace starnav
