#include "starnav/costmap/speed_limit_layer.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

struct SpeedLimitConfig {
  std::vector<ParamPolygon> zones;
  std::vector<double> limits_mps;
};

const ParamTable<SpeedLimitConfig>& speed_limit_params() {
  static const ParamTable<SpeedLimitConfig> t = [] {
    ParamTable<SpeedLimitConfig> t;
    t.polygons("zones", &SpeedLimitConfig::zones, "m",
               "areas of limited speed: polygons [[x, y], ...] in the map frame; the robot keeps to a zone's limit while any "
               "part of its footprint is inside");
    t.reals("limits_mps", &SpeedLimitConfig::limits_mps, positive(), "m/s",
            "the speed limit of each zone, one per zone in the order of zones; where zones overlap the lowest holds");
    return t;
  }();
  return t;
}

// Twice the signed area of (a, b, c): > 0 when c lies left of a -> b.
double orientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// `p`, collinear with a and b, within their bounding box (so on the closed segment).
bool within_box(const Vec2& p, const Vec2& a, const Vec2& b) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

// The closed segments a-b and c-d share a point.
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = orientation(c, d, a), d2 = orientation(c, d, b), d3 = orientation(a, b, c), d4 = orientation(a, b, d);
  if (((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))) return true;
  return (d1 == 0.0 && within_box(a, c, d)) || (d2 == 0.0 && within_box(b, c, d)) || (d3 == 0.0 && within_box(c, a, b)) ||
         (d4 == 0.0 && within_box(d, a, b));
}

// `p` on the boundary of `polygon` or inside it (even-odd); a polygon of one or two points is
// that point or segment.
bool inside_or_on(const Vec2& p, std::span<const Vec2> polygon) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vec2& a = polygon[j];
    const Vec2& b = polygon[i];
    if (orientation(a, b, p) == 0.0 && within_box(p, a, b)) return true;
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y())) inside = !inside;
  }
  return inside;
}

std::pair<Vec2, Vec2> bounding_box(std::span<const Vec2> polygon) {
  Vec2 lo = polygon.front(), hi = polygon.front();
  for (const Vec2& p : polygon) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}

}  // namespace

bool polygons_meet(std::span<const Vec2> a, std::span<const Vec2> b) {
  if (a.empty() || b.empty()) return false;
  // Either the boundaries cross, or one region holds a vertex of the other (then perhaps all of it).
  for (const Vec2& p : a)
    if (inside_or_on(p, b)) return true;
  for (const Vec2& p : b)
    if (inside_or_on(p, a)) return true;
  for (std::size_t i = 0, j = a.size() - 1; i < a.size(); j = i++)
    for (std::size_t k = 0, l = b.size() - 1; k < b.size(); l = k++)
      if (segments_meet(a[j], a[i], b[l], b[k])) return true;
  return false;
}

SpeedLimitLayer::SpeedLimitLayer(std::vector<SpeedZone> zones) : zones_(std::move(zones)) {
  for (const SpeedZone& z : zones_) {
    if (!(z.limit_mps > 0.0) || !std::isfinite(z.limit_mps)) throw Error("must be a finite number > 0", {}, 0, "limits_mps");
    if (z.polygon.size() < 3) throw Error("a zone needs at least 3 points", {}, 0, "zones");
  }
  // Lowest limit first: the first zone the footprint meets gives the answer.
  std::stable_sort(zones_.begin(), zones_.end(), [](const SpeedZone& x, const SpeedZone& y) { return x.limit_mps < y.limit_mps; });
  for (const SpeedZone& z : zones_) bounds_.push_back(bounding_box(z.polygon));
}

std::optional<double> SpeedLimitLayer::speed_limit_mps(std::span<const Vec2> area) const {
  if (area.empty()) return std::nullopt;
  const auto [lo, hi] = bounding_box(area);
  for (std::size_t i = 0; i < zones_.size(); ++i) {
    const auto& [zlo, zhi] = bounds_[i];
    if (hi.x() < zlo.x() || lo.x() > zhi.x() || hi.y() < zlo.y() || lo.y() > zhi.y()) continue;
    if (polygons_meet(area, zones_[i].polygon)) return zones_[i].limit_mps;
  }
  return std::nullopt;
}

CostmapLayerDef speed_limit_layer() {
  CostmapLayerDef d;
  d.info.role = Role::CostmapLayer;
  d.info.name = "speed_limit";
  d.info.section = "speed_limit";
  d.info.summary = "Speed-limit zones: polygons where the robot drives no faster than each zone's limit (Nav2's speed filter)";
  d.info.nav2_counterpart = "nav2_costmap_2d::SpeedFilter";
  d.info.params = speed_limit_params().specs();
  d.make = [](const CostmapLayerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<CostmapLayer> {
    const SpeedLimitConfig config = configured(speed_limit_params(), settings, ctx.file);
    try {
      if (config.limits_mps.size() != config.zones.size()) {
        const auto counted = [](std::size_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); };
        throw Error("gives " + counted(config.limits_mps.size(), "limit") + " for " + counted(config.zones.size(), "zone") +
                        " (one limit per zone, in the order of zones)",
                    {}, 0, "navigation.speed_limit.limits_mps");
      }
      std::vector<SpeedZone> zones;
      for (std::size_t i = 0; i < config.zones.size(); ++i) {
        SpeedZone& z = zones.emplace_back();
        for (const auto& xy : config.zones[i]) z.polygon.emplace_back(xy[0], xy[1]);
        z.limit_mps = config.limits_mps[i];
      }
      return std::make_unique<SpeedLimitLayer>(std::move(zones));
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
  };
  return d;
}

}  // namespace starnav
