#include "starnav/viz/map_raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav::viz {

namespace {

// Image row of grid row iy (file order, top row first).
int raster_row(const GridGeometry& g, int iy) { return g.y_down ? iy : g.height - 1 - iy; }

}  // namespace

std::vector<float> hillshade(const ElevationMap& map, const HillshadeOptions& o) {
  if (!std::isfinite(o.azimuth_deg)) throw Error("hillshade azimuth must be finite", {}, 0, "azimuth_deg");
  if (!(o.altitude_deg > 0.0 && o.altitude_deg <= 90.0))
    throw Error("hillshade altitude must be in (0, 90] degrees", {}, 0, "altitude_deg");
  if (!std::isfinite(o.z_factor)) throw Error("hillshade z factor must be finite", {}, 0, "z_factor");
  const GridGeometry& g = map.geometry();
  const int w = map.width(), h = map.height();
  std::vector<float> out(map.cell_count(), std::numeric_limits<float>::quiet_NaN());
  if (out.empty()) return out;

  // Direction to the light in the world: azimuth clockwise from the picture's up direction.
  const double az = deg_to_rad(o.azimuth_deg), alt = deg_to_rad(o.altitude_deg);
  const double up = g.y_down ? -1.0 : 1.0;
  const Vec2 light_world(std::cos(alt) * std::sin(az), up * std::cos(alt) * std::cos(az));
  // The same direction in the grid frame (the grid is the world turned by the origin yaw).
  const Vec2 light_grid = g.origin.rotation().transpose() * light_world;
  const double lx = light_grid.x(), ly = light_grid.y(), lz = std::sin(alt);
  const double res = g.resolution;

  auto observed = [&](int x, int y) { return map.contains(x, y) && map.observed_at(x, y); };
  // Slope along one axis at (x, y), in metres per metre of the grid frame.
  auto slope = [&](int x, int y, int dx, int dy) {
    const bool lo = observed(x - dx, y - dy), hi = observed(x + dx, y + dy);
    const double z = map.height_at(x, y);
    if (lo && hi) return (map.height_at(x + dx, y + dy) - map.height_at(x - dx, y - dy)) / (2.0 * res);
    if (hi) return (map.height_at(x + dx, y + dy) - z) / res;
    if (lo) return (z - map.height_at(x - dx, y - dy)) / res;
    return 0.0;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!map.observed_at(x, y)) continue;
      const double sx = o.z_factor * slope(x, y, 1, 0), sy = o.z_factor * slope(x, y, 0, 1);
      // Normal of z = f(x, y): (-sx, -sy, 1) / |.|
      const double n = std::sqrt(sx * sx + sy * sy + 1.0);
      const double shade = (-sx * lx - sy * ly + lz) / n;
      out[g.index(x, y)] = static_cast<float>(std::clamp(shade, 0.0, 1.0));
    }
  return out;
}

std::optional<HeightRange> elevation_colour_range(const ElevationMap& map, const ElevationStyle& style) {
  std::optional<HeightRange> r = style.range;
  if (r) {
    if (!std::isfinite(r->min) || !std::isfinite(r->max) || r->max < r->min)
      throw Error("colour range needs finite heights with min <= max", {}, 0, "range");
  } else {
    r = map.height_range();
  }
  if (r && r->max - r->min <= 0.0) {
    r->min -= 0.5;
    r->max += 0.5;
  }
  return r;
}

RgbaImage occupancy_raster(const OccupancyGrid& grid, const OccupancyPalette& palette) {
  const GridGeometry& g = grid.geometry();
  RgbaImage img(g.width, g.height);
  // One colour per occupancy value.
  std::array<Rgba, 256> lut{};
  for (int v = -128; v < 128; ++v)
    lut[static_cast<std::size_t>(v + 128)] = occupancy_colour(static_cast<std::int8_t>(v), palette);
  for (int iy = 0; iy < g.height; ++iy) {
    const int row = raster_row(g, iy);
    for (int ix = 0; ix < g.width; ++ix) img.set(ix, row, lut[static_cast<std::size_t>(grid(ix, iy) + 128)]);
  }
  return img;
}

RgbaImage elevation_raster(const ElevationMap& map, const ElevationStyle& style) {
  if (!(style.hillshade_strength >= 0.0 && style.hillshade_strength <= 1.0))
    throw Error("hillshade strength must be in [0, 1]", {}, 0, "hillshade_strength");
  const GridGeometry& g = map.geometry();
  RgbaImage img(g.width, g.height, style.unobserved);
  const auto range = elevation_colour_range(map, style);
  if (!range) return img;  // nothing observed
  std::vector<float> shade;
  if (style.hillshade && style.hillshade_strength > 0.0) shade = hillshade(map, style.light);
  const double flat = std::sin(deg_to_rad(style.light.altitude_deg));
  const double span = range->max - range->min;
  for (int iy = 0; iy < g.height; ++iy) {
    const int row = raster_row(g, iy);
    for (int ix = 0; ix < g.width; ++ix) {
      if (!map.observed_at(ix, iy)) continue;
      const std::size_t i = g.index(ix, iy);
      Rgba c = viridis((map.height_at_index(i) - range->min) / span);
      if (!shade.empty()) {
        const double f = (1.0 - style.hillshade_strength) + style.hillshade_strength * shade[i] / flat;
        c = {channel_byte(c.r * f), channel_byte(c.g * f), channel_byte(c.b * f), 255};
      }
      img.set(ix, row, c);
    }
  }
  return img;
}

}  // namespace starnav::viz
