#include "starnav/costmap/keepout_layer.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

struct KeepoutConfig {
  std::vector<ParamPolygon> zones;
};

const ParamTable<KeepoutConfig>& keepout_params() {
  static const ParamTable<KeepoutConfig> t = [] {
    ParamTable<KeepoutConfig> t;
    t.polygons("zones", &KeepoutConfig::zones, "m",
               "areas the robot must not enter: polygons [[x, y], ...] in the map frame; every cell a zone overlaps is an "
               "obstacle, expanded like sensed ones");
    return t;
  }();
  return t;
}

// Marks the cells of row `row` whose open column interval (c, c + 1) meets the open interval
// (xa, xb), or contains x when xa == xb; clipped to the grid.
void mark_span(std::vector<std::uint8_t>& mask, const GridGeometry& g, int row, double xa, double xb) {
  if (row < 0 || row >= g.height) return;
  if (xa > xb) std::swap(xa, xb);
  int c0 = 0, c1 = 0;
  if (xa < xb) {
    c0 = GridGeometry::floor_to_int(xa);
    c1 = GridGeometry::floor_to_int(std::ceil(xb) - 1.0);
  } else {
    if (xa == std::floor(xa)) return;  // on a column line: inside no cell
    c0 = c1 = GridGeometry::floor_to_int(xa);
  }
  c0 = std::max(c0, 0);
  c1 = std::min(c1, g.width - 1);
  for (int c = c0; c <= c1; ++c) mask[g.index(c, row)] = 1;
}

}  // namespace

void mark_polygon_cells(const GridGeometry& geometry, std::span<const Vec2> polygon, std::vector<std::uint8_t>& mask) {
  const std::size_t n = polygon.size();
  if (n < 3 || mask.size() != geometry.cell_count() || mask.empty()) return;
  // In continuous cell coordinates the cells are unit squares, whatever the grid's yaw.
  std::vector<Vec2> p(n);
  // A vertex written on a cell line (2.0 m on a 0.05 m grid) lands a rounding error off it: snap
  // it back, so that the cell beyond the line is not taken for a sliver of 1e-15 of its area.
  const auto snap = [](double v) {
    const double r = std::round(v);
    return std::abs(v - r) < 1e-9 ? r : v;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 c = geometry.world_to_cell_continuous(polygon[i]);
    p[i] = Vec2(snap(c.x()), snap(c.y()));
  }

  // A cell overlaps the polygon (with some area) when its centre lies inside, or when the
  // boundary crosses the cell's open square: two passes.
  // The boundary: per row, the part of each edge inside the row's open band spans a range of columns.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % n];
    const double ylo = std::min(a.y(), b.y()), yhi = std::max(a.y(), b.y());
    const int r0 = std::max(0, GridGeometry::floor_to_int(ylo));
    const int r1 = std::min(geometry.height - 1, GridGeometry::floor_to_int(yhi));
    for (int r = r0; r <= r1; ++r) {
      if (a.y() == b.y()) {
        if (a.y() > r && a.y() < r + 1) mark_span(mask, geometry, r, a.x(), b.x());
        continue;
      }
      const double band_lo = std::max(ylo, static_cast<double>(r)), band_hi = std::min(yhi, static_cast<double>(r + 1));
      if (!(band_lo < band_hi)) continue;
      const auto x_at = [&](double y) { return a.x() + (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()); };
      mark_span(mask, geometry, r, x_at(band_lo), x_at(band_hi));
    }
  }

  // The interior: cells whose centre lies inside (even-odd crossings of the row's centre line).
  std::vector<double> crossings;
  const auto by_y = [](const Vec2& u, const Vec2& v) { return u.y() < v.y(); };
  const int r0 = std::max(0, GridGeometry::floor_to_int(std::min_element(p.begin(), p.end(), by_y)->y()));
  const int r1 = std::min(geometry.height - 1, GridGeometry::floor_to_int(std::max_element(p.begin(), p.end(), by_y)->y()));
  for (int r = r0; r <= r1; ++r) {
    const double yc = r + 0.5;
    crossings.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = p[i], b = p[(i + 1) % n];
      if ((a.y() <= yc) != (b.y() <= yc)) crossings.push_back(a.x() + (b.x() - a.x()) * (yc - a.y()) / (b.y() - a.y()));
    }
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
      // The cells whose centre c + 0.5 lies within [xa, xb].
      const int first = std::max(0, GridGeometry::floor_to_int(std::ceil(crossings[k] - 0.5)));
      const int last = std::min(geometry.width - 1, GridGeometry::floor_to_int(std::floor(crossings[k + 1] - 0.5)));
      for (int c = first; c <= last; ++c) mask[geometry.index(c, r)] = 1;
    }
  }
}

std::vector<std::uint8_t> rasterize_polygon_cells(const GridGeometry& geometry, std::span<const Vec2> polygon) {
  check_rasterizing_cost(geometry, {&polygon, 1});
  std::vector<std::uint8_t> mask(geometry.cell_count(), 0);
  mark_polygon_cells(geometry, polygon, mask);
  return mask;
}

void check_rasterizing_cost(const GridGeometry& geometry, std::span<const std::span<const Vec2>> polygons) {
  // Each edge visits the rows it spans twice (its boundary, the crossings of the centre lines): a
  // polygon of many edges each spanning a huge grid is refused before the work.
  double visits = 0.0;
  for (const std::span<const Vec2> polygon : polygons)
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const double span = (polygon[i] - polygon[(i + 1) % polygon.size()]).norm() / geometry.resolution;  // rows, whatever the yaw
      visits += 2.0 + 2.0 * std::min(span, static_cast<double>(geometry.height));
    }
  if (visits > kMaxRasterizedEdgeRows)
    throw Error(std::string("the polygons' edges span ")
                    .append(std::to_string(static_cast<long long>(visits / 2.0)))
                    .append(" grid rows in all, above ")
                    .append(std::to_string(static_cast<long long>(kMaxRasterizedEdgeRows / 2.0)))
                    .append(" (fewer or smaller polygons)"),
                {}, 0, "zones");
}

KeepoutLayer::KeepoutLayer(const GridGeometry& geometry, const std::vector<ParamPolygon>& zones)
    : geometry_(geometry) {
  std::vector<std::vector<Vec2>> polygons;
  for (const ParamPolygon& zone : zones) {
    std::vector<Vec2>& polygon = polygons.emplace_back();
    for (const auto& xy : zone) polygon.emplace_back(xy[0], xy[1]);
  }
  const std::vector<std::span<const Vec2>> views(polygons.begin(), polygons.end());
  check_rasterizing_cost(geometry_, views);
  mask_.assign(geometry_.cell_count(), 0);
  for (const std::vector<Vec2>& polygon : polygons) mark_polygon_cells(geometry_, polygon, mask_);
}

void KeepoutLayer::contribute(const CellRect& rect, std::span<std::uint8_t> obstacles, std::span<std::uint8_t>) const {
  or_mask_over(geometry_, mask_, rect, obstacles);
}

CostmapLayerDef keepout_layer() {
  CostmapLayerDef d;
  d.info.role = Role::CostmapLayer;
  d.info.name = "keepout";
  d.info.section = "keepout";
  d.info.summary = "Keep-out zones: polygons the robot must not enter, obstacles of the navigation map (Nav2's keepout filter)";
  d.info.nav2_counterpart = "nav2_costmap_2d::KeepoutFilter";
  d.info.params = keepout_params().specs();
  d.make = [](const CostmapLayerContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<CostmapLayer> {
    const KeepoutConfig config = configured(keepout_params(), settings, ctx.file);
    try {
      return std::make_unique<KeepoutLayer>(ctx.geometry, config.zones);
    } catch (const Error& e) {
      rethrow_at_setting(e, settings, ctx.file);
    }
  };
  return d;
}

}  // namespace starnav
