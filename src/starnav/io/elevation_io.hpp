#pragma once
// Elevation map files (conventions.md, "Files"): 16-bit PNG + YAML sidecar, ESRI ASCII grid,
// CSV, Unity RAW, and GeoTIFF through GDAL when built with it.
#include <string>
#include <string_view>

#include "starnav/map/elevation_map.hpp"

namespace starnav {

// PNG16 + YAML (keys image, resolution, origin [x, y, yaw], z_min, z_max, optional nodata: the
// 16-bit value that marks unobserved cells). height = z_min + v / 65535 * (z_max - z_min).
// The image must be 1-channel 16-bit (8-bit and colour images are rejected); optional keys
// width/height are checked against it. A Unity RAW sidecar (format: unity_raw) reads its RAW.
// `companion`, when given, receives the other file it read: the image, or a sidecar's RAW.
ElevationMap read_elevation_yaml(const std::string& yaml_path, std::string* companion = nullptr);
// Quantises heights to 16 bit over the observed range; unobserved cells get the nodata value
// 0 (and observed heights use 1..65535) when any cell is unobserved.
void write_elevation_yaml(const ElevationMap& map, const std::string& yaml_path);
// The PNG write_elevation_yaml writes beside `yaml_path` (its extension replaced by .png).
std::string elevation_yaml_image_path(const std::string& yaml_path);

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
// The YAML sidecar beside a Unity RAW: "<raw file>.yaml".
std::string unity_raw_sidecar_path(const std::string& raw_path);
ElevationMap read_unity_raw(const std::string& path);

// GeoTIFF through GDAL (first band, nodata honoured, geotransform -> resolution and origin).
// GDAL is loaded on first use from starnav's plugin (io/gdal_raster.hpp); throws Error naming the
// file when it is not there (starnav built without GDAL, the plugin not found, or turned off by
// STARNAV_GDAL_PLUGIN=none).
ElevationMap read_geotiff(const std::string& path);

// Whether read_geotiff can read here: `detail` is the plugin's path when available, else the
// one-line reason read_geotiff would give.
struct GeotiffSupport {
  bool available = false;
  std::string detail;
};
GeotiffSupport geotiff_support();

// ---- Additions ---------------------------------------------------------------------------------

// How a file's horizontal coordinates became the map's metric geometry
// (docs/formats.md, "Geographic coordinates").
struct ElevationGeoref {
  enum class Crs {
    None,        // no CRS known (.asc without .prj, GeoTIFF without one): coordinates kept as given
    Projected,   // projected or local CRS: linear units converted to metres
    Geographic,  // longitude/latitude: converted to metres at the grid's centre latitude
  };
  Crs crs = Crs::None;
  std::string crs_name;              // as the file names it ("" when unknown)
  double x_min = 0.0, y_min = 0.0;   // lower-left corner of the grid, in the file's units
  double cell_x = 0.0, cell_y = 0.0; // cell size in the file's units
  // Metres per file unit applied along x and y. For a geographic CRS the two differ
  // (east-west shrinks with cos(latitude)) and the map's square cells use their geometric mean.
  double metres_per_unit_x = 1.0, metres_per_unit_y = 1.0;
  double centre_latitude_deg = 0.0;  // geographic only
};

// Metres per degree of latitude / longitude on an ellipsoid (default WGS 84) at a latitude.
double metres_per_degree_latitude(double latitude_deg, double semi_major_m = 6378137.0,
                                  double inverse_flattening = 298.257223563);
double metres_per_degree_longitude(double latitude_deg, double semi_major_m = 6378137.0,
                                   double inverse_flattening = 298.257223563);

// The metric geometry of a north-up width x height grid described in a CRS's units: `georef`
// gives crs, x_min, y_min, cell_x (== cell_y) and, for a projected CRS, metres_per_unit_x/y;
// the rest (geographic scales, centre latitude) is filled in. Geographic grids get square cells
// of the geometric mean of the east-west and north-south cell sizes at the centre latitude and
// the origin (0, 0). Throws Error (naming no file) for latitudes beyond +-90 or a bad geometry.
GridGeometry georeferenced_geometry(int width, int height, ElevationGeoref& georef,
                                    double semi_major_m = 6378137.0,
                                    double inverse_flattening = 298.257223563);

// read_asc also looks at a .prj beside the file (same name, extension .prj): when it declares a
// geographic CRS, cellsize and corner (degrees) are converted to metres and the origin is put at
// (0, 0); a projected .prj's linear unit is applied. Without a .prj, values are kept as given.
ElevationMap read_asc(const std::string& path, ElevationGeoref* georef);
// The same for GeoTIFF (the CRS comes from the file).
ElevationMap read_geotiff(const std::string& path, ElevationGeoref* georef);

// The side of the square RAW write_unity_raw writes for a width x height map: the smallest
// 2^n + 1 >= max(width, height) (n >= 0, so at least 2).
int unity_raw_size(int width, int height);

// Formats a double with the fewest digits that read back to the same value (used by the text
// writers so read(write(m)) == m).
std::string format_height(double value);

}  // namespace starnav
