// GeoTIFF elevation maps: the raster comes from starnav's GDAL plugin (io/gdal_raster.hpp), loaded
// on first use; here it is checked and turned into an ElevationMap (docs/formats.md, "GeoTIFF").
#include <dlfcn.h>
#include <unistd.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "starnav/config.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/io/elevation_io.hpp"
#include "starnav/io/gdal_raster.hpp"

namespace starnav {

namespace {

namespace fs = std::filesystem;

// Guard against files whose header promises far more cells than their bytes could hold
// (compression bombs, sparse tiles): deflate/LZW cannot expand a byte into more than ~1032.
constexpr std::uint64_t kCellsPerFileByte = 1100;
constexpr std::uint64_t kCellsAlwaysAllowed = 4u << 20;

constexpr const char* kPluginFile = "libstarnav_gdal.so";

using AbiFn = int (*)();
using ReadFn = void (*)(const char*, std::uint64_t, GdalRaster*);

struct Plugin {
  ReadFn read = nullptr;
  GeotiffSupport support;
};

// Loads the plugin at `path`; an empty `why` on success.
Plugin open_plugin(const std::string& path, std::string& why) {
  Plugin p;
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = dlerror();
    why = one_line(e ? e : "dlopen failed");
    return p;
  }
  const auto abi = reinterpret_cast<AbiFn>(dlsym(handle, kGdalPluginAbiSymbol));
  const auto read = reinterpret_cast<ReadFn>(dlsym(handle, kGdalPluginReadSymbol));
  if (!abi || !read) {
    why = path + " is not starnav's GDAL plugin";
    dlclose(handle);
    return p;
  }
  if (abi() != kGdalPluginAbi) {
    why = path + " is a GDAL plugin of another starnav build (interface " + std::to_string(abi()) + ", expected " +
          std::to_string(kGdalPluginAbi) + ")";
    dlclose(handle);
    return p;
  }
  // The handle stays open for the life of the process.
  p.read = read;
  p.support = {true, path};
  return p;
}

// The folder of the running executable ("" when /proc is not there).
std::string executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

// Where the plugin is looked for, in order: $STARNAV_GDAL_PLUGIN (a path, or "none" to go without
// GDAL); beside the executable as the build tree and an installation lay it out (bin/starnav with
// lib/starnav/libstarnav_gdal.so); the installation prefix starnav was configured with.
Plugin find_plugin() {
  Plugin p;
  if (const char* env = std::getenv("STARNAV_GDAL_PLUGIN"); env && *env) {
    const std::string value = env;
    if (value == "none") {
      p.support = {false, "GeoTIFF support needs GDAL: turned off by STARNAV_GDAL_PLUGIN=none"};
      return p;
    }
    std::string why;
    p = open_plugin(value, why);
    if (!p.read) p.support = {false, "GeoTIFF support needs GDAL: STARNAV_GDAL_PLUGIN: " + why};
    return p;
  }
  if (!STARNAV_HAVE_GDAL) {
    p.support = {false, "GeoTIFF support needs GDAL: rebuild with -DSTARNAV_WITH_GDAL=ON"};
    return p;
  }
  std::vector<std::string> candidates;
  const std::string exe_dir = executable_dir();
  if (!exe_dir.empty()) {
    candidates.push_back((fs::path(exe_dir) / "../lib/starnav" / kPluginFile).lexically_normal().string());
    candidates.push_back((fs::path(exe_dir) / STARNAV_GDAL_PLUGIN_FROM_BIN / kPluginFile).lexically_normal().string());
  }
  candidates.push_back((fs::path(STARNAV_GDAL_PLUGIN_INSTALL_DIR) / kPluginFile).string());
  std::string tried, last_error;
  for (const std::string& c : candidates) {
    if (tried.find(c) != std::string::npos) continue;
    tried += (tried.empty() ? "" : ", ") + c;
    std::error_code ec;
    if (!fs::exists(c, ec)) continue;
    std::string why;
    p = open_plugin(c, why);
    if (p.read) return p;
    last_error = why;
  }
  p.support = {false, "GeoTIFF support needs GDAL: its plugin " + std::string(kPluginFile) +
                          (last_error.empty() ? " was not found (looked at " + tried + "; set STARNAV_GDAL_PLUGIN)"
                                              : " did not load: " + last_error)};
  return p;
}

const Plugin& plugin() {
  static const Plugin p = find_plugin();
  return p;
}

double vertical_unit_metres(std::string unit) {
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (unit == "ft" || unit == "foot" || unit == "feet" || unit == "international foot") return 0.3048;
  if (unit == "us-ft" || unit == "ftus" || unit == "us survey foot" || unit == "foot_us") return 1200.0 / 3937.0;
  return 1.0;  // metres, or a unit GDAL does not name: kept as stored
}

std::string format_pixel(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return format_height(v);
}

}  // namespace

GeotiffSupport geotiff_support() { return plugin().support; }

ElevationMap read_geotiff(const std::string& path) { return read_geotiff(path, nullptr); }

ElevationMap read_geotiff(const std::string& path, ElevationGeoref* georef) {
  const InputFileScope reading_path(path);
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("file not found", path);
  if (!fs::is_regular_file(path, ec)) throw Error("not a regular file", path);
  const std::uint64_t file_bytes = fs::file_size(path, ec);
  const Plugin& gdal = plugin();
  if (!gdal.read) throw Error(gdal.support.detail, path);

  GdalRaster raster;
  gdal.read(path.c_str(), std::min(kMaxGridCells, kCellsAlwaysAllowed + file_bytes * kCellsPerFileByte), &raster);
  const int width = raster.width;
  const int height = raster.height;
  if (!raster.ok) {
    if (raster.error_field == "size" && raster.error.empty()) {
      if (width <= 0 || height <= 0)
        throw Error("raster size must be positive, got " + std::to_string(width) + " x " + std::to_string(height), path,
                    0, "size");
      throw Error("raster of " + std::to_string(width) + " x " + std::to_string(height) + " cells is too large for a " +
                      std::to_string(file_bytes) + "-byte file",
                  path, 0, "size");
    }
    throw Error(one_line(raster.error), path, 0, raster.error_field);
  }

  const double* gt = raster.geotransform;
  if (!raster.has_geotransform)
    throw Error("no geotransform: the TIFF is not georeferenced (cell size and origin unknown)", path, 0,
                "geotransform");
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(gt[i])) throw Error("geotransform has a non-finite term", path, 0, "geotransform");
  if (gt[2] != 0.0 || gt[4] != 0.0)
    throw Error("rotated or sheared geotransform (row/column terms " + format_height(gt[2]) + ", " +
                    format_height(gt[4]) + ") is not supported: north-up grids only",
                path, 0, "geotransform");
  if (!(gt[1] > 0.0)) throw Error("pixel width must be positive, got " + format_height(gt[1]), path, 0, "pixel size");
  if (!(gt[5] < 0.0))
    throw Error("pixel height must be negative (north-up), got " + format_height(gt[5]) + ": north-up grids only",
                path, 0, "geotransform");
  if (std::abs(gt[1] + gt[5]) > 1e-7 * gt[1])
    throw Error("non-square pixels (" + format_height(gt[1]) + " x " + format_height(-gt[5]) + ") are not supported",
                path, 0, "pixel size");

  ElevationGeoref g;
  g.cell_x = gt[1];
  g.cell_y = gt[1];  // square (checked above); x's value for both keeps the cells exactly square
  g.x_min = gt[0];
  g.y_min = gt[3] + gt[5] * height;
  double semi_major = 6378137.0, inverse_flattening = 298.257223563;
  g.crs_name = raster.crs_name;
  if (raster.crs == GdalRaster::Crs::Geographic) {
    g.crs = ElevationGeoref::Crs::Geographic;
    const double degrees_per_unit = raster.degrees_per_angular_unit;
    if (std::abs(degrees_per_unit - 1.0) > 1e-9) {
      g.x_min *= degrees_per_unit;
      g.y_min *= degrees_per_unit;
      g.cell_x *= degrees_per_unit;
      g.cell_y *= degrees_per_unit;
    }
    if (raster.semi_major_known) semi_major = raster.semi_major_m;
    if (raster.inverse_flattening_known)
      inverse_flattening = raster.inverse_flattening > 0 ? raster.inverse_flattening : kInfinity;
  } else if (raster.crs == GdalRaster::Crs::Projected) {
    g.crs = ElevationGeoref::Crs::Projected;
    const double m = raster.metres_per_linear_unit;
    g.metres_per_unit_x = g.metres_per_unit_y = m > 0 ? m : 1.0;
  }
  GridGeometry geometry;
  try {
    geometry = georeferenced_geometry(width, height, g, semi_major, inverse_flattening);
  } catch (const Error& e) {
    throw e.with_file(path);
  }

  const double nodata = raster.nodata;
  const bool has_nodata = raster.has_nodata;
  const double scale = raster.has_scale && std::isfinite(raster.scale) && raster.scale != 0.0 ? raster.scale : 1.0;
  const double offset = raster.has_offset && std::isfinite(raster.offset) ? raster.offset : 0.0;
  const double unit = vertical_unit_metres(raster.unit_type);
  const bool nodata_fits_float = has_nodata && std::isfinite(nodata) && std::abs(nodata) <= FLT_MAX;
  const float nodata_f = nodata_fits_float ? static_cast<float>(nodata) : 0.0f;
  auto is_nodata = [&](double v) {
    if (!has_nodata) return false;
    if (std::isnan(nodata)) return std::isnan(v);
    if (raster.float32 && nodata_fits_float) return static_cast<float>(v) == nodata_f;
    return v == nodata;
  };

  ElevationMap map;
  try {
    map = ElevationMap(geometry);
  } catch (const Error& e) {
    throw e.with_file(path);
  }
  const auto w = static_cast<std::size_t>(width);
  for (int r = 0; r < height; ++r) {
    const int iy = height - 1 - r;
    for (int ix = 0; ix < width; ++ix) {
      const double v = raster.values[w * static_cast<std::size_t>(r) + static_cast<std::size_t>(ix)];
      if (is_nodata(v)) continue;
      const double h = (v * scale + offset) * unit;
      if (!std::isfinite(h))
        throw Error("pixel (column " + std::to_string(ix) + ", row " + std::to_string(r) + ") is " + format_pixel(v) +
                        "; only the nodata value may mark a missing cell",
                    path, 0, "band 1");
      map.set_height(ix, iy, h);
    }
  }
  if (georef) *georef = g;
  return map;
}

}  // namespace starnav
