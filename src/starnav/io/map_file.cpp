#include "starnav/io/map_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/elevation_io.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/yaml_document.hpp"

namespace starnav {

namespace {

// A .yaml is an elevation sidecar when it has z_min/z_max, a map_server map when it has
// occupied_thresh (conventions.md).
MapFormat detect_yaml_kind(const std::string& path) {
  if (!std::filesystem::exists(path)) throw Error("file not found", path);
  const YAML::Node root = load_yaml_document(read_yaml_file(path), path);
  if (!root.IsMap()) throw Error("expected a YAML mapping of keys", path);
  if (root["z_min"] || root["z_max"]) return MapFormat::ElevationYaml;
  if (root["occupied_thresh"] || root["free_thresh"] || root["negate"]) return MapFormat::RosMap;
  throw Error("neither an elevation map (z_min, z_max) nor a map_server map (occupied_thresh)", path);
}

}  // namespace

const char* map_format_name(MapFormat f) {
  switch (f) {
    case MapFormat::MovingAi: return "movingai";
    case MapFormat::RosMap: return "ros_map";
    case MapFormat::ElevationYaml: return "elevation_png";
    case MapFormat::Asc: return "asc";
    case MapFormat::Csv: return "csv";
    case MapFormat::UnityRaw: return "unity_raw";
    case MapFormat::GeoTiff: return "geotiff";
  }
  return "unknown";
}

MapFormat detect_map_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".map") return MapFormat::MovingAi;
  if (ext == ".yaml" || ext == ".yml") return detect_yaml_kind(path);
  if (ext == ".asc") return MapFormat::Asc;
  if (ext == ".csv") return MapFormat::Csv;
  if (ext == ".raw" || ext == ".r16") return MapFormat::UnityRaw;
  if (ext == ".tif" || ext == ".tiff") return MapFormat::GeoTiff;
  throw Error("unknown map format (expected .map, .yaml, .asc, .csv, .raw, .tif)", path);
}

const GridGeometry& LoadedMap::geometry() const {
  return is_elevation() ? elevation().geometry() : occupancy().geometry();
}

OccupancyThresholds LoadedMap::thresholds() const {
  OccupancyThresholds t;
  if (ros) {
    // map_server already applied its thresholds when it turned pixels into 0/100/-1 (trinary)
    // or 0..99 (scale); what remains is to read those values back with the same cut-offs.
    t.occupied_percent = ros->occupied_thresh * 100.0;
    t.free_percent = ros->free_thresh * 100.0;
  }
  return t;
}

LoadedMap load_map(const std::string& path) {
  const InputFileScope reading_path(path);
  LoadedMap out;
  out.format = detect_map_format(path);
  out.files = {path};
  switch (out.format) {
    case MapFormat::MovingAi: {
      MovingAiMap m = read_movingai_map(path);
      out.map = m.to_occupancy();
      out.movingai = std::move(m);
      break;
    }
    case MapFormat::RosMap: {
      RosMapMetadata meta;
      out.map = read_ros_map(path, &meta);
      out.ros = meta;
      out.files.push_back(ros_map_image_path(path, meta.image));
      break;
    }
    case MapFormat::ElevationYaml: {
      std::string companion;
      out.map = read_elevation_yaml(path, &companion);
      if (!companion.empty()) out.files.push_back(companion);
      break;
    }
    case MapFormat::Asc: {
      out.map = read_asc(path);
      for (const char* ext : {".prj", ".PRJ"}) {
        std::filesystem::path prj(path);
        prj.replace_extension(ext);
        std::error_code ec;
        if (std::filesystem::is_regular_file(prj, ec)) out.files.push_back(prj.string());
      }
      break;
    }
    case MapFormat::Csv: out.map = read_elevation_csv(path); break;
    case MapFormat::UnityRaw:
      out.map = read_unity_raw(path);
      out.files.push_back(unity_raw_sidecar_path(path));
      break;
    case MapFormat::GeoTiff: out.map = read_geotiff(path); break;
  }
  return out;
}

void check_map_writable(const LoadedMap& map, const std::string& path, MapFormat format) {
  const bool elevation_format = format == MapFormat::ElevationYaml || format == MapFormat::Asc ||
                                format == MapFormat::Csv || format == MapFormat::UnityRaw ||
                                format == MapFormat::GeoTiff;
  if (elevation_format != map.is_elevation())
    throw Error(std::string("cannot write ") + (map.is_elevation() ? "an elevation map" : "an occupancy grid") +
                    " as " + map_format_name(format),
                path);
  if (format == MapFormat::GeoTiff) throw Error("writing GeoTIFF is not supported (read only)", path);
}

void save_map(const LoadedMap& map, const std::string& path, MapFormat format) {
  check_map_writable(map, path, format);
  switch (format) {
    case MapFormat::MovingAi:
      if (map.movingai)
        write_movingai_map(*map.movingai, path);
      else
        write_movingai_map(MovingAiMap::from_occupancy(map.occupancy(), map.thresholds()), path);
      return;
    case MapFormat::RosMap: {
      RosMapMetadata meta = map.ros.value_or(RosMapMetadata{});
      meta.image.clear();  // write the image beside the new YAML, named after it
      meta.resolution = map.occupancy().resolution();
      meta.origin = map.occupancy().origin();
      write_ros_map(map.occupancy(), path, meta);
      return;
    }
    case MapFormat::ElevationYaml: write_elevation_yaml(map.elevation(), path); return;
    case MapFormat::Asc: write_asc(map.elevation(), path); return;
    case MapFormat::Csv: write_elevation_csv(map.elevation(), path); return;
    case MapFormat::UnityRaw: write_unity_raw(map.elevation(), path); return;
    case MapFormat::GeoTiff: throw Error("writing GeoTIFF is not supported (read only)", path);
  }
}

std::vector<std::string> map_conversion_losses(const LoadedMap& map, MapFormat format) {
  check_map_writable(map, {}, format);
  std::vector<std::string> losses;
  const GridGeometry& g = map.geometry();
  const bool placed = g.origin.x != 0.0 || g.origin.y != 0.0 || g.origin.yaw != 0.0;
  if (format == MapFormat::MovingAi && map.format != MapFormat::MovingAi) {
    if (placed) losses.push_back("a .map keeps no origin or yaw: the map's origin (" + format_number(g.origin.x) + ", " +
                                 format_number(g.origin.y) + ", yaw " + format_number(g.origin.yaw) + " rad) is dropped");
    if (g.resolution != 1.0)
      losses.push_back("a .map keeps no resolution: its cells are read back as 1 unit, not " + format_number(g.resolution) + " m");
    const OccupancyCounts counts = map.occupancy().counts(map.thresholds());
    if (counts.unknown > 0)
      losses.push_back("a .map has no unknown cells: " + std::to_string(counts.unknown) + " unknown cells become obstacles ('@')");
  }
  if (format == MapFormat::Csv && map.format != MapFormat::Csv && (placed || g.resolution != 1.0))
    losses.push_back("an elevation CSV keeps no origin or resolution: it reads back with resolution 1 m at the origin");
  return losses;
}

std::vector<std::string> map_output_files(const std::string& path, MapFormat format, const std::optional<RosMapMetadata>& ros) {
  std::vector<std::string> files{path};
  switch (format) {
    case MapFormat::RosMap: {
      const bool scale = ros && ros->mode == RosMapMode::Scale;
      files.push_back(ros_map_image_path(path, std::filesystem::path(path).stem().string() + (scale ? ".png" : ".pgm")));
      break;
    }
    case MapFormat::ElevationYaml: files.push_back(elevation_yaml_image_path(path)); break;
    case MapFormat::UnityRaw: files.push_back(unity_raw_sidecar_path(path)); break;
    default: break;
  }
  return files;
}

MapFormat output_map_format(const std::string& path, bool elevation) {
  const std::string ext = lower_extension(path);
  if (ext == ".yaml" || ext == ".yml") return elevation ? MapFormat::ElevationYaml : MapFormat::RosMap;
  if (ext == ".map") return MapFormat::MovingAi;
  if (ext == ".asc") return MapFormat::Asc;
  if (ext == ".csv") return MapFormat::Csv;
  if (ext == ".raw" || ext == ".r16") return MapFormat::UnityRaw;
  if (ext == ".tif" || ext == ".tiff") return MapFormat::GeoTiff;
  throw Error("unknown output format (expected .map, .yaml, .asc, .csv, .raw)", path);
}

}  // namespace starnav
