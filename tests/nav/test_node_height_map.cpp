// NodeHeightMap: mapping from LiDAR scans (spec li2019 sections 5-7, docs/navigation.md).
// Truths used: a brute-force reference of the hit-only pipeline (min/max per cell, Li criteria by
// their definition, expansion by checking every pair of cells), the boxes' footprints and
// closed-form ray/box intersections, a from-scratch rebuild, and Bellman-Ford for escape cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/costmap/node_height_map.hpp"
#include "starnav/plan/dstar_lite.hpp"
#include "starnav/plan/grid_planner.hpp"
#include "starnav/sense/lidar.hpp"
#include "starnav/sim/world.hpp"

namespace starnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

GridGeometry grid(int w, int h, double res, double x0, double y0) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = Pose2(x0, y0, 0.0);
  return g;
}

ElevationMap flat_terrain(double size, double res, double x0, double y0) {
  const int n = static_cast<int>(std::lround(size / res));
  ElevationMap m(grid(n, n, res, x0, y0));
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) m.set_height(ix, iy, 0.0);
  return m;
}

Obstacle box_obstacle(const std::string& name, const Vec3& lo, const Vec3& hi) {
  Obstacle o;
  o.name = name;
  o.parts = {Box{0.5 * (lo + hi), hi - lo}};
  return o;
}

// Brute-force reference of the hit-only pipeline: every return's cell takes min / max; Li
// criteria from their definition; expansion by distance between centres.
struct Reference {
  GridGeometry g;
  std::vector<int> hits;
  std::vector<double> lo, hi;
  explicit Reference(const GridGeometry& geometry)
      : g(geometry), hits(g.cell_count(), 0), lo(g.cell_count(), kInf), hi(g.cell_count(), -kInf) {}
  void add(std::span<const Vec3> points, bool planar) {
    for (const Vec3& p : points) {
      const Vec2 c = g.world_to_cell_continuous(p.head<2>());
      const int x = static_cast<int>(std::floor(c.x())), y = static_cast<int>(std::floor(c.y()));
      if (x < 0 || y < 0 || x >= g.width || y >= g.height) continue;
      const std::size_t i = g.index(x, y);
      ++hits[i];
      const double z = planar ? 0.0 : p.z();
      lo[i] = std::min(lo[i], z);
      hi[i] = std::max(hi[i], z);
    }
  }
  std::vector<std::uint8_t> raw(const LiNodeParams& li, bool planar) const {
    std::vector<std::uint8_t> out(g.cell_count(), 0);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        const std::size_t i = g.index(x, y);
        if (!hits[i]) continue;
        if (planar) {
          out[i] = 1;
          continue;
        }
        bool b = hi[i] - lo[i] > li.max_step_m;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if ((dx == 0 && dy == 0) || !g.contains(x + dx, y + dy)) continue;
            const std::size_t j = g.index(x + dx, y + dy);
            if (!hits[j]) continue;
            const double l = g.resolution * std::hypot(dx, dy);
            if (std::abs(0.5 * (lo[i] + hi[i]) - 0.5 * (lo[j] + hi[j])) > std::tan(li.max_slope_rad) * l) b = true;
          }
        out[i] = b ? 1 : 0;
      }
    return out;
  }
};

std::vector<std::uint8_t> brute_expand(const GridGeometry& g, const std::vector<std::uint8_t>& raw, double radius_m) {
  std::vector<std::uint8_t> out(raw.size(), 0);
  const double r2 = radius_m * radius_m * (1 + 1e-9) + 1e-12 * g.resolution * g.resolution;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      for (int v = 0; v < g.height && !out[g.index(x, y)]; ++v)
        for (int u = 0; u < g.width; ++u)
          if (raw[g.index(u, v)]) {
            const double dx = (u - x) * g.resolution, dy = (v - y) * g.resolution;
            if (dx * dx + dy * dy <= r2) {
              out[g.index(x, y)] = 1;
              break;
            }
          }
  return out;
}

std::vector<std::uint8_t> as_mask(const std::vector<std::uint8_t>& v) {
  std::vector<std::uint8_t> m(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) m[i] = v[i] ? 1 : 0;
  return m;
}

// The cells where two masks differ, "" when none (readable failures).
std::string mask_diff(const GridGeometry& g, const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::ostringstream out;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = g.index(x, y);
      if ((a[i] != 0) != (b[i] != 0)) out << '(' << x << ',' << y << ':' << int(a[i]) << ") ";
    }
  return out.str();
}

void expect_same_derived(const NodeHeightMap& a, const NodeHeightMap& b) {
  EXPECT_EQ(as_mask(a.raw_blocked()), as_mask(b.raw_blocked()));
  EXPECT_EQ(a.blocked(), b.blocked());
  EXPECT_TRUE(a.occupancy() == b.occupancy());
}

// --- Hand-built heights: the Li criteria block exactly the cells they define.
TEST(NodeHeightMap, LiCriteriaOnHandBuiltHeights) {
  NodeMapParams p;
  p.barrier_distance_m = 0.0;
  p.li.max_step_m = 0.05;
  p.li.max_slope_rad = deg_to_rad(15.0);  // tan = 0.268: 0.0268 m straight, 0.0379 m diagonal at 0.1 m
  NodeHeightMap m(grid(10, 10, 0.1, 0.0, 0.0), p);
  const Vec3 origin(0.55, 0.55, 5.0);  // far above: beams pass above every hit
  std::vector<Vec3> pts;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) pts.push_back(Vec3(x * 0.1 + 0.05, y * 0.1 + 0.05, 0.0));
  pts.push_back(Vec3(0.25, 0.25, 0.06));  // cell (2, 2): spread 0.06 > 0.05, mid 0.03
  pts.push_back(Vec3(0.72, 0.72, 0.04));  // cell (7, 7): spread 0.04 (passes), mid 0.02 (passes)
  pts.push_back(Vec3(0.78, 0.38, 0.09));  // cell (7, 3): spread 0.09, mid 0.045 > diagonal limit
  m.integrate(origin, pts);
  std::vector<Cell> blocked;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      if (m.raw_blocked(x, y)) blocked.push_back({x, y});
  // (2, 2) by spread, its 4 straight neighbours by 0.03 > 0.0268 (diagonals: 0.03 < 0.0379);
  // (7, 3) by spread and all 8 neighbours by 0.045 > 0.0379.
  std::vector<Cell> want = {{2, 1}, {6, 2}, {7, 2}, {8, 2}, {1, 2}, {2, 2}, {3, 2}, {6, 3}, {7, 3},
                            {8, 3}, {2, 3}, {6, 4}, {7, 4}, {8, 4}};
  auto key = [](const Cell& c) { return c.y * 100 + c.x; };
  std::sort(want.begin(), want.end(), [&](const Cell& a, const Cell& b) { return key(a) < key(b); });
  EXPECT_EQ(blocked, want);
  EXPECT_DOUBLE_EQ(m.elevation().min_height_at(2, 2), 0.0);
  EXPECT_DOUBLE_EQ(m.elevation().max_height_at(2, 2), 0.06);

  // Random heights on a larger grid: equal to the definition, expansion to brute force.
  Rng rng(7);
  NodeMapParams q;
  q.barrier_distance_m = 0.25;
  q.clear = false;
  GridGeometry g = grid(23, 17, 0.1, -1.0, 2.0);
  g.origin.yaw = 0.3;  // a rotated grid: cells are found through the geometry
  NodeHeightMap r(g, q);
  Reference ref(g);
  for (int scan = 0; scan < 4; ++scan) {
    std::vector<Vec3> ps;
    for (int k = 0; k < 200; ++k)
      ps.push_back(Vec3(rng.uniform(-1.2, 1.5), rng.uniform(1.8, 3.9), rng.uniform(0.0, 0.12)));
    r.integrate(Vec3(0, 3, 1), ps);
    ref.add(ps, false);
    const std::vector<std::uint8_t> raw = ref.raw(q.li, false);
    ASSERT_EQ(as_mask(r.raw_blocked()), raw) << scan;
    ASSERT_EQ(r.blocked(), brute_expand(g, raw, q.barrier_distance_m)) << scan;
  }
}

// --- The evidence and clearing rules on hand-placed beams (grid 20 x 5 at 0.1 m, row 2).
TEST(NodeHeightMap, ClearingRulesOnHandPlacedBeams) {
  NodeMapParams p;
  p.barrier_distance_m = 0.0;
  const GridGeometry g = grid(20, 5, 0.1, 0.0, 0.0);
  {
    // A cell holding ground (0) and an obstacle (0.5) hits; then a beam passes through it at
    // 0.2 m and the ground is hit again: the stale 0.5 is dropped at once.
    NodeHeightMap m(g, p);
    m.integrate(Vec3(0.05, 0.25, 1.0), std::vector<Vec3>{Vec3(1.05, 0.25, 0.0), Vec3(1.05, 0.25, 0.5)});
    EXPECT_EQ(m.evidence(10, 2), 2);
    EXPECT_TRUE(m.raw_blocked(10, 2));
    const CostmapUpdate u = m.integrate(Vec3(0.05, 0.25, 0.2), std::vector<Vec3>{Vec3(1.55, 0.25, 0.2), Vec3(1.02, 0.27, 0.0)});
    EXPECT_EQ(u.cells_contradicted, 1u);
    EXPECT_EQ(m.evidence(10, 2), 3);  // 2 + hit_gain - miss_loss
    EXPECT_DOUBLE_EQ(m.elevation().max_height_at(10, 2), 0.0);
    EXPECT_FALSE(m.raw_blocked(10, 2));
    // A beam 0.03 m above the ground there contradicts nothing (clear_margin_m = 0.05).
    EXPECT_EQ(m.integrate(Vec3(0.05, 0.25, 0.03), std::vector<Vec3>{Vec3(1.55, 0.25, 0.03)}).cells_contradicted, 0u);
    EXPECT_EQ(m.evidence(10, 2), 3);
  }
  {
    // Without new hits a contradicted cell loses miss_loss per scan and is forgotten at 0.
    NodeHeightMap m(g, p);
    m.integrate(Vec3(0.05, 0.25, 1.0), std::vector<Vec3>{Vec3(1.05, 0.25, 0.5)});
    for (int k = 1; k >= 0; --k) {
      const CostmapUpdate u = m.integrate(Vec3(0.05, 0.25, 0.2), std::vector<Vec3>{Vec3(1.55, 0.25, 0.2)});
      EXPECT_EQ(m.evidence(10, 2), k);
      EXPECT_EQ(u.cells_cleared, k == 0 ? 1u : 0u);
    }
    EXPECT_FALSE(m.observed(10, 2));
    EXPECT_EQ(m.occupancy()(10, 2), kUnknownOccupancy);
  }
  {
    // A descending beam is judged by its highest point in the cell: from (0.05, z 1.0) to
    // (1.95, z 0) it crosses cell 10 between z 0.5 and 0.447; a hit at 0.52 is not 0.05 m above
    // 0.5, so it stands; a hit at 0.56 is, so it is contradicted.
    for (const double stored : {0.52, 0.56}) {
      NodeHeightMap m(g, p);
      m.integrate(Vec3(0.05, 0.25, 2.0), std::vector<Vec3>{Vec3(1.05, 0.25, stored)});
      const CostmapUpdate u = m.integrate(Vec3(0.05, 0.25, 1.0), std::vector<Vec3>{Vec3(1.95, 0.25, 0.0)});
      EXPECT_EQ(u.cells_contradicted, stored > 0.55 ? 1u : 0u) << stored;
    }
  }
}

// --- A known scene: flat ground and two boxes taller than the sensor, one VLP-16 scan.
struct Scene {
  GridGeometry g = grid(80, 80, 0.1, -4.0, -4.0);
  // Faces through cell centres, so face cells hold ground in front of the face and the face.
  std::vector<std::pair<Vec3, Vec3>> boxes = {{Vec3(1.05, -0.35, 0.0), Vec3(1.45, 0.45, 1.0)},
                                              {Vec3(-2.05, 1.55, 0.0), Vec3(-1.55, 2.25, 1.0)}};
  World world() const {
    WorldDescription d;
    d.terrain = flat_terrain(10.0, 0.1, -5.0, -5.0);
    for (std::size_t k = 0; k < boxes.size(); ++k)
      d.obstacles.push_back(box_obstacle(std::string(1, static_cast<char>('a' + k)), boxes[k].first, boxes[k].second));
    return World(d);
  }
  bool in_footprint(int x, int y) const {  // the cell's interior meets a box footprint
    const double cx0 = g.origin.x + x * g.resolution, cy0 = g.origin.y + y * g.resolution;
    for (const auto& [lo, hi] : boxes)
      if (cx0 < hi.x() && cx0 + g.resolution > lo.x() && cy0 < hi.y() && cy0 + g.resolution > lo.y()) return true;
    return false;
  }
};

LidarConfig vlp16_at(double height) {
  LidarConfig c = lidar_preset("vlp16", deg_to_rad(1.0));
  c.range_max = 30.0;
  c.mount = Pose3::from_rpy(Vec3(0, 0, height), 0, 0, 0);
  return c;
}

TEST(NodeHeightMap, KnownSceneGivesExactlyTheExpectedBlockedCells) {
  const Scene s;
  const World w = s.world();
  Lidar lidar(vlp16_at(0.6));
  NodeMapParams p;
  p.barrier_distance_m = 0.3;
  for (const Vec3& robot : {Vec3(0.03, 0.02, 0.0), Vec3(-0.61, 0.47, 0.0)}) {
    const LidarScan scan = lidar.scan(w, Pose3::from_rpy(robot, 0, 0, 0.2), 0.0);
    NodeHeightMap m(s.g, p);
    const CostmapUpdate u = m.integrate(scan);
    EXPECT_GT(u.cells_hit, 500u);
    EXPECT_EQ(u.cells_contradicted, 0u);  // nothing stored before the first scan

    // Returns above the step height lie on the boxes.
    std::vector<std::uint8_t> tall(s.g.cell_count(), 0), seen(s.g.cell_count(), 0);
    for (const Vec3& q : scan.points_world) {
      const std::optional<Cell> c = s.g.world_to_cell(q.head<2>());
      if (!c) continue;
      seen[s.g.index(c->x, c->y)] = 1;
      if (q.z() > p.li.max_step_m) {
        ASSERT_TRUE(s.in_footprint(c->x, c->y)) << q.transpose();
        tall[s.g.index(c->x, c->y)] = 1;
      }
    }
    // Expected: cells with a box return, and every seen cell beside one (ground at 0 next to a
    // face; the boxes' tops are never seen, the sensor is below them).
    std::vector<std::uint8_t> want(s.g.cell_count(), 0);
    int tall_cells = 0;
    for (int y = 0; y < s.g.height; ++y)
      for (int x = 0; x < s.g.width; ++x) {
        const std::size_t i = s.g.index(x, y);
        if (!seen[i]) continue;
        tall_cells += tall[i];
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (s.g.contains(x + dx, y + dy) && tall[s.g.index(x + dx, y + dy)]) want[i] = 1;
      }
    EXPECT_GT(tall_cells, 10);
    EXPECT_EQ(mask_diff(s.g, m.raw_blocked(), want), "");
    // And the same through the brute-force pipeline.
    Reference ref(s.g);
    ref.add(scan.points_world, false);
    EXPECT_EQ(ref.raw(p.li, false), want);
    EXPECT_EQ(m.blocked(), brute_expand(s.g, want, p.barrier_distance_m));
    // Occupancy: 100 blocked, 0 seen and free, -1 never seen.
    for (std::size_t i = 0; i < s.g.cell_count(); ++i) {
      const std::int8_t v = m.blocked()[i] ? 100 : (seen[i] ? 0 : -1);
      ASSERT_EQ(m.occupancy()[i], v) << i;
    }
  }
}

TEST(NodeHeightMap, OccupancyFeedsTheGridPlanners) {
  // Plan past box A on the mapped scene with unknown cells free: the path avoids the band, and
  // D* Lite repairs it with the reported changes after a second scan from elsewhere.
  const Scene s;
  const World w = s.world();
  Lidar lidar(vlp16_at(0.6));
  NodeHeightMap m(s.g);
  m.integrate(lidar.scan(w, Pose3::from_rpy(Vec3(0.03, 0.02, 0), 0, 0, 0), 0.0));
  GridPlannerOptions o;
  o.unknown_is_free = true;
  const Cell start = *s.g.world_to_cell(Vec2(0.03, 0.02)), goal = *s.g.world_to_cell(Vec2(2.5, 0.05));
  DStarLite d(m.occupancy(), o);
  PlanResult r = d.plan(start, goal);
  ASSERT_TRUE(r.found());
  for (const Cell& c : r.path_cells) ASSERT_FALSE(m.blocked(c.x, c.y));
  const CostmapUpdate u = m.integrate(lidar.scan(w, Pose3::from_rpy(Vec3(2.9, -1.2, 0), 0, 0, 2.0), 0.0));
  ASSERT_FALSE(u.occupancy_changed.empty());
  std::vector<CellChange> changes;
  for (const Cell& c : u.occupancy_changed) changes.push_back({c, m.occupancy()(c.x, c.y)});
  d.update_cells(changes);
  r = d.replan();
  ASSERT_TRUE(r.found());
  for (const Cell& c : r.path_cells) ASSERT_FALSE(m.blocked(c.x, c.y));
  // The repaired cost equals a fresh search on the new map.
  const PlanResult fresh = make_grid_planner("astar", m.occupancy(), o)->plan(start, goal);
  ASSERT_TRUE(fresh.found());
  EXPECT_NEAR(r.cost, fresh.cost, 1e-9);
}

TEST(NodeHeightMap, FlatGroundIsNeverContradicted) {
  // Beams over low ground must not clear the ground: repeated scans of a flat floor from moving
  // poses contradict nothing and leave every seen cell observed and free.
  WorldDescription d;
  d.terrain = flat_terrain(10.0, 0.1, -5.0, -5.0);
  const World w(d);
  Lidar lidar(vlp16_at(0.6));
  NodeHeightMap m(grid(80, 80, 0.1, -4.0, -4.0));
  for (int k = 0; k < 6; ++k) {
    const CostmapUpdate u = m.integrate(lidar.scan(w, Pose3::from_rpy(Vec3(0.2 * k, 0.1 * k, 0), 0, 0, 0.3 * k), 0));
    EXPECT_EQ(u.cells_contradicted, 0u) << k;
    EXPECT_EQ(u.cells_cleared, 0u) << k;
  }
  for (std::size_t i = 0; i < m.blocked().size(); ++i) ASSERT_EQ(m.blocked()[i], 0) << i;
}

TEST(NodeHeightMap, MovingBoxLeavesNoTrail) {
  WorldDescription d;
  d.terrain = flat_terrain(10.0, 0.1, -5.0, -5.0);
  Obstacle o = box_obstacle("mover", Vec3(1.05, -0.25, 0), Vec3(1.35, 0.25, 0.5));
  o.waypoints = {{1.0, Vec3(1.2, 0.0, 0.25)}, {2.0, Vec3(1.2, 2.5, 0.25)}};  // leaves to the side
  o.anchor = Vec3(1.2, 0.0, 0.25);
  d.obstacles = {o};
  const World w(d);
  Lidar lidar(vlp16_at(0.6));
  const Pose3 robot = Pose3::from_rpy(Vec3(0.03, 0.02, 0), 0, 0, 0);
  NodeMapParams p;
  const GridGeometry g = grid(80, 80, 0.1, -4.0, -4.0);
  NodeHeightMap m(g, p);
  for (int k = 0; k < 3; ++k) m.integrate(lidar.scan(w, robot, 0.1 * k));  // box at its start
  auto blocked_near_start = [&](const NodeHeightMap& map) {
    int n = 0;
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        const Vec2 c = g.cell_center(x, y);
        if (c.x() > 0.85 && c.x() < 1.55 && c.y() > -0.45 && c.y() < 0.45) n += map.raw_blocked(x, y);
      }
    return n;
  };
  ASSERT_GT(blocked_near_start(m), 5);
  // The box is gone (t >= 2 s): after evidence_max / miss_loss scans the beams that now reach
  // the ground where it stood have cleared every stale cell there.
  NodeHeightMap fresh(g, p);
  const int scans = p.evidence_max / p.miss_loss;
  std::size_t cleared = 0;
  for (int k = 0; k < scans; ++k) {
    const LidarScan scan = lidar.scan(w, robot, 3.0 + 0.1 * k);
    cleared += m.integrate(scan).cells_cleared;
    fresh.integrate(scan);
  }
  EXPECT_GT(cleared, 0u);
  EXPECT_EQ(blocked_near_start(m), 0);
  EXPECT_EQ(blocked_near_start(fresh), 0);
  // Where the box stood the map now equals one built from the new scans alone.
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const Vec2 c = g.cell_center(x, y);
      if (c.x() > 0.85 && c.x() < 1.55 && c.y() > -0.45 && c.y() < 0.45) {
        EXPECT_EQ(m.blocked(x, y), fresh.blocked(x, y)) << x << "," << y;
      }
    }
}

// Closed-form first hit of a horizontal ray with axis-aligned boxes (slab method).
std::optional<Vec2> ray_box_hit(const Vec2& o, const Vec2& dir, const std::vector<std::pair<Vec2, Vec2>>& boxes,
                                double range) {
  double best = range;
  for (const auto& [lo, hi] : boxes) {
    double t0 = 0.0, t1 = best;
    bool ok = true;
    for (int a = 0; a < 2 && ok; ++a) {
      if (dir[a] == 0.0) {
        ok = o[a] >= lo[a] && o[a] <= hi[a];
        continue;
      }
      double ta = (lo[a] - o[a]) / dir[a], tb = (hi[a] - o[a]) / dir[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      ok = t0 <= t1;
    }
    if (ok) best = t0;
  }
  if (best >= range) return std::nullopt;
  return o + best * dir;
}

TEST(NodeHeightMap, Lidar2DMarksReturnsAndClears) {
  // Two boxes inside a closed room (every beam returns: beams without a return clear nothing).
  std::vector<std::pair<Vec2, Vec2>> boxes = {{Vec2(1.03, -0.72), Vec2(1.61, 0.33)}, {Vec2(-2.17, 1.13), Vec2(-0.93, 1.42)},
                                              {Vec2(-2.85, -1.85), Vec2(-2.75, 2.85)}, {Vec2(2.75, -1.85), Vec2(2.85, 2.85)},
                                              {Vec2(-2.85, -1.85), Vec2(2.85, -1.75)}, {Vec2(-2.85, 2.75), Vec2(2.85, 2.85)}};
  auto make_world = [&](const std::vector<std::pair<Vec2, Vec2>>& bs) {
    WorldDescription d;
    for (std::size_t k = 0; k < bs.size(); ++k)
      d.obstacles.push_back(box_obstacle(std::string(1, static_cast<char>('a' + k)), Vec3(bs[k].first.x(), bs[k].first.y(), 0),
                                         Vec3(bs[k].second.x(), bs[k].second.y(), 1.0)));
    return World(d);
  };
  LidarConfig c = lidar_preset("generic_360");
  c.mount = Pose3::from_rpy(Vec3(0, 0, 0.3), 0, 0, 0);
  Lidar lidar(c);
  const Vec3 robot(0.013, 0.021, 0.0);
  const double yaw = 0.1;
  NodeMapParams p;
  p.mode = NodeMapMode::Lidar2D;
  p.barrier_distance_m = 0.2;
  const GridGeometry g = grid(60, 50, 0.1, -3.0, -2.0);
  NodeHeightMap m(g, p);
  const World w1 = make_world(boxes);
  m.integrate(lidar.scan(w1, Pose3::from_rpy(robot, 0, 0, yaw), 0));
  // Expected occupied cells: the closed-form hit of every beam.
  auto expected = [&](const std::vector<std::pair<Vec2, Vec2>>& bs) {
    std::vector<std::uint8_t> want(g.cell_count(), 0);
    for (int i = 0; i < c.beams; ++i) {
      const double a = c.azimuth(i) + yaw;
      const std::optional<Vec2> h = ray_box_hit(robot.head<2>(), Vec2(std::cos(a), std::sin(a)), bs, c.range_max);
      if (!h) continue;
      if (const std::optional<Cell> cell = g.world_to_cell(*h)) want[g.index(cell->x, cell->y)] = 1;
    }
    return want;
  };
  const std::vector<std::uint8_t> want = expected(boxes);
  EXPECT_GT(std::count(want.begin(), want.end(), 1), 100);
  EXPECT_EQ(mask_diff(g, m.raw_blocked(), want), "");
  EXPECT_EQ(mask_diff(g, m.blocked(), brute_expand(g, want, p.barrier_distance_m)), "");
  // The first box moves 1.5 m away: its old cells are cleared by the beams that now pass.
  std::vector<std::pair<Vec2, Vec2>> moved = boxes;
  moved[0].first.x() += 1.0, moved[0].second.x() += 1.0;
  const World w2 = make_world(moved);
  for (int k = 0; k < p.evidence_max / p.miss_loss; ++k) m.integrate(lidar.scan(w2, Pose3::from_rpy(robot, 0, 0, yaw), 0));
  EXPECT_EQ(mask_diff(g, m.raw_blocked(), expected(moved)), "");

  // Without the room, beams past the moved box return nothing: they clear only when told that a
  // missing return is open space (no_return_clear_m).
  const std::vector<std::pair<Vec2, Vec2>> open_before(boxes.begin(), boxes.begin() + 2);
  const std::vector<std::pair<Vec2, Vec2>> open_after(moved.begin(), moved.begin() + 2);
  const World o1 = make_world(open_before), o2 = make_world(open_after);
  for (const double clear_m : {0.0, c.range_max}) {
    NodeHeightMap n(g, p);
    n.integrate(lidar.scan(o1, Pose3::from_rpy(robot, 0, 0, yaw), 0), clear_m);
    EXPECT_EQ(mask_diff(g, n.raw_blocked(), expected(open_before)), "");
    for (int k = 0; k < p.evidence_max / p.miss_loss; ++k)
      n.integrate(lidar.scan(o2, Pose3::from_rpy(robot, 0, 0, yaw), 0), clear_m);
    if (clear_m > 0) {
      EXPECT_EQ(mask_diff(g, n.raw_blocked(), expected(open_after)), "");
    } else {
      EXPECT_NE(mask_diff(g, n.raw_blocked(), expected(open_after)), "");  // stale cells remain
    }
  }
  NodeHeightMap n(g, p);
  EXPECT_THROW(n.integrate(LidarScan{}, -1.0), Error);
}

// --- Incremental updates equal a from-scratch recomputation (random scans, clearing on).
TEST(NodeHeightMap, IncrementalEqualsRebuild) {
  for (const NodeMapMode mode : {NodeMapMode::Nodes3D, NodeMapMode::Lidar2D}) {
    Rng rng(mode == NodeMapMode::Nodes3D ? 11 : 12);
    NodeMapParams p;
    p.mode = mode;
    p.barrier_distance_m = 0.32;
    GridGeometry g = grid(130, 90, 0.1, -6.0, -4.0);  // several tiles
    if (mode == NodeMapMode::Nodes3D) g.origin.yaw = -0.4;
    NodeHeightMap m(g, p);
    NodeHeightMap ref(g, p);  // fed the same scans, then rebuilt from scratch after each
    OccupancyGrid before = m.occupancy();
    for (int scan = 0; scan < 25; ++scan) {
      const Vec3 origin(rng.uniform(-6.5, 7.5), rng.uniform(-4.5, 5.5), rng.uniform(0.3, 1.5));
      std::vector<Vec3> pts;
      const int n = rng.uniform_int(0, 400);
      for (int k = 0; k < n; ++k) {
        // Mostly ground, some obstacles; some points fall outside the grid.
        const double z = rng.uniform() < 0.8 ? rng.uniform(0.0, 0.03) : rng.uniform(0.0, 1.0);
        pts.push_back(Vec3(rng.uniform(-7.0, 8.0), rng.uniform(-5.0, 6.0), z));
      }
      const CostmapUpdate u = m.integrate(origin, pts);
      ref.integrate(origin, pts);
      ref.rebuild();
      expect_same_derived(m, ref);
      // The reported changes turn the previous occupancy into the new one.
      for (const Cell& c : u.occupancy_changed) {
        EXPECT_TRUE(c.x >= u.bounds.x0 && c.x < u.bounds.x1 && c.y >= u.bounds.y0 && c.y < u.bounds.y1);
        EXPECT_NE(before(c.x, c.y), m.occupancy()(c.x, c.y));
        before(c.x, c.y) = m.occupancy()(c.x, c.y);
      }
      ASSERT_TRUE(before == m.occupancy()) << scan;
    }
  }
}

// --- Escape cell: the cheapest way out of the band, against Bellman-Ford.
TEST(NodeHeightMap, EscapeCellIsTheCheapestWayOut) {
  Rng rng(5);
  NodeMapParams p;
  p.mode = NodeMapMode::Lidar2D;
  p.barrier_distance_m = 0.35;
  const GridGeometry g = grid(30, 24, 0.1, 0.0, 0.0);
  int checked = 0;
  for (int trial = 0; trial < 12; ++trial) {
    NodeHeightMap m(g, p);
    std::vector<Vec3> pts;
    for (int k = 0; k < 25; ++k) pts.push_back(Vec3(rng.uniform(0.0, 3.0), rng.uniform(0.0, 2.4), 0.0));
    m.integrate(Vec3(1.5, 1.2, 0.3), pts);
    const auto& raw = m.raw_blocked();
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        const std::size_t s = g.index(x, y);
        std::vector<Cell> path;
        const std::optional<Cell> e = m.escape_cell({x, y}, &path);
        if (raw[s]) {
          EXPECT_FALSE(e);
          continue;
        }
        if (!m.blocked()[s]) {
          ASSERT_TRUE(e);
          EXPECT_EQ(*e, (Cell{x, y}));
          continue;
        }
        // Bellman-Ford over cells that are not raw blocked, no corner cutting.
        std::vector<double> d(g.cell_count(), kInf);
        d[s] = 0;
        for (bool changed = true; changed;) {
          changed = false;
          for (int v = 0; v < g.height; ++v)
            for (int u = 0; u < g.width; ++u) {
              if (raw[g.index(u, v)] || d[g.index(u, v)] == kInf) continue;
              for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                  if ((dx == 0 && dy == 0) || !g.contains(u + dx, v + dy) || raw[g.index(u + dx, v + dy)]) continue;
                  if (dx != 0 && dy != 0 && (raw[g.index(u + dx, v)] || raw[g.index(u, v + dy)])) continue;
                  const double nd = d[g.index(u, v)] + std::hypot(dx, dy);
                  if (nd < d[g.index(u + dx, v + dy)] - 1e-12) {
                    d[g.index(u + dx, v + dy)] = nd;
                    changed = true;
                  }
                }
            }
        }
        double best = kInf;
        std::size_t best_i = 0;
        for (std::size_t i = 0; i < g.cell_count(); ++i)
          if (!m.blocked()[i] && d[i] < best - 1e-9) best = d[i], best_i = i;
        if (best == kInf) {
          EXPECT_FALSE(e);
          continue;
        }
        ASSERT_TRUE(e);
        const std::size_t ei = g.index(e->x, e->y);
        EXPECT_FALSE(m.blocked()[ei]);
        EXPECT_NEAR(d[ei], best, 1e-9);
        (void)best_i;
        // The path: starts at start, ends at the escape cell, valid moves, cost = best.
        ASSERT_FALSE(path.empty());
        EXPECT_EQ(path.front(), (Cell{x, y}));
        EXPECT_EQ(path.back(), *e);
        double cost = 0;
        for (std::size_t k = 1; k < path.size(); ++k) {
          const int dx = path[k].x - path[k - 1].x, dy = path[k].y - path[k - 1].y;
          ASSERT_LE(std::max(std::abs(dx), std::abs(dy)), 1);
          ASSERT_FALSE(raw[g.index(path[k].x, path[k].y)]);
          cost += std::hypot(dx, dy);
        }
        EXPECT_NEAR(cost, best, 1e-9);
        ++checked;
      }
  }
  EXPECT_GT(checked, 50);
  NodeHeightMap m(g, p);
  EXPECT_FALSE(m.escape_cell({-1, 3}));
}

TEST(NodeHeightMap, Deterministic) {
  const Scene s;
  const World w = s.world();
  LidarConfig c = vlp16_at(0.6);
  c.noise_sigma = 0.01;
  c.dropout = 0.05;
  auto run = [&] {
    Lidar lidar(c, Rng(99));
    NodeHeightMap m(s.g);
    for (int k = 0; k < 4; ++k) m.integrate(lidar.scan(w, Pose3::from_rpy(Vec3(0.1 * k, 0, 0), 0, 0, 0.1 * k), 0));
    return m;
  };
  const NodeHeightMap a = run(), b = run();
  EXPECT_TRUE(a.occupancy() == b.occupancy());
  EXPECT_TRUE(a.elevation() == b.elevation());
}

TEST(NodeHeightMap, BadParametersNameTheField) {
  auto field_of = [](const NodeMapParams& p) {
    try {
      NodeHeightMap m(grid(4, 4, 0.1, 0, 0), p);
    } catch (const Error& e) {
      return e.field();
    }
    return std::string();
  };
  NodeMapParams p;
  p.barrier_distance_m = -1;
  EXPECT_EQ(field_of(p), "barrier_distance_m");
  p = {};
  p.miss_loss = 3;
  EXPECT_EQ(field_of(p), "miss_loss");
  p = {};
  p.evidence_max = 1;
  EXPECT_EQ(field_of(p), "evidence_max");
  p = {};
  p.li.max_step_m = 0;
  EXPECT_EQ(field_of(p), "max_step_m");
  GridGeometry g = grid(4, 4, 0.1, 0, 0);
  g.y_down = true;
  EXPECT_THROW(NodeHeightMap(g, NodeMapParams{}), Error);
}

}  // namespace
}  // namespace starnav
