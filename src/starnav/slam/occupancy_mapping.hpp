#pragma once
// Occupancy grid mapping with known poses (Thrun, Burgard, Fox, Probabilistic Robotics ch. 9;
// docs/papers/ren2022.md, Mapping): each beam lowers the log-odds of the cells it crosses and raises the one it
// ends in. The grid grows as the robot explores (no size given in advance).
//
// Per scan every cell is updated at most once (a hit wins over a pass-through), so a cell near the
// sensor, crossed by many beams of one scan, is not driven to "free" by that scan alone (as
// Cartographer's probability grids do). Beams are traced with an exact grid traversal
// (Amanatides and Woo 1987): a cell is crossed when the segment from the sensor to the reading
// passes through its interior. Readings below range_min are dropped; a reading at or beyond the
// scan's range_max returned nothing: with no_return_clear_m > 0 the beam still clears the cells up
// to that distance, else it is dropped. Readings beyond max_range_m (when > 0) are cut to it and
// clear only.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/logs/robot_log.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/sense/sensor_messages.hpp"

namespace starnav {

// The most cells a map built from scans may grow to (2^26, about 67 million: a cell takes 16
// bytes while the map is built, 1 GiB, and twice that while the grid grows; the Freiburg campus at
// 5 cm takes 37 million): a pose or a reading far off the map's scale is refused instead of
// allocating without bound, and so are parameters whose one scan would reach farther
// (OccupancyMappingParams::validate).
inline constexpr std::int64_t kMaxOccupancyMapCells = std::int64_t{1} << 26;
// Bytes of one cell of the map being built (OccupancyMapper::Cell).
inline constexpr std::size_t kOccupancyMapperCellBytes = 16;
// The farthest cell index from the origin a map may use (2^40: 5.5 million km at the finest 5 mm
// cells), so that a wild pose is refused before any index arithmetic could overflow.
inline constexpr double kMaxLatticeIndex = 1099511627776.0;

// The cells of side `resolution` (lattice corner at the origin) that the segment from `from` to
// `to` passes through, in order from the one holding `from` to the one holding `to` (visited last,
// with last = true): an exact traversal (Amanatides and Woo 1987); where the segment passes
// exactly through a cell corner it steps in y first.
template <class Visit>
void for_each_cell_on_segment(const Vec2& from, const Vec2& to, double resolution, Visit&& visit) {
  const double fx = from.x() / resolution, fy = from.y() / resolution, tx = to.x() / resolution, ty = to.y() / resolution;
  std::int64_t ix = static_cast<std::int64_t>(std::floor(fx)), iy = static_cast<std::int64_t>(std::floor(fy));
  const std::int64_t ex = static_cast<std::int64_t>(std::floor(tx)), ey = static_cast<std::int64_t>(std::floor(ty));
  const double dx = tx - fx, dy = ty - fy;
  const int sx = dx > 0 ? 1 : (dx < 0 ? -1 : 0), sy = dy > 0 ? 1 : (dy < 0 ? -1 : 0);
  constexpr double inf = std::numeric_limits<double>::infinity();
  // The segment parameter (0..1) at the next vertical and horizontal cell boundary.
  double t_x = sx > 0 ? (static_cast<double>(ix + 1) - fx) / dx : (sx < 0 ? (static_cast<double>(ix) - fx) / dx : inf);
  double t_y = sy > 0 ? (static_cast<double>(iy + 1) - fy) / dy : (sy < 0 ? (static_cast<double>(iy) - fy) / dy : inf);
  const double step_x = sx ? std::abs(1.0 / dx) : inf, step_y = sy ? std::abs(1.0 / dy) : inf;
  // Exactly |ex - ix| + |ey - iy| boundary crossings; rounding cannot make the walk longer.
  std::int64_t steps = std::abs(ex - ix) + std::abs(ey - iy);
  for (; steps > 0; --steps) {
    visit(ix, iy, false);
    if (t_x < t_y) {
      ix += sx;
      t_x += step_x;
    } else {
      iy += sy;
      t_y += step_y;
    }
  }
  visit(ex, ey, true);
}

struct OccupancyMappingParams {
  double resolution_m = 0.05;      // the paper's
  double hit_probability = 0.7;    // inverse sensor model at the reading
  double miss_probability = 0.4;   // ... along the beam before it
  double clamp_min_probability = 0.12;  // log-odds bounds, so a cell can change its mind
  double clamp_max_probability = 0.97;
  double max_range_m = 0.0;        // 0: no cut besides the scan's range_max
  double no_return_clear_m = 0.0;  // 0: no-return beams are dropped
  // Error naming the field; also when the beams of one scan that returned nothing, clearing
  // no_return_clear_m (cut to max_range_m) all round, would span more than kMaxOccupancyMapCells
  // cells of resolution_m.
  void validate() const;
};
// The declared parameters (keys as the members).
const ParamTable<OccupancyMappingParams>& occupancy_mapping_params();

// A cell whose class changed with one scan: its lattice index (the cell's corner is at
// (ix, iy) * resolution) and its new value as map_server's trinary reading of the written map
// gives it: 100 occupied (at least 65 %, the grid's rounded percent), 0 free (at most 20 %:
// map_saver's rint(100 x 0.196)), -1 neither (or never observed).
struct MapCellChange {
  std::int64_t ix = 0, iy = 0;
  std::int8_t value = -1;
};

class OccupancyMapper {
 public:
  explicit OccupancyMapper(const OccupancyMappingParams& params = {});

  // With tracking on, each scan records which cells changed class (last_changes()): what a
  // viewer replays to show the map growing. Off by default (it costs a list per scan).
  void track_changes(bool on) { track_ = on; }
  // The changes of the last scan, in the order the cells were first touched by it.
  const std::vector<MapCellChange>& last_changes() const { return changes_; }

  // One scan taken from `sensor_pose` (the laser's pose in the map frame).
  void add_scan(const Pose2& sensor_pose, const LogScan& scan);
  void add_scan(const Pose2& sensor_pose, const ScanMessage& scan);
  // Beams in the sensor frame: angle, range; `range_max` as LogScan's.
  void add_rays(const Pose2& sensor_pose, double angle_min, double angle_increment, const std::vector<float>& ranges,
                double range_min, double range_max);

  // The map: cells never observed unknown (-1), the others their occupancy probability in
  // percent (0..100). Its origin is the first observed cell's corner, on the resolution's lattice.
  // An empty mapper gives a 1 x 1 unknown grid at the origin.
  OccupancyGrid grid() const;
  std::size_t scans() const { return scans_; }
  double log_odds_at(const Vec2& world) const;  // 0 when never observed or outside

 private:
  struct Cell {
    float log_odds = 0.0f;
    float before_scan = 0.0f;     // log_odds before the current scan's update
    std::uint32_t last_scan = 0;  // scan number of the last update (0: never; scans count from 1)
    bool last_hit = false;
    bool observed() const { return last_scan != 0; }
  };
  Cell& cell(std::int64_t ix, std::int64_t iy);  // grows the grid
  // Throws Error (field resolution_m) when the segment lies beyond kMaxLatticeIndex or the map
  // would need more than kMaxOccupancyMapCells cells to hold it: before any cell is touched.
  void check_reach(const Vec2& from, const Vec2& to) const;
  void update(std::int64_t ix, std::int64_t iy, bool hit);
  void trace(const Vec2& from, const Vec2& to, bool hit);
  // Beam i: range(i), at angle(i) from +x in the map frame.
  template <class Range, class Angle>
  void add_beams(const Pose2& sensor_pose, std::size_t beams, Range range, Angle angle, double range_min, double range_max);

  OccupancyMappingParams params_;
  float hit_ = 0, miss_ = 0, lo_ = 0, hi_ = 0;
  // Cells of [x0, x0 + w) x [y0, y0 + h) on the lattice of cells of `resolution` with corner (0, 0).
  std::int64_t x0_ = 0, y0_ = 0, w_ = 0, h_ = 0;
  std::vector<Cell> cells_;
  std::uint32_t scans_ = 0;
  // Change tracking: the cells first touched by the current scan (lattice index, observed before).
  struct Touched {
    std::int64_t ix, iy;
    bool observed_before;
  };
  bool track_ = false;
  std::vector<Touched> touched_;
  std::vector<MapCellChange> changes_;
  void collect_changes();
  static_assert(sizeof(Cell) == kOccupancyMapperCellBytes);
};

}  // namespace starnav
