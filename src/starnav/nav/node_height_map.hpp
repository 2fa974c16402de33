#pragma once
// Mapping from LiDAR scans for navigation in unknown and dynamic environments (spec li2019
// sections 5-7; docs/navigation.md has the rules in full).
//
// A world-aligned grid of 3D nodes. Each cell keeps the min and max height of its current hits
// and an integer evidence count. Per scan:
//   hits    every return falling in a cell updates its min/max (the first return of an
//           unobserved cell sets both); a cell hit in the scan gains `hit_gain` evidence (once
//           per scan, however many returns fall in it).
//   passes  every beam is walked over the grid from the sensor to its return (Amanatides-Woo).
//           A cell it crosses before its end cell contradicts the cell's stored hits when the
//           beam's highest point inside the cell lies more than `clear_margin_m` below the
//           cell's max height (there was something there, now the beam passes through): the
//           cell loses `miss_loss` evidence (once per scan), and its stored heights are replaced
//           by the scan's own hits in it, if any. A beam passing above the cell's hits (over low
//           ground) contradicts nothing. In 2D mode every crossed cell is contradicted.
//   result  evidence is clamped to [0, evidence_max]; a cell at 0 is unobserved again.
// Contradictions are judged against the map as it was before the scan, so the order of the
// returns within a scan does not matter.
//
// Walkability: the Li 2019 node criteria of terrain/TerrainAnalysis (height spread > max_step,
// mid-height difference to an observed 8-neighbour > tan(max_slope) * distance) on observed
// cells; unobserved cells are free for planning. 2D mode: a cell with evidence is occupied.
// Expansion: every cell whose centre lies within barrier_distance_m of a raw blocked cell's
// centre is blocked for planning (exact Euclidean distance transform).
// Incremental: only the cells whose heights or observed flag changed are re-analysed (in tiles),
// and only the expansion of those regions grown by the barrier distance is recomputed; the
// result equals rebuild() (a from-scratch recomputation of everything derived).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/distance_transform.hpp"
#include "starnav/map/mask_inflation.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sense/lidar.hpp"
#include "starnav/terrain/terrain_analysis.hpp"

namespace starnav {

enum class NodeMapMode : std::uint8_t {
  Nodes3D,  // min/max height per cell, Li 2019 criteria (3D LiDAR)
  Lidar2D,  // each return marks its cell occupied (2D LiDAR, paper Fig. 13)
};

struct NodeMapParams {
  NodeMapMode mode = NodeMapMode::Nodes3D;
  LiNodeParams li;                   // max_step_m = k_step * cell size, max_slope_rad = atan(k_slope)
  double barrier_distance_m = 0.36;  // obstacle expansion radius (robot's circumscribed radius)
  bool clear = true;                 // beams clear the cells they pass through
  double clear_margin_m = 0.05;      // a beam contradicts a cell only when its highest point there is this far below the cell's max
  int hit_gain = 2;                  // evidence gained by a cell hit in a scan
  int miss_loss = 1;                 // evidence lost by a cell a beam contradicts in a scan
  int evidence_max = 4;              // cap: a stale cell is cleared after evidence_max / miss_loss scans
  void validate() const;             // Error naming the field
};

// What one integrate() changed.
struct NodeMapUpdate {
  std::size_t returns_used = 0;     // returns inside the grid
  std::size_t cells_hit = 0;        // cells with at least one return
  std::size_t cells_contradicted = 0;
  std::size_t cells_cleared = 0;    // cells that became unobserved
  std::size_t cells_changed = 0;    // cells whose heights or observed flag changed
  CellRect bounds;                  // bounding rectangle of the occupancy changes (empty: none)
  std::vector<Cell> occupancy_changed;  // cells whose occupancy() value changed, row-major order
};

class NodeHeightMap {
 public:
  // All cells unobserved. Throws Error for a bad geometry (y_down grids are not metric) or params.
  explicit NodeHeightMap(const GridGeometry& geometry, const NodeMapParams& params = {});

  const GridGeometry& geometry() const { return geometry_; }
  const NodeMapParams& params() const { return params_; }
  int width() const { return geometry_.width; }
  int height() const { return geometry_.height; }

  // One scan: the sensor origin and the world points of its returns (self-filtered already).
  // Returns outside the grid are ignored; beams are walked over the part inside the grid.
  // Non-finite points are skipped.
  // `pass_ends`: optional end points of beams that returned nothing (open space up to there);
  // they are walked like the others, their last cell included, and clear without hitting.
  NodeMapUpdate integrate(const Vec3& sensor_origin, std::span<const Vec3> points_world,
                          std::span<const Vec3> pass_ends = {});
  // The same with a LidarScan (origin = scan.sensor_pose.position, points = scan.points_world).
  // With no_return_clear_m > 0, every ray without a return also clears up to that distance.
  // Opt in only when a missing return means open space: a LidarScan cannot tell it from a dropout
  // or a self-filtered ray, which would clear through real obstacles.
  NodeMapUpdate integrate(const LidarScan& scan, double no_return_clear_m = 0.0);

  // Recomputes every derived layer (analysis, raw mask, expansion, occupancy) from the evidence.
  void rebuild();

  // Obstacles known before the run (a map_server map of the building): cells blocked whatever
  // the scans say, expanded like sensed ones. `mask` is row-major over the grid, non-zero =
  // obstacle. 2D mode only (Error naming "map.prior" otherwise, or for a mask of another size).
  void set_static_obstacles(std::span<const std::uint8_t> mask);

  // Per-cell state.
  int evidence(int x, int y) const { return evidence_[geometry_.index(x, y)]; }
  bool observed(int x, int y) const { return evidence_[geometry_.index(x, y)] > 0; }
  // min / max heights of the observed cells (heights are 0 in 2D mode): height = mid.
  const ElevationMap& elevation() const { return elevation_; }
  // 1 = blocked before expansion (Li criteria, or occupied in 2D mode); unobserved cells are 0.
  const std::vector<std::uint8_t>& raw_blocked() const {
    return params_.mode == NodeMapMode::Nodes3D ? analysis_.li_blocked_mask() : raw2d_;
  }
  // 1 = blocked for planning (raw blocked expanded by barrier_distance_m).
  const std::vector<std::uint8_t>& blocked() const { return blocked_; }
  bool raw_blocked(int x, int y) const { return raw_blocked()[geometry_.index(x, y)] != 0; }
  bool blocked(int x, int y) const { return blocked_[geometry_.index(x, y)] != 0; }
  // The planners' view: 100 blocked, 0 observed and free, -1 unobserved and free (plan with
  // unknown_is_free = true).
  const OccupancyGrid& occupancy() const { return occupancy_; }
  // The obstacles before expansion (what a controller that checks the robot's footprint reads):
  // 100 raw blocked, 0 observed and free, -1 unobserved.
  const OccupancyGrid& raw_occupancy() const { return raw_occupancy_; }
  // Valid in Nodes3D mode only.
  const TerrainAnalysis& analysis() const { return analysis_; }

  // Where the robot at `start` should plan from. `start` itself when it is not blocked; when it
  // lies inside the expansion band but not in a raw blocked cell, the cell outside the band
  // reached by the cheapest 8-connected path (costs 1 and sqrt 2, no corner cutting past raw
  // blocked cells) through cells that are not raw blocked; ties go to the lower cell index.
  // Nothing when start is outside the grid, raw blocked, or no such cell exists. `path`, when
  // given, receives the cells from start to the escape cell.
  std::optional<Cell> escape_cell(Cell start, std::vector<Cell>* path = nullptr) const;

 private:
  struct Touched {
    std::uint32_t index;
    double old_lo, old_hi;
    bool old_observed;
  };
  void walk_beam(const Vec2& a, const Vec2& b, double za, double zb, std::uint32_t end_cell);
  void touch(std::uint32_t i);
  void refresh_occupancy(const CellRect& raw_changed, NodeMapUpdate& update);
  void refresh_expansion(const CellRect& raw_changed);
  std::int8_t occupancy_value(std::size_t i) const;
  std::int8_t raw_occupancy_value(std::size_t i) const;
  bool raw2d_value(std::size_t i) const { return evidence_[i] > 0 || (!static_.empty() && static_[i]); }

  GridGeometry geometry_;
  NodeMapParams params_;
  std::vector<std::uint8_t> evidence_;
  std::vector<double> lo_, hi_;
  ElevationMap elevation_;
  TerrainAnalysis analysis_;
  std::vector<std::uint8_t> raw2d_;
  std::vector<std::uint8_t> static_;  // prior obstacles (2D mode), empty when none
  std::vector<std::uint8_t> blocked_;
  OccupancyGrid occupancy_;
  OccupancyGrid raw_occupancy_;
  // Per-scan scratch: stamps say whether a cell was hit / contradicted in the current scan.
  std::uint32_t scan_ = 0;
  std::vector<std::uint32_t> hit_stamp_, miss_stamp_, touch_stamp_;
  std::vector<Touched> touched_;
  std::vector<std::uint8_t> tile_dirty_;
  std::vector<std::uint32_t> dirty_tiles_;
  std::vector<CellRect> dirty_rects_;
  std::vector<Vec3> pass_ends_;
  IncrementalInflation inflation_;  // the windowed expansion update
  bool any_evidence_ = false;
};

}  // namespace starnav
