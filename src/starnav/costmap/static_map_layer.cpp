#include "starnav/costmap/static_map_layer.hpp"

#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

StaticMapLayer::StaticMapLayer(const GridGeometry& geometry, std::vector<std::uint8_t> mask) : geometry_(geometry) {
  set_obstacles(std::move(mask));
}

void StaticMapLayer::set_obstacles(std::vector<std::uint8_t> mask) {
  if (!mask.empty() && mask.size() != geometry_.cell_count())
    throw Error("the prior map's mask has " + std::to_string(mask.size()) + " cells, the grid " +
                    std::to_string(geometry_.cell_count()),
                {}, 0, "map.prior");
  mask_ = std::move(mask);
}

void StaticMapLayer::contribute(const CellRect& rect, std::span<std::uint8_t> obstacles, std::span<std::uint8_t>) const {
  or_mask_over(geometry_, mask_, rect, obstacles);
}

CostmapLayerDef static_map_layer() {
  CostmapLayerDef d;
  d.info.role = Role::CostmapLayer;
  d.info.name = "static_map";
  d.info.section = "static_map";
  d.info.summary = "The obstacles of navigation.map.prior (a map_server map), known before the run (Nav2's static layer)";
  d.info.capabilities = {Capability::PriorMap};
  d.make = [](const CostmapLayerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<CostmapLayer> {
    if (!settings.empty()) param_unknown_key(settings.front(), {});
    return std::make_unique<StaticMapLayer>(ctx.geometry, ctx.prior_obstacles);
  };
  return d;
}

}  // namespace starnav
