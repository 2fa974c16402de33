// GeoTIFF elevation maps through GDAL (built only with -DSTARNAV_WITH_GDAL=ON; the twin
// elevation_nogdal.cpp says clearly that GDAL is missing). See docs/formats.md.
#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/io/elevation_io.hpp"

namespace starnav {

namespace {

constexpr std::uint64_t kMaxCells = 2147483647ULL;
// Guard against files whose header promises far more cells than their bytes could hold
// (compression bombs, sparse tiles): deflate/LZW cannot expand a byte into more than ~1032.
constexpr std::uint64_t kCellsPerFileByte = 1100;
constexpr std::uint64_t kCellsAlwaysAllowed = 4u << 20;

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// Collects GDAL's messages instead of letting them reach stderr; restores the previous handler.
class GdalErrorCapture {
 public:
  GdalErrorCapture() { CPLPushErrorHandlerEx(&GdalErrorCapture::handler, this); }
  ~GdalErrorCapture() { CPLPopErrorHandler(); }
  GdalErrorCapture(const GdalErrorCapture&) = delete;
  GdalErrorCapture& operator=(const GdalErrorCapture&) = delete;

  // The first failure GDAL reported (or `fallback`), on one line.
  std::string message(const std::string& fallback) const { return first_.empty() ? fallback : one_line(first_); }

 private:
  static void CPL_STDCALL handler(CPLErr cls, CPLErrorNum, const char* msg) {
    auto* self = static_cast<GdalErrorCapture*>(CPLGetErrorHandlerUserData());
    if (self && cls >= CE_Failure && self->first_.empty() && msg) self->first_ = msg;
  }
  std::string first_;
};

void register_gdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
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

ElevationMap read_geotiff(const std::string& path) { return read_geotiff(path, nullptr); }

ElevationMap read_geotiff(const std::string& path, ElevationGeoref* georef) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("file not found", path);
  if (!fs::is_regular_file(path, ec)) throw Error("not a regular file", path);
  const std::uint64_t file_bytes = fs::file_size(path, ec);

  register_gdal();
  GdalErrorCapture capture;
  const char* const drivers[] = {"GTiff", nullptr};
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers));
  if (!ds) throw Error("cannot read as GeoTIFF: " + capture.message("not a TIFF file GDAL can open"), path);
  if (ds->GetRasterCount() < 1) throw Error("the file has no raster band", path, 0, "band");
  GDALRasterBand* band = ds->GetRasterBand(1);
  const GDALDataType type = band->GetRasterDataType();
  if (GDALDataTypeIsComplex(type)) throw Error("complex-valued band 1 is not an elevation", path, 0, "band");

  const int width = ds->GetRasterXSize();
  const int height = ds->GetRasterYSize();
  if (width <= 0 || height <= 0)
    throw Error("raster size must be positive, got " + std::to_string(width) + " x " + std::to_string(height), path, 0,
                "size");
  const std::uint64_t cells = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  if (cells > kMaxCells || cells > kCellsAlwaysAllowed + file_bytes * kCellsPerFileByte)
    throw Error("raster of " + std::to_string(width) + " x " + std::to_string(height) + " cells is too large for a " +
                    std::to_string(file_bytes) + "-byte file",
                path, 0, "size");

  double gt[6] = {0, 1, 0, 0, 0, 1};
  if (ds->GetGeoTransform(gt) != CE_None)
    throw Error("no geotransform: the TIFF is not georeferenced (cell size and origin unknown)", path, 0,
                "geotransform");
  for (double v : gt)
    if (!std::isfinite(v)) throw Error("geotransform has a non-finite term", path, 0, "geotransform");
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
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  if (srs && !srs->IsEmpty()) {
    g.crs_name = srs->GetName() ? srs->GetName() : "";
    if (srs->IsGeographic()) {
      g.crs = ElevationGeoref::Crs::Geographic;
      const double radians_per_unit = srs->GetAngularUnits(nullptr);
      const double degrees_per_unit = radians_per_unit > 0 ? radians_per_unit * 180.0 / kPi : 1.0;
      if (std::abs(degrees_per_unit - 1.0) > 1e-9) {
        g.x_min *= degrees_per_unit;
        g.y_min *= degrees_per_unit;
        g.cell_x *= degrees_per_unit;
        g.cell_y *= degrees_per_unit;
      }
      OGRErr err = OGRERR_NONE;
      const double a = srs->GetSemiMajor(&err);
      if (err == OGRERR_NONE && a > 0) semi_major = a;
      const double invf = srs->GetInvFlattening(&err);
      if (err == OGRERR_NONE) inverse_flattening = invf > 0 ? invf : std::numeric_limits<double>::infinity();
    } else {
      g.crs = ElevationGeoref::Crs::Projected;
      const double m = srs->GetLinearUnits(nullptr);
      g.metres_per_unit_x = g.metres_per_unit_y = m > 0 ? m : 1.0;
    }
  }
  GridGeometry geometry;
  try {
    geometry = georeferenced_geometry(width, height, g, semi_major, inverse_flattening);
  } catch (const Error& e) {
    throw e.with_file(path);
  }

  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  int has_scale = 0, has_offset = 0;
  double scale = band->GetScale(&has_scale);
  double offset = band->GetOffset(&has_offset);
  if (!has_scale || !std::isfinite(scale) || scale == 0.0) scale = 1.0;
  if (!has_offset || !std::isfinite(offset)) offset = 0.0;
  const double unit = vertical_unit_metres(band->GetUnitType() ? band->GetUnitType() : "");
  const bool float32 = type == GDT_Float32;
  const bool nodata_fits_float = has_nodata && std::isfinite(nodata) && std::abs(nodata) <= FLT_MAX;
  const float nodata_f = nodata_fits_float ? static_cast<float>(nodata) : 0.0f;
  auto is_nodata = [&](double v) {
    if (!has_nodata) return false;
    if (std::isnan(nodata)) return std::isnan(v);
    if (float32 && nodata_fits_float) return static_cast<float>(v) == nodata_f;
    return v == nodata;
  };

  ElevationMap map;
  try {
    map = ElevationMap(geometry);
  } catch (const Error& e) {
    throw e.with_file(path);
  }
  std::vector<double> row(static_cast<std::size_t>(width));
  for (int r = 0; r < height; ++r) {
    if (band->RasterIO(GF_Read, 0, r, width, 1, row.data(), width, 1, GDT_Float64, 0, 0, nullptr) != CE_None)
      throw Error("reading row " + std::to_string(r) + " failed: " + capture.message("GDAL read error"), path, 0,
                  "band 1");
    const int iy = height - 1 - r;
    for (int ix = 0; ix < width; ++ix) {
      const double v = row[static_cast<std::size_t>(ix)];
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
