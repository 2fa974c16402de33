// The octree map against brute force: the occupied voxels of a scan and the free space along its
// rays, OctoMap's max-range rule, pruned leaves; the 2D grid of a synthetic room (walls with a
// door, a table whose top is above the band and legs in it, a low box, a pillar) from two
// simulated LiDAR scans; determinism of the tree, the grid and the .bt bytes; bad input.
#include <gtest/gtest.h>

#include <octomap/OcTree.h>  // only to read the written .bt back

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "starnav/cloud/octree_map.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using OctreeVoxel = std::array<long long, 3>;  // floor(p / resolution) per axis
using OctreeColumn = std::array<long long, 2>;

OctreeVoxel octree_voxel_of(const Vec3& p, double res) {
  return {static_cast<long long>(std::floor(p.x() / res)), static_cast<long long>(std::floor(p.y() / res)),
          static_cast<long long>(std::floor(p.z() / res))};
}

Vec3 octree_voxel_centre(const OctreeVoxel& v, double res) {
  return {(static_cast<double>(v[0]) + 0.5) * res, (static_cast<double>(v[1]) + 0.5) * res,
          (static_cast<double>(v[2]) + 0.5) * res};
}

// Within 1e-4 voxel of a face on some axis: OctoMap works in float and may put the point in either
// voxel, so the tests keep such points out.
bool octree_near_face(const Vec3& p, double res) {
  for (int a = 0; a < 3; ++a) {
    const double f = p[a] / res;
    if (std::abs(f - std::round(f)) < 1e-4) return true;
  }
  return false;
}

Rigid3 octree_pose(const Vec3& t, double yaw, double pitch, double roll) {
  Rigid3 pose = Rigid3::Identity();
  pose.linear() = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                   Eigen::AngleAxisd(roll, Vec3::UnitX()))
                      .toRotationMatrix();
  pose.translation() = t;
  return pose;
}

std::set<OctreeVoxel> octree_occupied_set(const OctreeMap& map) {
  std::set<OctreeVoxel> s;
  for (const Vec3& c : map.occupied_voxel_centres()) s.insert(octree_voxel_of(c, map.resolution()));
  return s;
}

// ---- A sphere of endpoints around the sensor ----------------------------------------------------

TEST(OctreeMap, SphereScanOccupiesExactlyTheEndpointVoxelsAndFreesTheRays) {
  const double res = 0.1;
  const Rigid3 pose = octree_pose({0.33, -0.21, 0.47}, 0.3, -0.15, 0.1);
  const Vec3 origin = pose.translation();
  for (const bool discretize : {false, true}) {
    SCOPED_TRACE(discretize ? "discretize" : "exact rays");
    OctreeMapConfig config;
    config.resolution_m = res;
    config.discretize = discretize;
    OctreeMap map(config);

    // A Fibonacci sphere: neighbouring directions 0.2 rad apart, so that at 2.5-3 m no ray comes
    // within 0.5 m of another endpoint (checked below).
    const int n = 300;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    Rng rng(11);
    PointCloud sensor_points, map_points;
    for (int i = 0; i < n; ++i) {
      const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
      const Vec3 dir(r * std::cos(golden * i), r * std::sin(golden * i), z);
      Vec3 p;
      do p = dir * rng.uniform(2.5, 3.0);
      while (octree_near_face(pose * p, res));
      sensor_points.push_back(p);
      map_points.push_back(pose * p);
    }
    std::map<OctreeVoxel, int> endpoint_of;
    for (int i = 0; i < n; ++i) endpoint_of[octree_voxel_of(map_points[static_cast<std::size_t>(i)], res)] = i;
    ASSERT_EQ(endpoint_of.size(), static_cast<std::size_t>(n));

    // Discretised insertion casts each ray to its endpoint voxel's centre.
    std::vector<std::vector<Vec3>> ray_samples(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const Vec3& p = map_points[static_cast<std::size_t>(i)];
      const OctreeVoxel end_voxel = octree_voxel_of(p, res);
      const Vec3 end = discretize ? octree_voxel_centre(end_voxel, res) : p;
      const int steps = static_cast<int>((end - origin).norm() / (res / 50.0));
      for (int s = 0; s <= steps; ++s) {
        const Vec3 q = origin + (end - origin) * (static_cast<double>(s) / steps);
        if (octree_near_face(q, res)) continue;
        const OctreeVoxel v = octree_voxel_of(q, res);
        if (v == end_voxel) continue;
        const auto other = endpoint_of.find(v);
        ASSERT_TRUE(other == endpoint_of.end()) << "the scene's premise: ray " << i << " crosses endpoint " << other->second;
        ray_samples[static_cast<std::size_t>(i)].push_back(q);
      }
    }

    const OctreeInsertStats stats = map.insert_scan(pose, sensor_points);
    EXPECT_EQ(stats.inserted, static_cast<std::size_t>(n));
    EXPECT_EQ(stats.non_finite + stats.outside_extent, 0u);

    std::set<OctreeVoxel> expected;
    for (const auto& [v, i] : endpoint_of) expected.insert(v);
    EXPECT_EQ(octree_occupied_set(map), expected);
    EXPECT_EQ(map.occupied_voxel_count(), expected.size());
    EXPECT_EQ(map.occupied_leaf_count(), expected.size());  // isolated voxels never prune
    for (const Vec3& p : map_points) {
      EXPECT_EQ(map.occupancy(p), CellState::Occupied);
      ASSERT_TRUE(map.probability(p).has_value());
      EXPECT_NEAR(*map.probability(p), 0.7, 1e-6);  // one hit
    }
    std::size_t checked = 0, not_free = 0;
    for (const auto& samples : ray_samples)
      for (const Vec3& q : samples) {
        ++checked;
        if (map.occupancy(q) != CellState::Free) ++not_free;
      }
    EXPECT_GT(checked, 100000u);
    EXPECT_EQ(not_free, 0u);
    EXPECT_NEAR(*map.probability(origin), 0.4, 1e-6);  // the sensor's own voxel: one miss per scan
    // Beyond the endpoints nothing was observed.
    for (const Vec3& p : sensor_points) EXPECT_EQ(map.occupancy(pose * (p * 1.3)), CellState::Unknown);
  }
}

TEST(OctreeMap, RaysBeyondMaxRangeOnlyClearUpToIt) {
  OctreeMapConfig config;
  config.resolution_m = 0.1;
  config.max_range_m = 2.0;
  config.discretize = false;
  OctreeMap map(config);
  const Vec3 origin(0.05, 0.05, 0.05);
  const Vec3 far(5.03, 0.37, 0.26), near(-1.46, 0.33, 0.12);  // 5 m beyond the limit, 1.5 m within
  const PointCloud points = {far - origin, near - origin};
  Rigid3 pose = Rigid3::Identity();
  pose.translation() = origin;
  map.insert_scan(pose, points);

  const Vec3 dir = (far - origin).normalized();
  for (const double d : {0.5, 1.0, 1.5, 1.85}) EXPECT_EQ(map.occupancy(origin + dir * d), CellState::Free) << d;
  for (const double d : {2.2, 3.0, 4.0}) EXPECT_EQ(map.occupancy(origin + dir * d), CellState::Unknown) << d;
  EXPECT_EQ(map.occupancy(far), CellState::Unknown);  // a max-range reading marks no endpoint
  EXPECT_EQ(map.occupancy(near), CellState::Occupied);
  EXPECT_EQ(octree_occupied_set(map), (std::set<OctreeVoxel>{octree_voxel_of(near, 0.1)}));
}

TEST(OctreeMap, PrunedLeavesAnswerPerVoxel) {
  // A solid 4 x 4 x 4 block of endpoints aligned to a depth-14 node: OctoMap prunes it into one
  // leaf, which every query still answers voxel by voxel.
  const double res = 0.1;
  OctreeMap map(OctreeMapConfig{.resolution_m = res});
  PointCloud points;
  std::set<OctreeVoxel> expected;
  for (long long i = 4; i < 8; ++i)
    for (long long j = 4; j < 8; ++j)
      for (long long k = 4; k < 8; ++k) {
        points.push_back(octree_voxel_centre({i, j, k}, res) + Vec3(0.013, -0.021, 0.017));
        expected.insert({i, j, k});
      }
  Rigid3 pose = Rigid3::Identity();
  pose.translation() = Vec3(-1.05, -0.95, -1.15);
  PointCloud sensor_points;
  for (const Vec3& p : points) sensor_points.push_back(p - pose.translation());
  map.insert_scan(pose, sensor_points);

  EXPECT_EQ(map.occupied_leaf_count(), 1u);
  EXPECT_EQ(map.occupied_voxel_count(), 64u);
  EXPECT_EQ(octree_occupied_set(map), expected);
  const std::vector<Vec3> centres = map.occupied_voxel_centres();
  ASSERT_EQ(centres.size(), 64u);
  EXPECT_NEAR(centres.front().x(), 0.45, 1e-12);  // ordered by (x, y, z) index
  EXPECT_NEAR(centres.back().z(), 0.75, 1e-12);
  EXPECT_EQ(map.occupancy({0.55, 0.65, 0.75}), CellState::Occupied);
  EXPECT_EQ(map.occupancy({0.85, 0.65, 0.75}), CellState::Unknown);

  // Known space: from the sensor's voxel to the block's far corner.
  const auto bounds = map.known_bounds();
  ASSERT_TRUE(bounds.has_value());
  EXPECT_NEAR(bounds->min.x(), -1.1, 1e-12);
  EXPECT_NEAR(bounds->min.y(), -1.0, 1e-12);
  EXPECT_NEAR(bounds->min.z(), -1.2, 1e-12);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(bounds->max[a], 0.8, 1e-12);
  EXPECT_FALSE(OctreeMap().known_bounds().has_value());
}

// ---- The room -------------------------------------------------------------------------------------

struct OctreeBox {
  Vec3 lo, hi;
};

// The room: interior x in [-2.93, 2.93], y in [-2.52, 2.47], walls 1.2 m high and 0.2 m thick, a
// door in the east wall at y in [-0.43, 0.37] opening on a closed corridor up to x = 4.93; the
// floor's surface at z = 0.01. Odd coordinates keep every face off the 0.1 m voxel faces.
struct OctreeRoomScene {
  std::vector<OctreeBox> boxes;
  std::vector<OctreeBox> in_band;  // what stands in the band [0.1, 0.6]: walls, legs, pillar
  OctreeBox low_box, table_top;
  std::vector<OctreeBox> legs;
  OctreeBox pillar;
};

OctreeRoomScene octree_room_scene() {
  OctreeRoomScene s;
  auto wall = [&](double x0, double y0, double x1, double y1) {
    s.boxes.push_back({{x0, y0, 0.01}, {x1, y1, 1.2}});
    s.in_band.push_back(s.boxes.back());
  };
  s.boxes.push_back({{-3.13, -2.72, -0.1}, {5.13, 2.67, 0.01}});  // floor
  wall(-3.13, -2.72, -2.93, 2.67);                                 // west
  wall(-3.13, -2.72, 5.13, -2.52);                                 // south (room and corridor)
  wall(-3.13, 2.47, 5.13, 2.67);                                   // north
  wall(2.93, -2.52, 3.13, -0.43);                                  // east, south of the door
  wall(2.93, 0.37, 3.13, 2.47);                                    // east, north of the door
  wall(4.93, -2.52, 5.13, 2.47);                                   // the corridor's end
  s.table_top = {{1.02, 0.63, 0.75}, {1.98, 1.37, 0.8}};
  s.boxes.push_back(s.table_top);
  for (const double x : {1.02, 1.92})
    for (const double y : {0.63, 1.31}) {
      s.legs.push_back({{x, y, 0.01}, {x + 0.06, y + 0.06, 0.75}});
      s.boxes.push_back(s.legs.back());
      s.in_band.push_back(s.legs.back());
    }
  s.low_box = {{-2.03, -1.63, 0.01}, {-1.42, -1.04, 0.07}};
  s.boxes.push_back(s.low_box);
  s.pillar = {{-1.83, 0.83, 0.01}, {-1.32, 1.32, 1.2}};
  s.boxes.push_back(s.pillar);
  s.in_band.push_back(s.pillar);
  return s;
}

// The nearest hit of a ray on the boxes (slab method), if any within 30 m.
std::optional<Vec3> octree_cast(const std::vector<OctreeBox>& boxes, const Vec3& o, const Vec3& d) {
  double best = 30.0;
  bool hit = false;
  for (const OctreeBox& b : boxes) {
    double t0 = 0.0, t1 = best;
    for (int a = 0; a < 3 && t0 <= t1; ++a) {
      if (std::abs(d[a]) < 1e-12) {
        if (o[a] < b.lo[a] || o[a] > b.hi[a]) t0 = kInfinity;
        continue;
      }
      double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (t0 <= t1 && t0 > 1e-9 && t0 < best) {
      best = t0;
      hit = true;
    }
  }
  if (!hit) return std::nullopt;
  return o + d * best;
}

// A LiDAR scan in the map frame: 1440 azimuths x 51 elevations (-45..30 degrees, 1.5 apart).
PointCloud octree_lidar_scan(const OctreeRoomScene& scene, const Vec3& origin, double res) {
  PointCloud hits;
  for (int e = 0; e <= 50; ++e) {
    const double el = (-45.0 + 1.5 * e) * kPi / 180.0;
    for (int a = 0; a < 1440; ++a) {
      const double az = a * 0.25 * kPi / 180.0;
      const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const auto p = octree_cast(scene.boxes, origin, d);
      if (p && !octree_near_face(*p, res)) hits.push_back(*p);
    }
  }
  return hits;
}

struct OctreeRoom {
  static constexpr double kRes = 0.1;
  OctreeRoomScene scene = octree_room_scene();
  std::vector<Rigid3> poses = {octree_pose({0.52, -0.47, 0.45}, 0.4, 0.05, -0.03),
                               octree_pose({1.03, -1.08, 0.45}, -0.7, 0.0, 0.04)};
  std::vector<PointCloud> map_scans;     // the hits in the map frame
  std::vector<PointCloud> sensor_scans;  // the same in each sensor's frame
  OctreeRoom() {
    for (const Rigid3& pose : poses) {
      map_scans.push_back(octree_lidar_scan(scene, pose.translation(), kRes));
      sensor_scans.push_back(transform_cloud(map_scans.back(), pose.inverse()));
    }
  }
  OctreeMap build() const {
    OctreeMap map(OctreeMapConfig{.resolution_m = kRes});
    for (std::size_t i = 0; i < poses.size(); ++i) map.insert_scan(poses[i], sensor_scans[i]);
    return map;
  }
};

const OctreeRoom& octree_room() {
  static const OctreeRoom room;
  return room;
}
const OctreeMap& octree_room_map() {
  static const OctreeMap map = octree_room().build();
  return map;
}

// Whether the 2D segment a-b meets the box's footprint grown by `margin` (Liang-Barsky).
bool octree_segment_meets(const Vec2& a, const Vec2& b, const OctreeBox& box, double margin) {
  double t0 = 0.0, t1 = 1.0;
  const Vec2 d = b - a;
  for (int k = 0; k < 2; ++k) {
    const double lo = box.lo[k] - margin, hi = box.hi[k] + margin;
    if (lo > hi) return false;  // shrunk to nothing
    if (std::abs(d[k]) < 1e-15) {
      if (a[k] < lo || a[k] > hi) return false;
      continue;
    }
    double ta = (lo - a[k]) / d[k], tb = (hi - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

bool octree_square_meets(const OctreeColumn& c, double res, const OctreeBox& box, double margin) {
  const double x0 = static_cast<double>(c[0]) * res, y0 = static_cast<double>(c[1]) * res;
  return x0 <= box.hi.x() + margin && x0 + res >= box.lo.x() - margin && y0 <= box.hi.y() + margin &&
         y0 + res >= box.lo.y() - margin;
}

std::array<Vec2, 5> octree_square_points(const OctreeColumn& c, double res) {
  const double x0 = static_cast<double>(c[0]) * res, y0 = static_cast<double>(c[1]) * res;
  return {Vec2(x0, y0), Vec2(x0 + res, y0), Vec2(x0, y0 + res), Vec2(x0 + res, y0 + res),
          Vec2(x0 + 0.5 * res, y0 + 0.5 * res)};
}

// The grid cell's voxel column (grids at the octree's resolution).
OctreeColumn octree_column_of(const OccupancyGrid& grid, int ix, int iy, double res) {
  const Vec2 c = grid.geometry().cell_center(ix, iy);
  return {static_cast<long long>(std::floor(c.x() / res)), static_cast<long long>(std::floor(c.y() / res))};
}

TEST(OctreeGrid, RoomGivesWallsAndLegsOccupiedObservedFloorFreeShadowsUnknown) {
  const OctreeRoom& room = octree_room();
  const OctreeMap& map = octree_room_map();
  const double res = OctreeRoom::kRes;
  GridProjectionConfig band;  // [0.1, 0.6] above z = 0
  band.padding_m = 0.3;
  const OccupancyGrid grid = map.project_to_grid(band);
  ASSERT_EQ(grid.resolution(), res);

  // Brute force: the columns of the endpoint voxels whose centre is in the band. Within one scan an
  // endpoint wins over the rays, and two scans cannot bring a hit voxel down to free (0.85 - 0.4 > 0).
  std::set<OctreeColumn> expected_occupied;
  for (const PointCloud& scan : room.map_scans)
    for (const Vec3& p : scan) {
      const OctreeVoxel v = octree_voxel_of(p, res);
      const double zc = (static_cast<double>(v[2]) + 0.5) * res;
      if (zc >= 0.1 && zc <= 0.6) expected_occupied.insert({v[0], v[1]});
    }
  std::set<OctreeColumn> occupied;
  for (int iy = 0; iy < grid.height(); ++iy)
    for (int ix = 0; ix < grid.width(); ++ix)
      if (grid(ix, iy) == kOccupiedOccupancy) occupied.insert(octree_column_of(grid, ix, iy, res));
  EXPECT_EQ(occupied, expected_occupied);

  // Occupied exactly at walls, legs and the pillar: each occupied cell touches one of them...
  for (const OctreeColumn& c : occupied) {
    bool touches = false;
    for (const OctreeBox& b : room.scene.in_band) touches = touches || octree_square_meets(c, res, b, 0.0);
    EXPECT_TRUE(touches) << c[0] << " " << c[1];
  }
  // ... every leg and the pillar show, and so does the south wall's whole face (seen by both scans).
  for (const OctreeBox& leg : room.scene.legs) {
    bool seen = false;
    for (const OctreeColumn& c : occupied) seen = seen || octree_square_meets(c, res, leg, 0.0);
    EXPECT_TRUE(seen) << leg.lo.transpose();
  }
  for (long long kx = -29; kx <= 28; ++kx) EXPECT_TRUE(occupied.count({kx, -26})) << kx;

  // Per cell: free where a sensor sees the whole cell past every standing thing (grown by one
  // voxel); unknown where for every sensor a standing thing (shrunk by the discretisation's
  // reach) hides all of it.
  std::size_t free_checked = 0, unknown_checked = 0, unknown_in_room = 0, box_free = 0, table_free = 0;
  for (int iy = 0; iy < grid.height(); ++iy)
    for (int ix = 0; ix < grid.width(); ++ix) {
      const OctreeColumn c = octree_column_of(grid, ix, iy, res);
      const Vec2 centre = grid.geometry().cell_center(ix, iy);
      const bool on_floor = centre.x() > -2.93 && centre.x() < 4.93 && centre.y() > -2.52 && centre.y() < 2.47;
      if (!on_floor) continue;
      bool near_standing = false;
      for (const OctreeBox& b : room.scene.in_band) near_standing = near_standing || octree_square_meets(c, res, b, 0.1);
      if (near_standing) continue;
      const auto points = octree_square_points(c, res);
      bool seen = false, hidden = true;
      for (const Rigid3& pose : room.poses) {
        const Vec2 s = pose.translation().head<2>();
        bool clear = true;
        for (const Vec2& q : points)
          for (const OctreeBox& b : room.scene.in_band) clear = clear && !octree_segment_meets(s, q, b, 0.1);
        seen = seen || clear;
        bool hidden_from_here = false;
        for (const OctreeBox& b : room.scene.in_band) {
          bool all = true;
          for (const Vec2& q : points) all = all && octree_segment_meets(s, q, b, -0.08);
          hidden_from_here = hidden_from_here || all;
        }
        hidden = hidden && hidden_from_here;
      }
      if (seen) {
        ++free_checked;
        EXPECT_EQ(grid(ix, iy), kFreeOccupancy) << centre.transpose();
        if (octree_square_meets(c, res, room.scene.low_box, 0.0)) ++box_free;
        if (octree_square_meets(c, res, room.scene.table_top, 0.0)) ++table_free;
      } else if (hidden) {
        ++unknown_checked;
        if (centre.x() < 2.93) ++unknown_in_room;
        EXPECT_EQ(grid(ix, iy), kUnknownOccupancy) << centre.transpose();
      }
    }
  EXPECT_GT(free_checked, 2000u);
  EXPECT_GT(unknown_checked, 350u);  // behind the east wall, beside the door
  EXPECT_GT(unknown_in_room, 30u);   // behind the pillar
  EXPECT_GT(box_free, 35u);          // the low box is under the band
  EXPECT_GT(table_free, 35u);        // the table's top is above it

  // The padding (3 cells) holds nothing; the known space starts right inside it.
  const auto bounds = map.known_bounds();
  ASSERT_TRUE(bounds.has_value());
  EXPECT_NEAR(grid.origin().x, bounds->min.x() - 0.3, 1e-9);
  EXPECT_NEAR(grid.origin().y, bounds->min.y() - 0.3, 1e-9);
  EXPECT_EQ(grid.width(), static_cast<int>(std::lround((bounds->max.x() - bounds->min.x()) / res)) + 6);
  EXPECT_EQ(grid.height(), static_cast<int>(std::lround((bounds->max.y() - bounds->min.y()) / res)) + 6);
  for (int iy = 0; iy < grid.height(); ++iy)
    for (int ix = 0; ix < grid.width(); ++ix) {
      if (ix < 3 || iy < 3 || ix >= grid.width() - 3 || iy >= grid.height() - 3) {
        EXPECT_EQ(grid(ix, iy), kUnknownOccupancy) << ix << " " << iy;
      }
    }
}

TEST(OctreeGrid, OtherResolutionsGatherTheVoxelColumns) {
  const OctreeMap& map = octree_room_map();
  GridProjectionConfig fine_config;
  fine_config.padding_m = 0.2;
  const OccupancyGrid fine = map.project_to_grid(fine_config);

  // A 0.2 m cell holds 2 x 2 voxel columns: occupied when one of them is, else free when one is.
  GridProjectionConfig coarse_config = fine_config;
  coarse_config.resolution_m = 0.2;
  const OccupancyGrid coarse = map.project_to_grid(coarse_config);
  EXPECT_NEAR(coarse.origin().x, fine.origin().x, 1e-12);
  EXPECT_NEAR(coarse.origin().y, fine.origin().y, 1e-12);
  EXPECT_EQ(coarse.width(), (fine.width() + 1) / 2);
  EXPECT_EQ(coarse.height(), (fine.height() + 1) / 2);
  std::size_t mismatches = 0;
  for (int cy = 0; cy < coarse.height(); ++cy)
    for (int cx = 0; cx < coarse.width(); ++cx) {
      bool any_occupied = false, any_free = false;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          if (!fine.contains(2 * cx + dx, 2 * cy + dy)) continue;
          const std::int8_t v = fine(2 * cx + dx, 2 * cy + dy);
          any_occupied = any_occupied || v == kOccupiedOccupancy;
          any_free = any_free || v == kFreeOccupancy;
        }
      const std::int8_t want = any_occupied ? kOccupiedOccupancy : any_free ? kFreeOccupancy : kUnknownOccupancy;
      if (coarse(cx, cy) != want) ++mismatches;
    }
  EXPECT_EQ(mismatches, 0u);

  // A 0.05 m cell lies in one voxel column and takes its value.
  GridProjectionConfig finer_config = fine_config;
  finer_config.resolution_m = 0.05;
  const OccupancyGrid finer = map.project_to_grid(finer_config);
  ASSERT_EQ(finer.width(), 2 * fine.width());
  ASSERT_EQ(finer.height(), 2 * fine.height());
  mismatches = 0;
  for (int iy = 0; iy < finer.height(); ++iy)
    for (int ix = 0; ix < finer.width(); ++ix)
      if (finer(ix, iy) != fine(ix / 2, iy / 2)) ++mismatches;
  EXPECT_EQ(mismatches, 0u);

  // A band that starts below the floor's voxels makes the whole floor occupied.
  GridProjectionConfig low = fine_config;
  low.min_height_m = 0.0;
  EXPECT_GT(map.project_to_grid(low).counts().occupied, 3 * fine.counts().occupied);
}

TEST(OctreeMap, SameInsertsGiveTheSameTreeGridAndBytes) {
  const OctreeMap& first = octree_room_map();
  const OctreeMap second = octree_room().build();
  EXPECT_EQ(first.binary(), second.binary());
  EXPECT_EQ(first.project_to_grid(), second.project_to_grid());
  EXPECT_EQ(first.occupied_voxel_centres(), second.occupied_voxel_centres());

  test::ScratchDir dir;
  first.write(dir.file("a.bt"));
  second.write(dir.file("b.bt"));
  const std::string bytes = test::read_text(dir.file("a.bt"));
  EXPECT_EQ(bytes, test::read_text(dir.file("b.bt")));
  EXPECT_EQ(bytes.rfind("# Octomap OcTree binary file", 0), 0u);
  // Writing kept the probabilities (it converts a copy to maximum likelihood).
  EXPECT_EQ(first.binary(), bytes);
  EXPECT_NEAR(*first.probability(octree_room().map_scans[0][0]), 0.7, 0.2);

  // OctoMap reads it back: the same occupied voxels.
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(dir.file("a.bt")));
  EXPECT_DOUBLE_EQ(tree.getResolution(), 0.1);
  std::size_t occupied = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
    if (tree.isNodeOccupied(*it)) occupied += std::size_t{1} << (3 * (16 - it.getDepth()));
  EXPECT_EQ(occupied, first.occupied_voxel_count());
  // ... and writes it back byte for byte (the header here is OctoMap's own).
  std::ostringstream rewritten;
  ASSERT_TRUE(tree.writeBinary(rewritten));
  EXPECT_EQ(rewritten.str(), bytes);
}

TEST(OctreeMap, MatchesOctoMapsOwnInsertPointCloud) {
  // The same scans through OcTree::insertPointCloud: the same probabilities and the same file.
  // Poses without rotation, so that both receive bit-identical map-frame points.
  const OctreeRoom& room = octree_room();
  for (const auto& [discretize, max_range] : {std::pair{true, kInfinity}, std::pair{false, 3.0}}) {
    SCOPED_TRACE(discretize ? "discretize" : "exact rays, max range 3 m");
    OctreeMap ours(OctreeMapConfig{.resolution_m = OctreeRoom::kRes, .max_range_m = max_range, .discretize = discretize});
    octomap::OcTree theirs(OctreeRoom::kRes);
    std::vector<Vec3> probes;
    for (std::size_t s = 0; s < room.poses.size(); ++s) {
      Rigid3 pose = Rigid3::Identity();
      pose.translation() = room.poses[s].translation();
      PointCloud sensor_points;
      octomap::Pointcloud cloud;
      for (const Vec3& p : room.map_scans[s]) {
        sensor_points.push_back(p - pose.translation());
        const Vec3 q = pose * sensor_points.back();
        cloud.push_back(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
        probes.push_back(q);
        probes.push_back(0.5 * (q + pose.translation()));
      }
      ours.insert_scan(pose, sensor_points);
      const Vec3& o = pose.translation();
      theirs.insertPointCloud(cloud, octomap::point3d(static_cast<float>(o.x()), static_cast<float>(o.y()), static_cast<float>(o.z())),
                              std::isfinite(max_range) ? max_range : -1.0, false, discretize);
    }
    std::size_t differences = 0;
    for (const Vec3& p : probes) {
      // As OctoMap is given points: in float.
      const octomap::OcTreeNode* node = theirs.search(
          octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
      const std::optional<double> prob = ours.probability(p);
      if (node == nullptr ? prob.has_value() : (!prob || *prob != node->getOccupancy())) ++differences;
    }
    EXPECT_EQ(differences, 0u);
    std::ostringstream theirs_bytes;
    ASSERT_TRUE(theirs.writeBinary(theirs_bytes));
    EXPECT_EQ(ours.binary(), theirs_bytes.str());
  }
}

// ---- Bad input ----------------------------------------------------------------------------------

template <class F>
std::string octree_error_field(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.field();
  }
  return "(no error)";
}

TEST(OctreeMapErrors, BadConfigurationsNameTheirField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(octree_error_field([] { (void)OctreeMap(OctreeMapConfig{.resolution_m = 0.0}); }), "resolution_m");
  EXPECT_EQ(octree_error_field([] { (void)OctreeMap(OctreeMapConfig{.resolution_m = -0.05}); }), "resolution_m");
  EXPECT_EQ(octree_error_field([&] { (void)OctreeMap(OctreeMapConfig{.resolution_m = nan}); }), "resolution_m");
  EXPECT_EQ(octree_error_field([] { (void)OctreeMap(OctreeMapConfig{.prob_hit = 0.4}); }), "prob_hit");
  EXPECT_EQ(octree_error_field([] { (void)OctreeMap(OctreeMapConfig{.prob_miss = 0.6}); }), "prob_miss");
  EXPECT_EQ(octree_error_field([] { (void)OctreeMap(OctreeMapConfig{.clamping_max = 0.1}); }), "clamping_max");
  EXPECT_EQ(octree_error_field([] { (void)OctreeMap(OctreeMapConfig{.occupancy_threshold = 0.99}); }), "occupancy_threshold");
  EXPECT_EQ(octree_error_field([] { (void)OctreeMap(OctreeMapConfig{.max_range_m = 0.0}); }), "max_range_m");

  OctreeMap map;
  EXPECT_EQ(octree_error_field([&] { (void)map.project_to_grid(); }), "");  // empty: nothing to project
  const PointCloud points = {{1.0, 0.2, 0.3}};
  map.insert_scan(Rigid3::Identity(), points);
  EXPECT_EQ(octree_error_field([&] { (void)map.project_to_grid({.resolution_m = -1.0}); }), "resolution_m");
  EXPECT_EQ(octree_error_field([&] { (void)map.project_to_grid({.min_height_m = 0.5, .max_height_m = 0.5}); }),
            "max_height_m");
  EXPECT_EQ(octree_error_field([&] { (void)map.project_to_grid({.min_height_m = 0.3, .max_height_m = 0.31}); }),
            "max_height_m");  // no voxel centre (0.325 is the next) within the band
  EXPECT_EQ(octree_error_field([&] { (void)map.project_to_grid({.padding_m = nan}); }), "padding_m");
  EXPECT_EQ(octree_error_field([&] { (void)map.project_to_grid({.floor_z_m = nan}); }), "floor_z_m");
}

TEST(OctreeMapErrors, BadPosesAreRefusedAndBadPointsCounted) {
  OctreeMap map;
  const PointCloud points = {{1.0, 0.0, 0.0}};
  Rigid3 nan_pose = Rigid3::Identity();
  nan_pose.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(octree_error_field([&] { map.insert_scan(nan_pose, points); }), "sensor_pose");
  Rigid3 nan_rotation = Rigid3::Identity();
  nan_rotation.linear()(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(octree_error_field([&] { map.insert_scan(nan_rotation, points); }), "sensor_pose");
  Rigid3 scaled = Rigid3::Identity();
  scaled.linear() *= 2.0;
  EXPECT_EQ(octree_error_field([&] { map.insert_scan(scaled, points); }), "sensor_pose");
  Rigid3 far_away = Rigid3::Identity();
  far_away.translation().x() = 5000.0;  // the tree reaches 1638.4 m at 0.05 m
  EXPECT_EQ(octree_error_field([&] { map.insert_scan(far_away, points); }), "sensor_pose");
  EXPECT_FALSE(map.known_bounds().has_value());  // nothing was inserted

  const double inf = std::numeric_limits<double>::infinity();
  const PointCloud mixed = {{1.0, 0.0, 0.0}, {std::nan(""), 0.0, 0.0}, {0.0, inf, 0.0}, {2000.0, 0.0, 0.0}, {1e300, 0.0, 0.0}};
  const OctreeInsertStats stats = map.insert_scan(Rigid3::Identity(), mixed);
  EXPECT_EQ(stats.inserted, 1u);
  EXPECT_EQ(stats.non_finite, 2u);
  EXPECT_EQ(stats.outside_extent, 2u);
  EXPECT_EQ(map.occupied_voxel_count(), 1u);
}

TEST(OctreeMapErrors, UnwritablePathNamesTheFile) {
  OctreeMap map;
  const PointCloud points = {{1.0, 0.2, 0.3}};
  map.insert_scan(Rigid3::Identity(), points);
  const std::string path = "/nonexistent-starnav-dir/map.bt";
  try {
    map.write(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

}  // namespace
}  // namespace starnav
