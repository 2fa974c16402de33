#pragma once
// The costmap-layer role (Nav2's costmap plugins; docs/navigation.md, "The navigation map"): one
// source of obstacles of the navigation map. The layered costmap (costmap/layered_costmap.hpp)
// keeps its layers in order; each takes the sensor data it wants and says which cells its
// contribution changed, and over those cells every layer ORs its obstacles and the cells it has
// observed into the master map, which the costmap then inflates and hands to the planner, the
// controller and the recoveries. A layer may also limit the robot's speed where it is
// (speed_limit_mps). Built by name from the registry (navigation.layers) with its
// declared parameters.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/core/component.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/grid_geometry.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/robot/robot_model.hpp"
#include "starnav/terrain/terrain_analysis.hpp"

namespace starnav {

// A scan placed in the map frame: the sensor's origin, its returns, and the end points of beams
// that returned nothing but cross open space up to there.
struct CostmapScan {
  Vec3 origin = Vec3::Zero();
  std::span<const Vec3> points;
  std::span<const Vec3> pass_ends;
};

// What the sensing layers did with one scan (summed over the layers).
struct CostmapScanStats {
  std::size_t returns_used = 0;        // returns inside the grid
  std::size_t cells_hit = 0;           // cells with at least one return
  std::size_t cells_contradicted = 0;  // cells a beam passed through against what they held
  std::size_t cells_cleared = 0;       // cells that became unobserved
  std::size_t cells_changed = 0;       // cells whose state changed
};

class CostmapLayer {
 public:
  virtual ~CostmapLayer() = default;
  virtual std::string_view name() const = 0;
  // One scan. Appends the rectangles of cells whose contribution changed (in an order the costmap
  // keeps) and adds to `stats`.
  virtual void on_scan(const CostmapScan& /*scan*/, std::vector<CellRect>& /*changed*/, CostmapScanStats& /*stats*/) {}
  // ORs this layer's obstacles (non-zero = obstacle) and observed cells over `rect` into the
  // master's row-major masks.
  virtual void contribute(const CellRect& rect, std::span<std::uint8_t> obstacles, std::span<std::uint8_t> observed) const = 0;
  // A layer that keeps heights (the 3D nodes): them, for pictures; null otherwise.
  virtual const ElevationMap* heights() const { return nullptr; }
  // A layer that limits the robot's speed (speed-limit zones, Nav2's speed filter): the lowest
  // limit (m/s, > 0) it sets anywhere on `area`, a polygon in the map frame (the robot's footprint
  // at its pose; touching counts); nothing where it sets none. The navigator lowers the
  // controller's translation limits to the lowest over the layers at every control step.
  virtual std::optional<double> speed_limit_mps(std::span<const Vec2> /*area*/) const { return std::nullopt; }
  // Re-derives whatever the layer keeps incrementally from its raw state (a from-scratch check of
  // the incremental updates; the costmap's rebuild() calls it).
  virtual void recompute() {}
};

// ORs a fixed row-major mask (one byte per cell of `geometry`, non-zero = obstacle) over `rect`
// into the master's obstacles: the contribution of every layer whose obstacles do not change.
inline void or_mask_over(const GridGeometry& geometry, std::span<const std::uint8_t> mask, const CellRect& rect,
                         std::span<std::uint8_t> obstacles) {
  if (mask.empty()) return;
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const std::size_t i = geometry.index(x, y);
      if (mask[i]) obstacles[i] = 1;
    }
}

enum class NodeMapMode : std::uint8_t {
  Nodes3D,  // min/max height per cell, Li 2019 criteria (3D LiDAR)
  Lidar2D,  // each return marks its cell occupied (2D LiDAR, paper Fig. 13)
};

// The navigation map's settings (navigation.map.*) the costmap and its layers read.
struct NodeMapParams {
  NodeMapMode mode = NodeMapMode::Nodes3D;
  LiNodeParams li;                   // max_step_m = k_step * cell size, max_slope_rad = atan(k_slope)
  double barrier_distance_m = 0.36;  // obstacle expansion radius (robot's circumscribed radius)
  bool clear = true;                 // beams clear the cells they pass through
  double clear_margin_m = 0.05;      // a beam contradicts a cell only when its highest point there is this far below the cell's max
  int hit_gain = 2;                  // evidence gained by a cell hit in a scan
  int miss_loss = 1;                 // evidence lost by a cell a beam contradicts in a scan
  int evidence_max = 4;              // cap: a stale cell is cleared after evidence_max / miss_loss scans
  double clearance_range_m = 2.0;    // the distance field (controllers, recoveries) is exact out to this
  void validate() const;             // Error naming the field
};

struct CostmapLayerContext {
  GridGeometry geometry;                      // the costmap's grid
  NodeMapParams map;                          // navigation.map.*
  std::vector<std::uint8_t> prior_obstacles;  // obstacles known before the run (navigation.map.prior), empty: none
  RobotConfig robot;
  std::string file;                           // the scenario (relative paths)
};
using CostmapLayerDef = ComponentDef<CostmapLayer, CostmapLayerContext>;

}  // namespace starnav
