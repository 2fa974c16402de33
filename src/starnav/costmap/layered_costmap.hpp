#pragma once
// The navigation map (docs/navigation.md, "The navigation map"): a world-aligned grid made of
// layers (costmap/costmap_layer.hpp) in order, Nav2's layered costmap without its middleware.
// Per scan every layer takes what it wants and says which cells its contribution changed; over
// those cells the costmap recomposes its master masks (a cell is an obstacle when any layer says
// so, observed when any layer observed it), expands the obstacles by the barrier distance (exact
// Euclidean distance transform, incrementally over the window a change can affect), and derives
// the views the navigation reads:
//   occupancy()      the planners' grid: 100 blocked (an obstacle or within the barrier distance of
//                    one), 0 observed and free, -1 unobserved and free (plan with unknown_is_free);
//   raw_occupancy()  the obstacles before expansion (what a controller that checks the footprint
//                    reads): 100 obstacle, 0 observed, -1 unobserved;
//   clearance()      the distance of every cell to its nearest obstacle out to a range (exact,
//                    kept up to date lazily: the controllers, the recoveries' footprint check);
//   escape_cell()    where a robot inside the expansion band plans from.
// The result equals rebuild(), a from-scratch recomputation of everything derived (a test checks it).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "starnav/costmap/costmap_layer.hpp"
#include "starnav/map/obstacle_distance_field.hpp"
#include "starnav/map/mask_inflation.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sense/lidar.hpp"

namespace starnav {

// What one scan changed.
struct CostmapUpdate {
  std::size_t returns_used = 0;     // returns inside the grid
  std::size_t cells_hit = 0;        // cells with at least one return
  std::size_t cells_contradicted = 0;
  std::size_t cells_cleared = 0;    // cells that became unobserved
  std::size_t cells_changed = 0;    // cells whose heights or observed flag changed
  CellRect bounds;                  // bounding rectangle of the occupancy changes (empty: none)
  std::vector<Cell> occupancy_changed;  // cells whose occupancy() value changed, row-major order
};

class LayeredCostmap {
 public:
  // The layers in order (none is an empty map). Throws Error for a bad geometry (y_down grids are
  // not metric) or params (field named).
  LayeredCostmap(const GridGeometry& geometry, const NodeMapParams& params, std::vector<std::unique_ptr<CostmapLayer>> layers);
  LayeredCostmap(LayeredCostmap&&) noexcept;
  LayeredCostmap& operator=(LayeredCostmap&&) noexcept;
  ~LayeredCostmap();

  const GridGeometry& geometry() const { return geometry_; }
  const NodeMapParams& params() const { return params_; }
  int width() const { return geometry_.width; }
  int height() const { return geometry_.height; }
  const std::vector<std::unique_ptr<CostmapLayer>>& layers() const { return layers_; }

  // One scan: the sensor origin and the world points of its returns (self-filtered already).
  // Returns outside the grid are ignored; beams are walked over the part inside the grid.
  // Non-finite points are skipped. `pass_ends`: optional end points of beams that returned
  // nothing (open space up to there); they are walked like the others, their last cell included,
  // and clear without hitting.
  CostmapUpdate integrate(const Vec3& sensor_origin, std::span<const Vec3> points_world,
                          std::span<const Vec3> pass_ends = {});
  // The same with a LidarScan (origin = scan.sensor_pose.position, points = scan.points_world).
  // With no_return_clear_m > 0, every ray without a return also clears up to that distance. Opt
  // in only when a missing return means open space: a LidarScan cannot tell it from a dropout or a
  // self-filtered ray, which would clear through real obstacles.
  CostmapUpdate integrate(const LidarScan& scan, double no_return_clear_m = 0.0);

  // Recomputes every derived mask (each layer's own derivations, the master, the expansion, the
  // views) from the layers' raw state.
  void rebuild();

  bool observed(int x, int y) const { return observed_[geometry_.index(x, y)] != 0; }
  // 1 = an obstacle of some layer (before expansion); unobserved cells are 0 unless a layer knows them.
  const std::vector<std::uint8_t>& raw_blocked() const { return obstacles_; }
  // 1 = blocked for planning (the obstacles expanded by barrier_distance_m).
  const std::vector<std::uint8_t>& blocked() const { return blocked_; }
  bool raw_blocked(int x, int y) const { return obstacles_[geometry_.index(x, y)] != 0; }
  bool blocked(int x, int y) const { return blocked_[geometry_.index(x, y)] != 0; }
  const OccupancyGrid& occupancy() const { return occupancy_; }
  const OccupancyGrid& raw_occupancy() const { return raw_occupancy_; }
  // The heights of the first layer that keeps them (3D nodes), else null.
  const ElevationMap* heights() const;
  // The distance field of the obstacles, brought up to date.
  const ObstacleDistanceField& clearance() const;

  // The lowest speed limit (m/s) any layer sets on `area` (a polygon in the map frame: the
  // robot's footprint); nothing when no layer limits the speed there.
  std::optional<double> speed_limit_mps(std::span<const Vec2> area) const;

  // Where the robot at `start` should plan from. `start` itself when it is not blocked; when it
  // lies inside the expansion band but not in an obstacle cell, the cell outside the band reached
  // by the cheapest 8-connected path (costs 1 and sqrt 2, no corner cutting past obstacle cells)
  // through cells that are not obstacles; ties go to the lower cell index. Nothing when start is
  // outside the grid, an obstacle, or no such cell exists. `path`, when given, receives the cells
  // from start to the escape cell.
  std::optional<Cell> escape_cell(Cell start, std::vector<Cell>* path = nullptr) const;

 private:
  void recompose(const CellRect& rect);
  void refresh_views(const CellRect& obstacles_changed, CostmapUpdate& update);
  std::int8_t occupancy_value(std::size_t i) const;
  std::int8_t raw_occupancy_value(std::size_t i) const;

  GridGeometry geometry_;
  NodeMapParams params_;
  std::vector<std::unique_ptr<CostmapLayer>> layers_;
  std::vector<std::uint8_t> obstacles_, observed_, blocked_;
  OccupancyGrid occupancy_, raw_occupancy_;
  IncrementalInflation inflation_;
  std::unique_ptr<ObstacleDistanceField> clearance_;  // refers to obstacles_: on the heap, so moves keep it valid
  std::vector<CellRect> changed_;  // scratch
  std::vector<std::uint8_t> before_;  // scratch: obstacle cells of changed_ before a scan
  std::vector<Vec3> pass_ends_;    // scratch
};

}  // namespace starnav
