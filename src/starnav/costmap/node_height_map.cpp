#include "starnav/costmap/node_height_map.hpp"

#include "starnav/core/error.hpp"

namespace starnav {

NodeHeightMap::Parts NodeHeightMap::make_parts(const GridGeometry& geometry, const NodeMapParams& params) {
  Parts p;
  auto prior = std::make_unique<StaticMapLayer>(geometry, std::vector<std::uint8_t>{});
  auto nodes = std::make_unique<NodeHeightLayer>(geometry, params);
  p.prior = prior.get();
  p.nodes = nodes.get();
  p.layers.push_back(std::move(prior));
  p.layers.push_back(std::move(nodes));
  return p;
}

NodeHeightMap::NodeHeightMap(const GridGeometry& geometry, const NodeMapParams& params)
    : NodeHeightMap(geometry, params, make_parts(geometry, params)) {}

NodeHeightMap::NodeHeightMap(const GridGeometry& geometry, const NodeMapParams& params, Parts parts)
    : LayeredCostmap(geometry, params, std::move(parts.layers)), prior_(parts.prior), nodes_(parts.nodes) {}

void NodeHeightMap::set_static_obstacles(std::span<const std::uint8_t> mask) {
  if (params().mode != NodeMapMode::Lidar2D)
    throw Error("a prior map needs the 2D map mode (map.mode lidar_2d)", {}, 0, "map.prior");
  prior_->set_obstacles(std::vector<std::uint8_t>(mask.begin(), mask.end()));
  rebuild();
}

}  // namespace starnav
