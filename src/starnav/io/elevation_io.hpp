#pragma once
// Elevation map files (conventions.md, "Files"): 16-bit PNG + YAML sidecar, ESRI ASCII grid,
// CSV, Unity RAW, and GeoTIFF through GDAL when built with it.
#include <string>
#include <string_view>

#include "starnav/map/elevation_map.hpp"

namespace starnav {

// PNG16 + YAML (keys image, resolution, origin [x, y, yaw], z_min, z_max, optional nodata: the
// 16-bit value that marks unobserved cells). height = z_min + v / 65535 * (z_max - z_min).
ElevationMap read_elevation_yaml(const std::string& yaml_path);
// Quantises heights to 16 bit over the observed range; unobserved cells get the nodata value
// 0 (and observed heights use 1..65535) when any cell is unobserved.
void write_elevation_yaml(const ElevationMap& map, const std::string& yaml_path);

// ESRI ASCII grid. Honours NODATA_value, xllcorner/yllcorner and xllcenter/yllcenter.
ElevationMap parse_asc(std::string_view text, const std::string& source);
ElevationMap read_asc(const std::string& path);
void write_asc(const ElevationMap& map, const std::string& path);

// CSV: one row of comma-separated heights per grid row, top row first, empty field for an
// unobserved cell; no geometry (resolution and origin are given when reading).
ElevationMap parse_elevation_csv(std::string_view text, const std::string& source, double resolution = 1.0,
                                 Pose2 origin = {});
ElevationMap read_elevation_csv(const std::string& path, double resolution = 1.0, Pose2 origin = {});
void write_elevation_csv(const ElevationMap& map, const std::string& path);

// Unity terrain RAW: 16-bit little-endian, rows bottom first, square 2^n + 1 (padded by edge
// replication, with a warning on stderr when padding). Heights quantised over the observed
// range; the range is written to a sidecar `<path>.yaml` (resolution, origin, z_min, z_max,
// size, and the unpadded width/height) so the export reads back.
void write_unity_raw(const ElevationMap& map, const std::string& path);
ElevationMap read_unity_raw(const std::string& path);

// GeoTIFF through GDAL (first band, nodata honoured, geotransform -> resolution and origin).
// Throws Error when starnav was built without GDAL.
ElevationMap read_geotiff(const std::string& path);

}  // namespace starnav
