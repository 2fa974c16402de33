// libstarnav_gdal.so: reads rasters through GDAL for starnav's GeoTIFF reader (io/geotiff.cpp loads
// it with dlopen; io/gdal_raster.hpp describes the interface). Reading only: every check of what
// the values mean stays in the library.
#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstdint>
#include <exception>
#include <mutex>
#include <new>
#include <numbers>
#include <string>

#include "starnav/io/gdal_raster.hpp"

namespace {

// Collects GDAL's messages instead of letting them reach stderr; restores the previous handler.
class GdalErrorCapture {
 public:
  GdalErrorCapture() { CPLPushErrorHandlerEx(&GdalErrorCapture::handler, this); }
  ~GdalErrorCapture() { CPLPopErrorHandler(); }
  GdalErrorCapture(const GdalErrorCapture&) = delete;
  GdalErrorCapture& operator=(const GdalErrorCapture&) = delete;

  // The first failure GDAL reported, or `fallback`.
  std::string message(const std::string& fallback) const { return first_.empty() ? fallback : first_; }

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

void fail(starnav::GdalRaster& out, std::string message, std::string field) {
  out.ok = false;
  out.error = std::move(message);
  out.error_field = std::move(field);
}

void read(const char* path, std::uint64_t max_cells, starnav::GdalRaster& out) {
  using Crs = starnav::GdalRaster::Crs;
  register_gdal();
  GdalErrorCapture capture;
  const char* const drivers[] = {"GTiff", nullptr};
  GDALDatasetUniquePtr ds(GDALDataset::Open(path, GDAL_OF_RASTER | GDAL_OF_READONLY, drivers));
  if (!ds) return fail(out, "cannot read as GeoTIFF: " + capture.message("not a TIFF file GDAL can open"), "");
  if (ds->GetRasterCount() < 1) return fail(out, "the file has no raster band", "band");
  GDALRasterBand* band = ds->GetRasterBand(1);
  const GDALDataType type = band->GetRasterDataType();
  if (GDALDataTypeIsComplex(type)) return fail(out, "complex-valued band 1 is not an elevation", "band");
  out.width = ds->GetRasterXSize();
  out.height = ds->GetRasterYSize();
  if (out.width <= 0 || out.height <= 0) return fail(out, "", "size");
  if (static_cast<std::uint64_t>(out.width) * static_cast<std::uint64_t>(out.height) > max_cells)
    return fail(out, "", "size");

  out.has_geotransform = ds->GetGeoTransform(out.geotransform) == CE_None;
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  if (srs && !srs->IsEmpty()) {
    out.crs_name = srs->GetName() ? srs->GetName() : "";
    if (srs->IsGeographic()) {
      out.crs = Crs::Geographic;
      const double radians_per_unit = srs->GetAngularUnits(nullptr);
      out.degrees_per_angular_unit = radians_per_unit > 0 ? radians_per_unit * 180.0 / std::numbers::pi : 1.0;
      OGRErr err = OGRERR_NONE;
      const double a = srs->GetSemiMajor(&err);
      if (err == OGRERR_NONE && a > 0) {
        out.semi_major_known = true;
        out.semi_major_m = a;
      }
      const double invf = srs->GetInvFlattening(&err);
      if (err == OGRERR_NONE) {
        out.inverse_flattening_known = true;
        out.inverse_flattening = invf;
      }
    } else {
      out.crs = Crs::Projected;
      out.metres_per_linear_unit = srs->GetLinearUnits(nullptr);
    }
  }
  int flag = 0;
  out.nodata = band->GetNoDataValue(&flag);
  out.has_nodata = flag != 0;
  out.scale = band->GetScale(&flag);
  out.has_scale = flag != 0;
  out.offset = band->GetOffset(&flag);
  out.has_offset = flag != 0;
  out.unit_type = band->GetUnitType() ? band->GetUnitType() : "";
  out.float32 = type == GDT_Float32;

  const auto w = static_cast<std::size_t>(out.width);
  out.values.resize(w * static_cast<std::size_t>(out.height));
  for (int r = 0; r < out.height; ++r)
    if (band->RasterIO(GF_Read, 0, r, out.width, 1, out.values.data() + w * static_cast<std::size_t>(r), out.width, 1,
                       GDT_Float64, 0, 0, nullptr) != CE_None)
      return fail(out, "reading row " + std::to_string(r) + " failed: " + capture.message("GDAL read error"), "band 1");
  out.ok = true;
}

}  // namespace

extern "C" int starnav_gdal_plugin_abi() { return starnav::kGdalPluginAbi; }

extern "C" void starnav_gdal_read_raster(const char* path, std::uint64_t max_cells, starnav::GdalRaster* out) {
  *out = starnav::GdalRaster{};
  try {
    read(path, max_cells, *out);
  } catch (const std::bad_alloc&) {
    fail(*out, "out of memory reading the raster", "size");
  } catch (const std::exception& e) {
    fail(*out, std::string("GDAL failed: ") + e.what(), "");
  }
}
