#pragma once
// Maps as rasters, one pixel per cell: occupancy as greys, elevation as a colour ramp times a
// hillshade. Rows are in file order, top row first: row r holds iy = height - 1 - r for metric
// (y-up) grids and iy = r for index grids (y_down), so the raster looks like the map's image
// file.
#include <optional>
#include <vector>

#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/viz/colour.hpp"
#include "starnav/viz/raster.hpp"

namespace starnav::viz {

// The light of a hillshade: it comes from `azimuth_deg` measured clockwise from the picture's
// up direction (+y of the world for metric maps, -y for y_down index grids), so 315 lights
// from the upper left as cartographers do, and `altitude_deg` above the horizon. Heights are
// multiplied by `z_factor` (vertical exaggeration).
struct HillshadeOptions {
  double azimuth_deg = 315.0;
  double altitude_deg = 45.0;
  double z_factor = 1.0;
};

// Per cell, the cosine between the surface normal and the direction to the light, clamped to
// [0, 1] (Lambert); NaN for unobserved cells. Slopes are central differences of observed
// neighbours (one-sided at borders and next to unobserved cells; flat when a cell has no
// observed neighbour along an axis), in metres per metre and turned by the origin yaw, so a
// plane gets the same shade everywhere. Flat ground gets sin(altitude). Throws Error for
// non-finite options or an altitude outside (0, 90] degrees.
std::vector<float> hillshade(const ElevationMap& map, const HillshadeOptions& options = {});

// How elevation maps are coloured: height -> viridis over `range` (default: the map's observed
// height range; a zero-width range is widened by 0.5 m each way), times
// (1 - strength) + strength * shade / sin(altitude), so flat ground keeps the ramp's colour
// (and the legend's) while slopes facing the light brighten and the others darken.
struct ElevationStyle {
  std::optional<HeightRange> range{};
  bool hillshade = true;
  double hillshade_strength = 0.6;  // 0 = plain ramp
  HillshadeOptions light{};
  Rgba unobserved{0, 0, 0, 0};  // transparent: the picture's background shows through
};

// The height range the ramp spans for `map` with `style`; nothing when no cell is observed and
// the style gives no range. Throws Error for a non-finite or inverted range in the style.
std::optional<HeightRange> elevation_colour_range(const ElevationMap& map, const ElevationStyle& style = {});

RgbaImage occupancy_raster(const OccupancyGrid& grid, const OccupancyPalette& palette = {});
RgbaImage elevation_raster(const ElevationMap& map, const ElevationStyle& style = {});

}  // namespace starnav::viz
