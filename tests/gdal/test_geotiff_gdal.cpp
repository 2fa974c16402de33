// GeoTIFF files written here with GDAL and read back through starnav's GDAL plugin: round trip,
// Float32 nodata, a geographic CRS, and what the reader refuses. Built only with the plugin
// (tests/CMakeLists.txt); this executable links GDAL to write its inputs, the library does not.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "starnav/io/elevation_io.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::error_of;
using test::ScratchDir;

struct TiffSpec {
  int width = 4, height = 3;
  GDALDataType type = GDT_Float64;
  double gt[6] = {500000.0, 2.0, 0.0, 4000006.0, 0.0, -2.0};
  std::string crs = "utm32";  // "utm32", "wgs84", "" (none)
  bool has_nodata = false;
  double nodata = 0.0;
  std::vector<double> values;  // rows top first
};

void write_tiff(const std::string& path, const TiffSpec& s) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  ASSERT_NE(driver, nullptr);
  GDALDataset* ds = driver->Create(path.c_str(), s.width, s.height, 1, s.type, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6];
  std::copy(std::begin(s.gt), std::end(s.gt), gt);
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  if (s.crs == "utm32") {
    srs.SetWellKnownGeogCS("WGS84");
    srs.SetUTM(32, TRUE);
    ds->SetSpatialRef(&srs);
  } else if (s.crs == "wgs84") {
    srs.SetWellKnownGeogCS("WGS84");
    ds->SetSpatialRef(&srs);
  }
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (s.has_nodata) band->SetNoDataValue(s.nodata);
  std::vector<double> v = s.values;
  ASSERT_EQ(band->RasterIO(GF_Write, 0, 0, s.width, s.height, v.data(), s.width, s.height, GDT_Float64, 0, 0,
                           nullptr),
            CE_None);
  GDALClose(ds);
}

TEST(GeoTiffTest, RoundTripThroughAFileWrittenWithGdal) {
  ScratchDir dir;
  TiffSpec s;
  s.has_nodata = true;
  s.nodata = -9999;
  s.values = {101.25, 102.5, -9999, 104.125,  // top row: iy = 2
              0.1,    0.2,   0.3,   1e-7,     //
              -5.5,   7,     8,     9.75};    // bottom row: iy = 0
  write_tiff(dir.file("rt.tif"), s);
  ElevationGeoref g;
  const ElevationMap m = read_geotiff(dir.file("rt.tif"), &g);
  ASSERT_EQ(m.width(), 4);
  ASSERT_EQ(m.height(), 3);
  EXPECT_EQ(m.resolution(), 2.0);
  EXPECT_EQ(m.origin().x, 500000.0);
  EXPECT_EQ(m.origin().y, 4000000.0);  // lower-left corner: 4000006 - 3 * 2
  EXPECT_EQ(g.crs, ElevationGeoref::Crs::Projected);
  EXPECT_NE(g.crs_name.find("UTM"), std::string::npos) << g.crs_name;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      const double v = s.values[static_cast<std::size_t>(r * 4 + c)];
      if (v == -9999) {
        EXPECT_FALSE(m.observed_at(c, 2 - r));
      } else {
        EXPECT_EQ(m.height_at(c, 2 - r), v) << c << "," << r;
      }
    }
  EXPECT_EQ(m.observed_count(), 11u);
  // Through ASC and back: exact.
  write_asc(m, dir.file("rt.asc"));
  EXPECT_EQ(read_asc(dir.file("rt.asc")), m);
}

TEST(GeoTiffTest, Float32NodataAndGeographicCrs) {
  ScratchDir dir;
  TiffSpec s;
  s.width = 2;
  s.height = 2;
  s.type = GDT_Float32;
  s.crs = "wgs84";
  const double cell = 1.0 / 1200.0;  // 3 arc-seconds
  s.gt[0] = 10.0;
  s.gt[1] = cell;
  s.gt[3] = 45.0 + cell;  // rows span 45 - cell .. 45 + cell: centre latitude 45
  s.gt[5] = -cell;
  s.has_nodata = true;
  s.nodata = -3.4e38;  // stored as the nearest float
  s.values = {-3.4e38, 200.5, 300.25, 400};
  write_tiff(dir.file("g.tif"), s);
  ElevationGeoref g;
  const ElevationMap m = read_geotiff(dir.file("g.tif"), &g);
  EXPECT_EQ(g.crs, ElevationGeoref::Crs::Geographic);
  EXPECT_NEAR(g.centre_latitude_deg, 45.0, 1e-9);
  EXPECT_NEAR(m.resolution(), cell * std::sqrt(111132.0 * 78847.0), 0.01);
  EXPECT_EQ(m.origin().x, 0.0);
  EXPECT_FALSE(m.observed_at(0, 1));
  EXPECT_EQ(m.height_at(1, 1), 200.5);
  EXPECT_EQ(m.height_at(0, 0), 300.25);
  EXPECT_EQ(m.observed_count(), 3u);
}

TEST(GeoTiffTest, RejectsRotationNonSquarePixelsAndNaN) {
  ScratchDir dir;
  TiffSpec base;
  base.values.assign(12, 1.0);

  TiffSpec rotated = base;
  rotated.gt[2] = 0.5;
  write_tiff(dir.file("rot.tif"), rotated);
  std::string what = error_of([&] { read_geotiff(dir.file("rot.tif")); });
  EXPECT_EQ(what.rfind(dir.file("rot.tif") + ": geotransform: rotated", 0), 0u) << what;

  TiffSpec sheared = base;
  sheared.gt[4] = -0.25;
  write_tiff(dir.file("shear.tif"), sheared);
  what = error_of([&] { read_geotiff(dir.file("shear.tif")); });
  EXPECT_EQ(what.rfind(dir.file("shear.tif") + ": geotransform:", 0), 0u) << what;

  TiffSpec rect = base;
  rect.gt[5] = -3.0;
  write_tiff(dir.file("rect.tif"), rect);
  what = error_of([&] { read_geotiff(dir.file("rect.tif")); });
  EXPECT_EQ(what.rfind(dir.file("rect.tif") + ": pixel size: non-square", 0), 0u) << what;

  TiffSpec south_up = base;
  south_up.gt[5] = 2.0;
  write_tiff(dir.file("south.tif"), south_up);
  what = error_of([&] { read_geotiff(dir.file("south.tif")); });
  EXPECT_NE(what.find("north-up"), std::string::npos) << what;

  TiffSpec nan = base;
  nan.values[5] = std::numeric_limits<double>::quiet_NaN();
  write_tiff(dir.file("nan.tif"), nan);
  what = error_of([&] { read_geotiff(dir.file("nan.tif")); });
  EXPECT_EQ(what.rfind(dir.file("nan.tif") + ": band 1: pixel (column 1, row 1) is NaN", 0), 0u) << what;

  // NaN as the nodata value marks cells unobserved.
  TiffSpec nan_nodata = nan;
  nan_nodata.has_nodata = true;
  nan_nodata.nodata = std::numeric_limits<double>::quiet_NaN();
  write_tiff(dir.file("nan_nodata.tif"), nan_nodata);
  EXPECT_EQ(read_geotiff(dir.file("nan_nodata.tif")).observed_count(), 11u);
}

}  // namespace
}  // namespace starnav
