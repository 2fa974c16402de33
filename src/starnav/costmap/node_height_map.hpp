#pragma once
// The navigation map of Li et al. 2019 as one object (docs/navigation.md): a layered costmap of the
// static layer (the prior map's obstacles) and the node-height layer, the default composition a
// scenario gets, with both layers' own state at hand for tests and tools.
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/costmap/layered_costmap.hpp"
#include "starnav/costmap/node_height_layer.hpp"
#include "starnav/costmap/static_map_layer.hpp"

namespace starnav {

class NodeHeightMap : public LayeredCostmap {
 public:
  // All cells unobserved. Throws Error for a bad geometry (y_down grids are not metric) or params.
  explicit NodeHeightMap(const GridGeometry& geometry, const NodeMapParams& params = {});

  int evidence(int x, int y) const { return nodes_->evidence(x, y); }
  // min / max heights of the observed cells (heights are 0 in 2D mode): height = mid.
  const ElevationMap& elevation() const { return nodes_->elevation(); }
  // Valid in Nodes3D mode only.
  const TerrainAnalysis& analysis() const { return nodes_->analysis(); }
  // Obstacles known before the run: cells blocked whatever the scans say, expanded like sensed
  // ones. `mask` is row-major over the grid, non-zero = obstacle. 2D mode only (Error naming
  // "map.prior" otherwise, or for a mask of another size).
  void set_static_obstacles(std::span<const std::uint8_t> mask);

 private:
  struct Parts {
    std::vector<std::unique_ptr<CostmapLayer>> layers;
    StaticMapLayer* prior = nullptr;
    NodeHeightLayer* nodes = nullptr;
  };
  static Parts make_parts(const GridGeometry& geometry, const NodeMapParams& params);
  NodeHeightMap(const GridGeometry& geometry, const NodeMapParams& params, Parts parts);

  StaticMapLayer* prior_;
  NodeHeightLayer* nodes_;
};

}  // namespace starnav
