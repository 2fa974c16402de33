#pragma once
// What starnav's GDAL plugin (libstarnav_gdal.so, src/plugins/gdal/) hands to the library: the
// first band of a raster file with its georeferencing, read through GDAL. The library never links
// GDAL itself: it loads the plugin with dlopen the first time a GeoTIFF is read (io/geotiff.cpp),
// so programs that never read one do not pay for loading GDAL's hundred-odd shared libraries at
// start-up (about 75 ms per process). Validation and the conversion into an ElevationMap happen in
// the library; the plugin only reads.
//
// The plugin is built from the same tree with the same compiler, so the types below cross the
// boundary as they are; kGdalPluginAbi changes whenever this header does, and the library refuses
// a plugin of another version.
#include <cstdint>
#include <string>
#include <vector>

namespace starnav {

inline constexpr int kGdalPluginAbi = 1;
inline constexpr const char* kGdalPluginAbiSymbol = "starnav_gdal_plugin_abi";
inline constexpr const char* kGdalPluginReadSymbol = "starnav_gdal_read_raster";

struct GdalRaster {
  // The outcome: ok, or a one-line message and the field it concerns ("band", "size", ...).
  bool ok = false;
  std::string error;
  std::string error_field;

  int width = 0;
  int height = 0;
  bool has_geotransform = false;
  double geotransform[6] = {0, 1, 0, 0, 0, 1};  // GDAL's affine terms

  enum class Crs : std::uint8_t { None, Geographic, Projected };
  Crs crs = Crs::None;
  std::string crs_name;
  double degrees_per_angular_unit = 1.0;  // geographic
  bool semi_major_known = false;
  double semi_major_m = 6378137.0;
  bool inverse_flattening_known = false;
  double inverse_flattening = 298.257223563;  // 0 for a sphere
  double metres_per_linear_unit = 1.0;        // projected

  bool float32 = false;  // the band's type is Float32 (nodata compares in float then)
  bool has_nodata = false;
  double nodata = 0.0;
  bool has_scale = false;
  double scale = 1.0;
  bool has_offset = false;
  double offset = 0.0;
  std::string unit_type;

  std::vector<double> values;  // width * height, rows top first, the band's raw values
};

}  // namespace starnav

// The plugin's two entry points (C linkage, looked up with dlsym).
extern "C" int starnav_gdal_plugin_abi();
// Reads the first band of `path` into `out`; refuses (out->ok false, field "size") a raster of
// more than `max_cells` cells before reading its values. Never throws; GDAL's own messages go into
// out->error instead of stderr.
extern "C" void starnav_gdal_read_raster(const char* path, std::uint64_t max_cells, starnav::GdalRaster* out);
