#pragma once
// One entry point for every map file starnav reads: format detection by name and content,
// load into an occupancy grid or an elevation map, save in another format.
#include <optional>
#include <string>
#include <vector>
#include <variant>

#include "starnav/io/movingai.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav {

enum class MapFormat { MovingAi, RosMap, ElevationYaml, Asc, Csv, UnityRaw, GeoTiff };

const char* map_format_name(MapFormat f);  // "movingai", "ros_map", "elevation_png", "asc", "csv", "unity_raw", "geotiff"

// By extension, and for .yaml by its keys (z_min/z_max: elevation; occupied_thresh: map_server).
// Throws Error for an unknown extension or a YAML that is neither.
MapFormat detect_map_format(const std::string& path);

struct LoadedMap {
  MapFormat format = MapFormat::MovingAi;
  std::variant<OccupancyGrid, ElevationMap> map;
  std::optional<MovingAiMap> movingai;     // the original characters, for MovingAI maps
  std::optional<RosMapMetadata> ros;       // thresholds and mode, for map_server maps
  std::vector<std::string> files;          // every file read: the one named, then its companions

  bool is_elevation() const { return std::holds_alternative<ElevationMap>(map); }
  const OccupancyGrid& occupancy() const { return std::get<OccupancyGrid>(map); }
  const ElevationMap& elevation() const { return std::get<ElevationMap>(map); }
  const GridGeometry& geometry() const;
  // Thresholds the map's own file asks for (map_server thresholds), else the defaults.
  OccupancyThresholds thresholds() const;
};

LoadedMap load_map(const std::string& path);

// The format a map is written in, by the output's extension: .yaml (map_server, or a 16-bit PNG
// with its YAML for an elevation map), .map, .asc, .csv, .raw/.r16, .tif/.tiff (refused when
// writing). Throws Error(path) for another extension.
MapFormat output_map_format(const std::string& path, bool elevation);

// Throws Error(path) unless `format` suits the map (occupancy formats for occupancy grids,
// elevation formats for elevation maps) and starnav writes it: what a command checks first.
void check_map_writable(const LoadedMap& map, const std::string& path, MapFormat format);
// Saves `map` as `format`; check_map_writable's errors otherwise.
void save_map(const LoadedMap& map, const std::string& path, MapFormat format);
// What writing `map` as `format` loses, one sentence each (empty when nothing): a MovingAI .map
// keeps neither origin, yaw nor resolution and has no unknown cells; an elevation CSV keeps no
// origin or resolution. A command prints them as warnings before writing. check_map_writable's
// errors (without a path) for a format that does not suit the map.
std::vector<std::string> map_conversion_losses(const LoadedMap& map, MapFormat format);
// Every file save_map writes for `path`, the named one first, then its companions: the image
// beside a map_server YAML, the PNG beside an elevation YAML, the sidecar of a Unity RAW. A
// command checks them all before writing any. `ros`: the metadata a map_server map keeps (its
// mode chooses the image's format).
std::vector<std::string> map_output_files(const std::string& path, MapFormat format,
                                          const std::optional<RosMapMetadata>& ros = std::nullopt);

}  // namespace starnav
