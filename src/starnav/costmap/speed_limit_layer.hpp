#pragma once
// Speed-limit zones (Nav2's speed filter, from polygons rather than a mask map): areas where the
// robot may drive no faster than a limit, given as polygons in the map frame, each with its limit
// in m/s (navigation.speed_limit.zones and limits_mps). The layer adds no obstacle and observes
// nothing; at every control step the navigator asks it for the lowest limit among the zones the
// robot's footprint meets and lowers the controller's translation limits to it, so that the
// whole body, not only its centre, keeps to the limit inside a zone (docs/navigation.md,
// "Speed-limit zones"). Overlapping zones: the lowest limit holds.
#include <optional>
#include <span>
#include <vector>

#include "starnav/core/params.hpp"
#include "starnav/costmap/costmap_layer.hpp"

namespace starnav {

// True when the closed regions of polygons `a` and `b` (each closing itself, inside by the
// even-odd rule; a single point or a segment is a region too) share a point: an edge of one
// meets an edge of the other, or a vertex of one lies inside or on the other.
bool polygons_meet(std::span<const Vec2> a, std::span<const Vec2> b);

struct SpeedZone {
  std::vector<Vec2> polygon;  // map frame
  double limit_mps = 0.0;     // > 0
};

class SpeedLimitLayer final : public CostmapLayer {
 public:
  // Error naming the field for a limit that is not a finite number > 0.
  explicit SpeedLimitLayer(std::vector<SpeedZone> zones);
  std::string_view name() const override { return "speed_limit"; }
  void contribute(const CellRect& /*rect*/, std::span<std::uint8_t> /*obstacles*/, std::span<std::uint8_t> /*observed*/) const override {}
  std::optional<double> speed_limit_mps(std::span<const Vec2> area) const override;
  const std::vector<SpeedZone>& zones() const { return zones_; }  // lowest limit first

 private:
  std::vector<SpeedZone> zones_;
  std::vector<std::pair<Vec2, Vec2>> bounds_;  // each zone's bounding box (min, max corners)
};

}  // namespace starnav
