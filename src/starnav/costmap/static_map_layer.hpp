#pragma once
// The obstacles known before the run (navigation.map.prior: a map_server map of the building):
// cells that are obstacles whatever the scans say, expanded like sensed ones (Nav2's static
// layer). They do not count as observed: a free cell of the prior map stays unknown until a scan
// sees it (unknown cells are free for planning either way).
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/costmap/costmap_layer.hpp"

namespace starnav {

class StaticMapLayer final : public CostmapLayer {
 public:
  // `mask` row-major over `geometry`, non-zero = obstacle; empty: no obstacles (Error for another size).
  StaticMapLayer(const GridGeometry& geometry, std::vector<std::uint8_t> mask);
  std::string_view name() const override { return "static_map"; }
  void contribute(const CellRect& rect, std::span<std::uint8_t> obstacles, std::span<std::uint8_t> observed) const override;
  // New obstacles (the costmap must be rebuilt after).
  void set_obstacles(std::vector<std::uint8_t> mask);

 private:
  GridGeometry geometry_;
  std::vector<std::uint8_t> mask_;
};

}  // namespace starnav
