#pragma once
// The 3D map as an octree of occupancy probabilities (OctoMap, Hornung et al. 2013; Ou et al.
// 2022 section 2.3; docs/mapping3d.md) and the 2D occupancy grid the planner uses.
// OctoMap stays behind the implementation: including this header needs no OctoMap header.
//
// Voxels: the map frame is cut into cubes of side resolution_m, voxel (i, j, k) covering
// [i r, (i+1) r) x [j r, (j+1) r) x [k r, (k+1) r) (r = resolution_m, i = floor(x / r)); the tree
// reaches +-32768 voxels on each axis (+-1638.4 m at 0.05 m). Each observed voxel holds a
// log-odds occupancy updated by OctoMap's hit / miss model with clamping; it is occupied at or
// above occupancy_threshold, free below; a voxel never observed is unknown. Equal neighbours are
// pruned into bigger leaves; every query below answers per voxel, whatever the pruning.
//
// Determinism: the same inserts give the same tree, the same grid and the same bytes written.
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

// OctoMap's defaults except max_range_m (OctoMap: no limit, as here) and discretize.
struct OctreeMapConfig {
  double resolution_m = 0.05;  // hdl_graph_slam's map cloud resolution
  double prob_hit = 0.7;       // an endpoint's update; in (0.5, 1)
  double prob_miss = 0.4;      // the update of a voxel a ray passes through; in (0, 0.5)
  double clamping_min = 0.1192;  // probabilities are clamped to [min, max] so that a voxel can change
  double clamping_max = 0.971;   //   its state again after a few contrary observations
  double occupancy_threshold = 0.5;  // occupied at or above it; in (clamping_min, clamping_max)
  // Rays longer than this clear free space up to max_range_m only and mark no endpoint; must be
  // > 0, infinity for no limit.
  double max_range_m = kInfinity;
  // OctoMap's discretised insertion: endpoints falling in one voxel cast one ray, to the voxel's
  // centre (much faster for dense scans; rays run to the centre, not the point).
  bool discretize = true;
  void validate() const;  // Error naming the field
};

// The 2D grid of project_to_grid. A grid column is the vertical prism over one cell.
struct GridProjectionConfig {
  double resolution_m = 0.0;  // the grid's cell size; 0: the octree's resolution
  double floor_z_m = 0.0;     // the floor's height in the map frame (graph SLAM 3D puts it at 0)
  // The robot's height band above the floor: [floor_z + min_height, floor_z + max_height].
  // 0.1 m keeps the floor's own voxels and its roughness out; 0.6 m covers the simulated Mecanum
  // robot with its LiDAR at 0.55 m (scenarios/ou2022_mapping3d.yaml).
  double min_height_m = 0.1;
  double max_height_m = 0.6;
  double padding_m = 0.0;  // unknown margin around the known space, rounded up to whole cells
  void validate() const;   // Error naming the field
};

// What insert_scan did with the points it was given.
struct OctreeInsertStats {
  std::size_t inserted = 0;        // passed to OctoMap (a ray each, or per voxel when discretised)
  std::size_t non_finite = 0;      // NaN or infinite coordinates: dropped (organised clouds' holes)
  std::size_t outside_extent = 0;  // beyond the tree's +-32768 voxels: dropped
};

// Move-only; a moved-from map may only be assigned to or destroyed.
class OctreeMap {
 public:
  explicit OctreeMap(const OctreeMapConfig& config = {});  // validates the configuration
  ~OctreeMap();
  OctreeMap(OctreeMap&&) noexcept;
  OctreeMap& operator=(OctreeMap&&) noexcept;
  OctreeMap(const OctreeMap&) = delete;
  OctreeMap& operator=(const OctreeMap&) = delete;

  const OctreeMapConfig& config() const;
  double resolution() const;

  // One scan (a key frame): `points_sensor` in the sensor frame, `sensor_pose` the sensor in the
  // map frame. OctoMap's insertPointCloud from the sensor's origin: every voxel a ray passes
  // through (the sensor's own voxel included, the endpoint's excluded) gets a miss, every endpoint
  // voxel a hit; a voxel both passed through and hit in one scan only gets the hit. A point beyond
  // max_range_m only clears its ray up to max_range_m. Throws Error (field "sensor_pose") for a
  // non-finite or non-rigid pose or a sensor outside the tree's extent.
  OctreeInsertStats insert_scan(const Rigid3& sensor_pose, std::span<const Vec3> points_sensor);

  // The voxel holding `p_map` (map frame): Occupied, Free, or Unknown (never observed, outside
  // the tree, or not finite).
  CellState occupancy(const Vec3& p_map) const;
  // Its occupancy probability, or nothing when unknown.
  std::optional<double> probability(const Vec3& p_map) const;

  // Leaves of the tree that are occupied (a pruned leaf counts once, as the .bt file stores it).
  std::size_t occupied_leaf_count() const;
  // Occupied voxels at the map's resolution (pruned leaves counted voxel by voxel).
  std::size_t occupied_voxel_count() const;
  // The centre of every occupied voxel at the map's resolution, ordered by (x, y, z) index.
  void for_each_occupied_voxel(const std::function<void(const Vec3& centre)>& visit) const;
  std::vector<Vec3> occupied_voxel_centres() const;
  // The axis-aligned box of the known (free or occupied) space, voxel faces included; nothing for
  // an empty map.
  std::optional<CloudBounds> known_bounds() const;
  std::size_t memory_bytes() const;  // OctoMap's estimate of the tree's memory

  // OctoMap's compact binary format (.bt, OcTree::writeBinary): the maximum-likelihood map, each
  // voxel occupied or free, pruned. The map itself keeps its probabilities (a copy is converted).
  std::string binary() const;
  // binary() into `path`; Error naming the file when it cannot be written.
  void write(const std::string& path) const;

  // The planner's 2D occupancy grid (ROS values: 100 occupied, 0 free, -1 unknown; save it as a
  // map_server map with write_ros_map, io/ros_map.hpp). The rule, per grid cell:
  //  - a voxel is in the band when its centre's height is within
  //    [floor_z_m + min_height_m, floor_z_m + max_height_m];
  //  - a voxel belongs to every cell whose square overlaps its own square in x, y (so a cell of a
  //    coarser grid gathers several voxel columns, a finer grid's cells share one);
  //  - occupied (100) when any occupied voxel in the band belongs to it; otherwise free (0) when
  //    any free voxel in the band does; otherwise unknown (-1).
  // Geometry: origin at the lower-left corner of the known space's x, y bounds less the padding
  // (whole cells), yaw 0, rows bottom-up; width and height cover the bounds and the padding, so
  // with the octree's resolution the cells are the voxel columns. Throws Error for a bad
  // configuration (field named), an empty map, or a grid beyond 2^31 cells.
  OccupancyGrid project_to_grid(const GridProjectionConfig& config = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace starnav
