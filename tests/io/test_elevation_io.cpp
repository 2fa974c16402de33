// Elevation map files: PNG16 + YAML, ESRI ASCII grid, CSV, Unity RAW, GeoTIFF (GDAL).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/io/elevation_io.hpp"
#include "starnav/io/image.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;
using test::read_text;
using test::ScratchDir;
using test::write_text;

// A map whose heights come from `f`; cells where `f` returns NaN are left unobserved.
ElevationMap make_map(int w, int h, double res, Pose2 origin, const std::function<double(int, int)>& f) {
  GridGeometry g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.origin = origin;
  ElevationMap m(g);
  for (int iy = 0; iy < h; ++iy)
    for (int ix = 0; ix < w; ++ix)
      if (const double v = f(ix, iy); !std::isnan(v)) m.set_height(ix, iy, v);
  return m;
}

// Awkward heights: non-terminating binary fractions, big and tiny magnitudes, negatives.
double awkward(int ix, int iy) {
  const double base = (ix * 0.1 + iy * 0.7) / 3.0 - 17.0 * std::sin(ix * 1.3 + iy);
  if ((ix + 2 * iy) % 7 == 3) return std::numeric_limits<double>::quiet_NaN();  // unobserved
  if (ix == 1 && iy == 0) return 1e-300;
  if (ix == 2 && iy == 0) return -123456789.123456789;
  if (ix == 0 && iy == 1) return 0.1 + 0.2;
  return base;
}

void expect_same_geometry(const ElevationMap& a, const ElevationMap& b) {
  EXPECT_EQ(a.width(), b.width());
  EXPECT_EQ(a.height(), b.height());
  EXPECT_EQ(a.resolution(), b.resolution());
  EXPECT_EQ(a.origin().x, b.origin().x);
  EXPECT_EQ(a.origin().y, b.origin().y);
  EXPECT_EQ(a.origin().yaw, b.origin().yaw);
}

void expect_no_nan(const ElevationMap& m) {
  for (std::size_t i = 0; i < m.cell_count(); ++i) {
    ASSERT_TRUE(std::isfinite(m.heights()[i])) << "cell " << i;
    ASSERT_TRUE(std::isfinite(m.min_heights()[i])) << "cell " << i;
    ASSERT_TRUE(std::isfinite(m.max_heights()[i])) << "cell " << i;
  }
}

using test::error_of;

// ---- PNG16 + YAML ------------------------------------------------------------------------------

TEST(ElevationYamlTest, HandBuiltFileGivesHandComputedHeights) {
  ScratchDir dir;
  GrayImage img;
  img.width = 3;
  img.height = 2;
  img.max_value = 65535;
  img.pixels = {0, 65535, 32768,  // top row: iy = 1
                1000, 7, 13107};  // bottom row: iy = 0; 7 is nodata
  write_png(img, dir.file("hand.png"));
  write_text(dir.file("hand.yaml"),
             "image: hand.png\nresolution: 0.25\norigin: [2.0, -3.5, 0.5]\nz_min: -10\nz_max: 20\nnodata: 7\n");
  const ElevationMap m = read_elevation_yaml(dir.file("hand.yaml"));
  ASSERT_EQ(m.width(), 3);
  ASSERT_EQ(m.height(), 2);
  EXPECT_EQ(m.resolution(), 0.25);
  EXPECT_EQ(m.origin().x, 2.0);
  EXPECT_EQ(m.origin().y, -3.5);
  EXPECT_EQ(m.origin().yaw, 0.5);
  // height = -10 + v / 65535 * 30
  EXPECT_DOUBLE_EQ(m.height_at(0, 1), -10.0);
  EXPECT_DOUBLE_EQ(m.height_at(1, 1), 20.0);
  EXPECT_NEAR(m.height_at(2, 1), 5.000228885328450, 1e-12);   // 32768 * 30 / 65535 - 10
  EXPECT_NEAR(m.height_at(0, 0), -9.542229343099108, 1e-12);  // 1000 * 30 / 65535 - 10
  EXPECT_FALSE(m.observed_at(1, 0));                           // nodata
  EXPECT_NEAR(m.height_at(2, 0), -4.0, 1e-12);                 // 13107 = 65535 / 5: -10 + 6
  EXPECT_EQ(m.observed_count(), 5u);
  // The origin's yaw rotates the grid about its lower-left corner.
  const Vec2 c = m.geometry().cell_center(2, 1);
  const double gx = 2.5 * 0.25, gy = 1.5 * 0.25;
  EXPECT_NEAR(c.x(), 2.0 + std::cos(0.5) * gx - std::sin(0.5) * gy, 1e-12);
  EXPECT_NEAR(c.y(), -3.5 + std::sin(0.5) * gx + std::cos(0.5) * gy, 1e-12);
}

TEST(ElevationYamlTest, RoundTripAllObservedWithinHalfQuantum) {
  ScratchDir dir;
  const ElevationMap m = make_map(9, 6, 0.05, Pose2(12.5, -7.25, -1.2), [](int ix, int iy) {
    return 100.0 + 30.0 * std::sin(ix * 0.9) * std::cos(iy * 0.4) + ix * 0.01;
  });
  write_elevation_yaml(m, dir.file("terrain.yaml"));
  ASSERT_TRUE(fs::exists(dir.file("terrain.png")));
  const ElevationMap r = read_elevation_yaml(dir.file("terrain.yaml"));
  expect_same_geometry(m, r);
  const auto range = m.height_range();
  ASSERT_TRUE(range);
  const double half_quantum = (range->max - range->min) / 65535.0 / 2.0;
  EXPECT_EQ(r.observed_count(), m.cell_count());
  for (int iy = 0; iy < m.height(); ++iy)
    for (int ix = 0; ix < m.width(); ++ix) EXPECT_NEAR(r.height_at(ix, iy), m.height_at(ix, iy), half_quantum * 1.0001);
  // The extremes are exact (v = 0 and 65535).
  EXPECT_DOUBLE_EQ(r.height_range()->min, range->min);
  EXPECT_DOUBLE_EQ(r.height_range()->max, range->max);
  // The YAML names its image, z range, and no nodata when every cell is observed.
  const std::string yaml = read_text(dir.file("terrain.yaml"));
  EXPECT_NE(yaml.find("image: terrain.png"), std::string::npos);
  EXPECT_EQ(yaml.find("nodata"), std::string::npos);
}

TEST(ElevationYamlTest, RoundTripWithUnobservedCellsKeepsThem) {
  ScratchDir dir;
  const ElevationMap m = make_map(8, 5, 1.0, Pose2(0, 0, 0), awkward);
  // awkward() spans ~1.2e8 m: the bound below is relative to that range.
  write_elevation_yaml(m, dir.file("holes.yaml"));
  const ElevationMap r = read_elevation_yaml(dir.file("holes.yaml"));
  expect_same_geometry(m, r);
  EXPECT_EQ(r.observed(), m.observed());
  EXPECT_LT(r.observed_count(), r.cell_count());
  const auto range = m.height_range();
  const double half_quantum = (range->max - range->min) / 65534.0 / 2.0;  // value 0 is nodata
  for (std::size_t i = 0; i < m.cell_count(); ++i)
    if (m.observed_at_index(i)) {
      EXPECT_NEAR(r.height_at_index(i), m.height_at_index(i), half_quantum * 1.0001);
    }
  EXPECT_NE(read_text(dir.file("holes.yaml")).find("nodata: 0"), std::string::npos);
}

TEST(ElevationYamlTest, FlatAndEmptyMapsRoundTrip) {
  ScratchDir dir;
  const ElevationMap flat = make_map(4, 3, 2.0, Pose2(1, 2, 0), [](int, int) { return 42.5; });
  write_elevation_yaml(flat, dir.file("flat.yaml"));
  EXPECT_EQ(read_elevation_yaml(dir.file("flat.yaml")), flat);  // z_min == z_max: exact

  const ElevationMap none =
      make_map(2, 2, 1.0, Pose2(0, 0, 0), [](int, int) { return std::numeric_limits<double>::quiet_NaN(); });
  write_elevation_yaml(none, dir.file("none.yaml"));
  const ElevationMap r = read_elevation_yaml(dir.file("none.yaml"));
  EXPECT_EQ(r.observed_count(), 0u);
  EXPECT_EQ(r, none);
}

TEST(ElevationYamlTest, ImageIsFoundBesideTheYamlAndMayBeAbsolute) {
  ScratchDir dir;
  fs::create_directories(dir.path() / "sub");
  const ElevationMap m = make_map(3, 3, 1.0, Pose2(0, 0, 0), [](int ix, int iy) { return ix + 10.0 * iy; });
  write_elevation_yaml(m, dir.file("sub/a.yaml"));
  const ElevationMap r = read_elevation_yaml(dir.file("sub/a.yaml"));
  EXPECT_EQ(r.width(), 3);
  // An absolute image path in a YAML elsewhere.
  write_text(dir.file("b.yaml"), "image: " + dir.file("sub/a.png") +
                                      "\nresolution: 1\norigin: [0, 0, 0]\nz_min: 0\nz_max: 20\n");
  const ElevationMap b = read_elevation_yaml(dir.file("b.yaml"));
  EXPECT_EQ(b.height_at(2, 2), 20.0);  // the highest cell is 65535: this YAML's z_max
  EXPECT_EQ(b.height_at(0, 0), 0.0);
  // A wrong declared size names the key.
  write_text(dir.file("c.yaml"), "image: sub/a.png\nresolution: 1\norigin: [0, 0, 0]\nz_min: 0\nz_max: 1\nwidth: 4\n");
  const std::string what = error_of([&] { read_elevation_yaml(dir.file("c.yaml")); });
  EXPECT_EQ(what.rfind(dir.file("c.yaml") + ":6: width:", 0), 0u) << what;
}

// ---- ESRI ASCII grid ---------------------------------------------------------------------------

TEST(AscTest, HandBuiltHeaderAnyCaseAndSpacing) {
  const std::string text =
      "NCOLS 3\r\n"
      "nRows\t\t2\r\n"
      "XLLCENTER   100.5\r\n"
      "yllcorner -20\r\n"
      "CellSize 1\r\n"
      "nodata_value -9999\r\n"
      "  1.5 -9999  3e2\r\n"
      "4\t5 6\r\n";
  const ElevationMap m = parse_asc(text, "hand.asc");
  ASSERT_EQ(m.width(), 3);
  ASSERT_EQ(m.height(), 2);
  EXPECT_EQ(m.resolution(), 1.0);
  EXPECT_EQ(m.origin().x, 100.0);  // centre of the lower-left cell minus half a cell
  EXPECT_EQ(m.origin().y, -20.0);
  EXPECT_EQ(m.origin().yaw, 0.0);
  // First data row is the top row (iy = 1).
  EXPECT_EQ(m.height_at(0, 1), 1.5);
  EXPECT_FALSE(m.observed_at(1, 1));
  EXPECT_EQ(m.height_at(2, 1), 300.0);
  EXPECT_EQ(m.height_at(0, 0), 4.0);
  EXPECT_EQ(m.height_at(1, 0), 5.0);
  EXPECT_EQ(m.height_at(2, 0), 6.0);
  EXPECT_EQ(m.observed_count(), 5u);
}

TEST(AscTest, ZeroNodataIsNotAHeight) {
  const ElevationMap m = parse_asc(
      "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 3\nNODATA_value 0\n0 1680.5\n0.0 1700\n", "z.asc");
  EXPECT_FALSE(m.observed_at(0, 1));
  EXPECT_FALSE(m.observed_at(0, 0));  // "0.0" equals the nodata value too
  EXPECT_EQ(m.height_at(1, 1), 1680.5);
  EXPECT_EQ(m.observed_count(), 2u);
  // Without NODATA_value, 0 is a height.
  const ElevationMap n = parse_asc("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n0\n", "n.asc");
  EXPECT_TRUE(n.observed_at(0, 0));
}

TEST(AscTest, RoundTripIsExact) {
  ScratchDir dir;
  const ElevationMap m = make_map(8, 5, 0.1 + 0.2, Pose2(361015.59563119, 70223.434086869, 0.0), awkward);
  write_asc(m, dir.file("a.asc"));
  const ElevationMap r = read_asc(dir.file("a.asc"));
  EXPECT_EQ(r, m);
  EXPECT_LT(r.observed_count(), r.cell_count());
}

TEST(AscTest, RoundTripWhenAHeightEqualsTheUsualNodata) {
  ScratchDir dir;
  const ElevationMap m = make_map(3, 2, 5.0, Pose2(0, 0, 0), [](int ix, int iy) {
    if (ix == 0 && iy == 0) return -9999.0;
    if (ix == 1 && iy == 1) return std::numeric_limits<double>::quiet_NaN();
    return ix * 1.5 + iy;
  });
  write_asc(m, dir.file("n.asc"));
  EXPECT_EQ(read_asc(dir.file("n.asc")), m);
}

TEST(AscTest, WriteRefusesARotatedMap) {
  ScratchDir dir;
  const ElevationMap m = make_map(2, 2, 1.0, Pose2(0, 0, 0.3), [](int, int) { return 1.0; });
  const std::string what = error_of([&] { write_asc(m, dir.file("r.asc")); });
  EXPECT_EQ(what.rfind(dir.file("r.asc") + ": origin:", 0), 0u) << what;
}

TEST(AscTest, ErrorsNameFileLineAndKey) {
  const std::string what = error_of(
      [] { parse_asc("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 inf\n", "mem.asc"); });
  EXPECT_EQ(what.rfind("mem.asc:6: ", 0), 0u) << what;
  EXPECT_NE(what.find("not finite"), std::string::npos) << what;
  const std::string w2 = error_of([] { parse_asc("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\n1 2\n", "m2.asc"); });
  EXPECT_EQ(w2.rfind("m2.asc:5: cellsize: missing", 0), 0u) << w2;
}

// Reference values: metres per degree on WGS 84 (standard geodesy tables).
TEST(AscTest, MetresPerDegreeMatchReferenceValues) {
  EXPECT_NEAR(metres_per_degree_latitude(0.0), 110574.0, 1.0);
  EXPECT_NEAR(metres_per_degree_longitude(0.0), 111320.0, 1.0);
  EXPECT_NEAR(metres_per_degree_latitude(45.0), 111132.0, 1.0);
  EXPECT_NEAR(metres_per_degree_longitude(45.0), 78847.0, 1.0);
  EXPECT_NEAR(metres_per_degree_latitude(60.0), 111412.0, 1.0);
  EXPECT_NEAR(metres_per_degree_longitude(60.0), 55800.0, 1.0);
  EXPECT_NEAR(metres_per_degree_longitude(90.0), 0.0, 1e-6);
}

// The usual series for metres per degree (independent of the ellipsoid formulas used above).
double series_lat(double deg) {
  const double p = deg * std::numbers::pi / 180;
  return 111132.92 - 559.82 * std::cos(2 * p) + 1.175 * std::cos(4 * p) - 0.0023 * std::cos(6 * p);
}
double series_lon(double deg) {
  const double p = deg * std::numbers::pi / 180;
  return 111412.84 * std::cos(p) - 93.5 * std::cos(3 * p) + 0.118 * std::cos(5 * p);
}

TEST(AscTest, GeographicPrjConvertsDegreesToMetres) {
  ScratchDir dir;
  // 1 arc-second cells, lower-left corner at 39.5 N: centre latitude 39.5 + 2/3600 / 2.
  const std::string asc =
      "ncols 3\nnrows 2\nxllcorner -104.3\nyllcorner 39.5\ncellsize 0.000277777777778\nNODATA_value -32768\n"
      "1700 1701 1702\n1690 -32768 1692\n";
  write_text(dir.file("geo.asc"), asc);
  write_text(dir.file("geo.prj"),
             "GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\",SPHEROID[\"WGS_1984\",6378137.0,298.257223563]],"
             "PRIMEM[\"Greenwich\",0.0],UNIT[\"Degree\",0.0174532925199433]]");
  ElevationGeoref g;
  const ElevationMap m = read_asc(dir.file("geo.asc"), &g);
  EXPECT_EQ(g.crs, ElevationGeoref::Crs::Geographic);
  EXPECT_EQ(g.crs_name, "GCS_WGS_1984");
  const double lat = 39.5 + 0.000277777777778;
  EXPECT_NEAR(g.centre_latitude_deg, lat, 1e-9);
  const double dx = 0.000277777777778 * series_lon(lat), dy = 0.000277777777778 * series_lat(lat);
  EXPECT_NEAR(m.resolution(), std::sqrt(dx * dy), 1e-4);
  EXPECT_GT(m.resolution(), 23.0);  // between ~23.8 m (east-west) and ~30.8 m (north-south)
  EXPECT_LT(m.resolution(), 31.0);
  EXPECT_EQ(m.origin().x, 0.0);  // local frame at the lower-left corner
  EXPECT_EQ(m.origin().y, 0.0);
  EXPECT_EQ(g.x_min, -104.3);
  EXPECT_EQ(g.y_min, 39.5);
  EXPECT_EQ(m.height_at(1, 1), 1701.0);
  EXPECT_FALSE(m.observed_at(1, 0));
  // The same grid without its .prj keeps cellsize and corner as given.
  fs::remove(dir.file("geo.prj"));
  ElevationGeoref none;
  const ElevationMap raw = read_asc(dir.file("geo.asc"), &none);
  EXPECT_EQ(none.crs, ElevationGeoref::Crs::None);
  EXPECT_EQ(raw.resolution(), 0.000277777777778);
  EXPECT_EQ(raw.origin().x, -104.3);
}

TEST(AscTest, ProjectedPrjInFeetIsConvertedAndMetresKept) {
  ScratchDir dir;
  const std::string asc = "ncols 2\nnrows 1\nxllcorner 1000\nyllcorner 2000\ncellsize 10\n5 6\n";
  write_text(dir.file("ft.asc"), asc);
  write_text(dir.file("ft.prj"),
             "PROJCS[\"NAD_1983_StatePlane_Colorado_Central_FIPS_0502_Feet\",GEOGCS[\"GCS_North_American_1983\","
             "DATUM[\"D_North_American_1983\",SPHEROID[\"GRS_1980\",6378137.0,298.257222101]],PRIMEM[\"Greenwich\",0.0],"
             "UNIT[\"Degree\",0.0174532925199433]],PROJECTION[\"Lambert_Conformal_Conic\"],"
             "UNIT[\"Foot_US\",0.3048006096012192]]");
  ElevationGeoref g;
  const ElevationMap m = read_asc(dir.file("ft.asc"), &g);
  EXPECT_EQ(g.crs, ElevationGeoref::Crs::Projected);
  EXPECT_NEAR(m.resolution(), 3.048006096012192, 1e-12);
  EXPECT_NEAR(m.origin().x, 304.8006096012192, 1e-9);
  EXPECT_NEAR(m.origin().y, 609.6012192024384, 1e-9);

  write_text(dir.file("m.asc"), asc);
  write_text(dir.file("m.prj"),
             "PROJCS[\"WGS_1984_UTM_Zone_13N\",GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\",SPHEROID[\"WGS_1984\","
             "6378137.0,298.257223563]],PRIMEM[\"Greenwich\",0.0],UNIT[\"Degree\",0.0174532925199433]],"
             "PROJECTION[\"Transverse_Mercator\"],UNIT[\"Meter\",1.0]]");
  const ElevationMap mm = read_asc(dir.file("m.asc"));
  EXPECT_EQ(mm.resolution(), 10.0);
  EXPECT_EQ(mm.origin().x, 1000.0);
}

// ---- CSV -------------------------------------------------------------------------------------

TEST(CsvTest, HandBuiltRowsTopFirstEmptyFieldUnobserved) {
  const ElevationMap m = parse_elevation_csv("1, 2.5,3\r\n4,,-6e1\r\n", "h.csv", 0.5, Pose2(1, 2, 0.25));
  ASSERT_EQ(m.width(), 3);
  ASSERT_EQ(m.height(), 2);
  EXPECT_EQ(m.resolution(), 0.5);
  EXPECT_EQ(m.origin().x, 1.0);
  EXPECT_EQ(m.origin().y, 2.0);
  EXPECT_EQ(m.origin().yaw, 0.25);
  EXPECT_EQ(m.height_at(0, 1), 1.0);
  EXPECT_EQ(m.height_at(1, 1), 2.5);
  EXPECT_EQ(m.height_at(2, 1), 3.0);
  EXPECT_EQ(m.height_at(0, 0), 4.0);
  EXPECT_FALSE(m.observed_at(1, 0));
  EXPECT_EQ(m.height_at(2, 0), -60.0);
}

TEST(CsvTest, RoundTripIsExact) {
  ScratchDir dir;
  const ElevationMap m = make_map(8, 5, 0.3, Pose2(-1.5, 2.25, 0.7), awkward);
  write_elevation_csv(m, dir.file("m.csv"));
  const ElevationMap r = read_elevation_csv(dir.file("m.csv"), 0.3, Pose2(-1.5, 2.25, 0.7));
  EXPECT_EQ(r, m);
  // One column with unobserved cells at the bottom: blank lines are cells there.
  const ElevationMap col = make_map(1, 4, 1.0, Pose2(0, 0, 0), [](int, int iy) {
    return iy < 2 ? std::numeric_limits<double>::quiet_NaN() : iy * 1.25;
  });
  write_elevation_csv(col, dir.file("c.csv"));
  EXPECT_EQ(read_elevation_csv(dir.file("c.csv")), col);
}

TEST(CsvTest, BadGeometryArgumentsNameTheFile) {
  const std::string what = error_of([] { parse_elevation_csv("1,2\n", "g.csv", -1.0); });
  EXPECT_EQ(what.rfind("g.csv: resolution:", 0), 0u) << what;
}

// ---- Unity RAW ---------------------------------------------------------------------------------

std::uint16_t raw_sample(const std::string& bytes, int size, int rx, int ry) {
  const std::size_t at = (static_cast<std::size_t>(ry) * static_cast<std::size_t>(size) + static_cast<std::size_t>(rx)) * 2;
  return static_cast<std::uint16_t>(static_cast<unsigned char>(bytes[at]) |
                                    (static_cast<unsigned char>(bytes[at + 1]) << 8));
}

TEST(RawTest, SizeIsSmallestPowerOfTwoPlusOne) {
  EXPECT_EQ(unity_raw_size(1, 1), 2);
  EXPECT_EQ(unity_raw_size(2, 1), 2);
  EXPECT_EQ(unity_raw_size(3, 3), 3);
  EXPECT_EQ(unity_raw_size(4, 2), 5);
  EXPECT_EQ(unity_raw_size(33, 20), 33);
  EXPECT_EQ(unity_raw_size(20, 34), 65);
  EXPECT_EQ(unity_raw_size(129, 67), 129);
  EXPECT_EQ(unity_raw_size(240, 144), 257);
}

TEST(RawTest, RoundTripWithinHalfQuantumAndEdgePadding) {
  ScratchDir dir;
  const ElevationMap m = make_map(6, 3, 0.5, Pose2(3.0, -4.0, 0.1), [](int ix, int iy) {
    return 1000.0 + 37.3 * std::sin(ix * 0.8 + iy * 0.3) + 0.001 * ix * iy;
  });
  testing::internal::CaptureStderr();
  write_unity_raw(m, dir.file("t.raw"));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("padded 6 x 3 to 9 x 9"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  ASSERT_TRUE(fs::exists(dir.file("t.raw.yaml")));
  const std::string bytes = read_text(dir.file("t.raw"));
  ASSERT_EQ(bytes.size(), 9u * 9u * 2u);
  // Rows bottom first; padding replicates the last column and the top row (and the corner).
  for (int ry = 0; ry < 9; ++ry)
    for (int rx = 0; rx < 9; ++rx) {
      const int sx = std::min(rx, 5), sy = std::min(ry, 2);
      EXPECT_EQ(raw_sample(bytes, 9, rx, ry), raw_sample(bytes, 9, sx, sy)) << rx << "," << ry;
    }
  // Bottom-first order: the lowest sample in the file is the lowest height of the map.
  const ElevationMap r = read_unity_raw(dir.file("t.raw"));
  expect_same_geometry(m, r);
  const auto range = m.height_range();
  const double half_quantum = (range->max - range->min) / 65535.0 / 2.0;
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 6; ++ix) {
      EXPECT_NEAR(r.height_at(ix, iy), m.height_at(ix, iy), half_quantum * 1.0001);
      const double v = (m.height_at(ix, iy) - range->min) / (range->max - range->min) * 65535.0;
      EXPECT_EQ(raw_sample(bytes, 9, ix, iy), static_cast<std::uint16_t>(std::lround(v)));
    }
}

TEST(RawTest, TheSidecarReadsAsTheRaw) {
  ScratchDir dir;
  const ElevationMap m = make_map(3, 3, 1.0, Pose2(0, 0, 0), [](int ix, int iy) { return ix * 2.0 + iy; });
  write_unity_raw(m, dir.file("s.raw"));
  EXPECT_EQ(read_elevation_yaml(dir.file("s.raw.yaml")), read_unity_raw(dir.file("s.raw")));
}

TEST(RawTest, NoPaddingNoWarning) {
  ScratchDir dir;
  const ElevationMap m = make_map(5, 5, 1.0, Pose2(0, 0, 0), [](int ix, int iy) { return ix - iy * 2.0; });
  testing::internal::CaptureStderr();
  write_unity_raw(m, dir.file("s.raw"));
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(fs::file_size(dir.file("s.raw")), 5u * 5u * 2u);
  const ElevationMap r = read_unity_raw(dir.file("s.raw"));
  for (int iy = 0; iy < 5; ++iy)
    for (int ix = 0; ix < 5; ++ix) EXPECT_NEAR(r.height_at(ix, iy), m.height_at(ix, iy), 12.0 / 65535 / 2 * 1.0001);
}

TEST(RawTest, UnobservedCellsComeBackUnobserved) {
  ScratchDir dir;
  const ElevationMap m = make_map(4, 4, 1.0, Pose2(0, 0, 0), [](int ix, int iy) {
    return ix == iy ? std::numeric_limits<double>::quiet_NaN() : ix * 3.0 + iy;
  });
  testing::internal::CaptureStderr();
  write_unity_raw(m, dir.file("u.raw"));
  testing::internal::GetCapturedStderr();
  const ElevationMap r = read_unity_raw(dir.file("u.raw"));
  EXPECT_EQ(r.observed(), m.observed());
  const double half_quantum = 11.0 / 65534.0 / 2.0;
  for (std::size_t i = 0; i < m.cell_count(); ++i)
    if (m.observed_at_index(i)) {
      EXPECT_NEAR(r.height_at_index(i), m.height_at_index(i), half_quantum * 1.0001);
    }
}

TEST(RawTest, HandBuiltFileIsLittleEndianBottomFirst) {
  ScratchDir dir;
  // 3 x 3 samples, bottom row first: 0x0201 = 513 at raw (0, 0).
  std::string bytes(18, '\0');
  bytes[0] = 0x01;
  bytes[1] = 0x02;
  bytes[16] = static_cast<char>(0xff);  // raw (2, 2): 0xffff
  bytes[17] = static_cast<char>(0xff);
  write_text(dir.file("h.raw"), bytes);
  write_text(dir.file("h.raw.yaml"),
             "size: 3\nwidth: 3\nheight: 2\nresolution: 2\norigin: [1, 1, 0]\nz_min: 100\nz_max: 165.535\n");
  const ElevationMap m = read_unity_raw(dir.file("h.raw"));
  ASSERT_EQ(m.width(), 3);
  ASSERT_EQ(m.height(), 2);  // the third raw row is padding
  EXPECT_NEAR(m.height_at(0, 0), 100.513, 1e-9);  // 100 + 513 / 65535 * 65.535
  EXPECT_NEAR(m.height_at(1, 0), 100.0, 1e-12);
  EXPECT_EQ(m.origin().x, 1.0);
  EXPECT_EQ(m.resolution(), 2.0);
}

// ---- real DEMs under ../shared ----------------------------------------------------------------

struct DemFact {
  const char* file;
  int width, height;
  double min, max;          // from SOURCES.md (range of the valid cells)
  double tolerance;         // SOURCES.md rounds float ranges to 0.1 m
  std::size_t unobserved;   // cells holding the nodata value (counted with awk / GDAL's mask)
  double resolution_lo, resolution_hi;  // metres per cell as starnav reads it
};

const DemFact kAscFacts[] = {
    {"landlab/hugo_site.asc", 76, 55, 1660, 1711, 0, 2028, 10, 10},
    {"landlab/pre_runout_DEM.asc", 80, 122, 189.0, 582.4, 0.05, 122, 10, 10},
    // Geographic but no .prj: cellsize kept as given (degrees).
    {"landlab/srtmgl3_front_range_144x144.asc", 144, 144, 2186, 3345, 0, 0, 0.000833333333, 0.000833333333},
    {"landlab/srtmgl3_front_range_240x144.asc", 240, 144, 1943, 3286, 0, 0, 0.000833333333, 0.000833333333},
    // Geographic with a .prj: 1 arc-second at 39.5 N is 23.8 m east-west, 30.8 m north-south.
    {"landlab/west_bijou_escarpment_snippet.asc", 129, 67, 1690, 1807, 0, 0, 27.0, 27.2},
    {"landlab/west_bijou_gully.asc", 43, 89, 1680.8, 1725.4, 0.05, 2739, 3, 3},
};

void check_dem(const ElevationMap& m, const DemFact& f) {
  SCOPED_TRACE(f.file);
  EXPECT_EQ(m.width(), f.width);
  EXPECT_EQ(m.height(), f.height);
  expect_no_nan(m);
  EXPECT_EQ(m.cell_count() - m.observed_count(), f.unobserved);
  const auto range = m.height_range();
  ASSERT_TRUE(range);
  EXPECT_NEAR(range->min, f.min, f.tolerance);
  EXPECT_NEAR(range->max, f.max, f.tolerance);
  EXPECT_GE(m.resolution(), f.resolution_lo * (1 - 1e-9));
  EXPECT_LE(m.resolution(), f.resolution_hi * (1 + 1e-9));
}

TEST(SharedDemAscTest, EveryAscGridLoadsWithItsFacts) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/dem");
  for (const DemFact& f : kAscFacts) {
    const std::string path = test::shared_path("datasets/dem/" + std::string(f.file));
    ASSERT_FALSE(path.empty()) << f.file;
    check_dem(read_asc(path), f);
  }
  const ElevationMap pre = read_asc(test::shared_path("datasets/dem/landlab/pre_runout_DEM.asc"));
  EXPECT_EQ(pre.origin().x, 361015.59563119);
  EXPECT_EQ(pre.origin().y, 70223.434086869);
  ElevationGeoref g;
  const ElevationMap bijou = read_asc(test::shared_path("datasets/dem/landlab/west_bijou_escarpment_snippet.asc"), &g);
  EXPECT_EQ(g.crs, ElevationGeoref::Crs::Geographic);
  EXPECT_EQ(bijou.origin().x, 0.0);
  EXPECT_NEAR(g.x_min, -104.341805555546, 1e-12);
}

// Every file under datasets/dem loads with the size its header states, whatever the table says.
TEST(SharedDemAscTest, EveryFileInTheFolderLoads) {
  STARNAV_SKIP_WITHOUT_SHARED("datasets/dem");
  int loaded = 0;
  for (const auto& entry : fs::recursive_directory_iterator(test::shared_path("datasets/dem"))) {
    const std::string path = entry.path().string();
    const std::string ext = entry.path().extension().string();
    SCOPED_TRACE(path);
    if (ext == ".asc") {
      std::ifstream in(path);
      std::string key;
      long ncols = 0, nrows = 0;
      for (int i = 0; i < 2; ++i) {
        long v = 0;
        in >> key >> v;
        for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        (key == "ncols" ? ncols : nrows) = v;
      }
      const ElevationMap m = read_asc(path);
      EXPECT_EQ(m.width(), ncols);
      EXPECT_EQ(m.height(), nrows);
      expect_no_nan(m);
      ++loaded;
    } else if (ext == ".tif" && test::expect_geotiff()) {
      const ElevationMap m = read_geotiff(path);
      EXPECT_GT(m.observed_count(), 0u);
      expect_no_nan(m);
      ++loaded;
    }
  }
  EXPECT_GE(loaded, test::expect_geotiff() ? 9 : 6);
}

const DemFact kTiffFacts[] = {
    // 3 arc-seconds around 32.67 N: 78.0 m east-west, 92.4 m north-south; geometric mean ~84.9 m.
    {"pysheds/dem.tif", 367, 359, 147, 298, 0, 0, 84.5, 85.3},
    // 30 arc-seconds around 49.8 N: 600 m east-west, 927 m north-south; mean ~746 m.
    {"terra/elev.tif", 95, 90, 141, 547, 0, 3942, 740, 752},
    {"terra/elev_vinschgau.tif", 252, 194, 388, 3863, 0, 445, 250, 250},
};

TEST(SharedDemGeoTiffTest, EveryGeoTiffLoadsWithItsFacts) {
  if (!test::expect_geotiff()) GTEST_SKIP() << "without GDAL";
  STARNAV_SKIP_WITHOUT_SHARED("datasets/dem");
  for (const DemFact& f : kTiffFacts) {
    const std::string path = test::shared_path("datasets/dem/" + std::string(f.file));
    ASSERT_FALSE(path.empty()) << f.file;
    testing::internal::CaptureStderr();
    const ElevationMap m = read_geotiff(path);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << f.file;
    check_dem(m, f);
  }
  ElevationGeoref g;
  const ElevationMap v = read_geotiff(test::shared_path("datasets/dem/terra/elev_vinschgau.tif"), &g);
  EXPECT_EQ(g.crs, ElevationGeoref::Crs::Projected);
  EXPECT_EQ(v.origin().x, 598250.0);
  EXPECT_EQ(v.origin().y, 5193000.0 - 194 * 250.0);
  const ElevationMap p = read_geotiff(test::shared_path("datasets/dem/pysheds/dem.tif"), &g);
  EXPECT_EQ(g.crs, ElevationGeoref::Crs::Geographic);
  const double lat = 32.821666666665358 - 359 * 0.000833333333333 / 2;
  EXPECT_NEAR(g.centre_latitude_deg, lat, 1e-9);
  EXPECT_NEAR(p.resolution(), 0.000833333333333 * std::sqrt(series_lat(lat) * series_lon(lat)), 1e-3);
}

// The plugin is found exactly when this build and run should have it (docs/formats.md, "GeoTIFF").
TEST(GeoTiffTest, PluginIsAvailableExactlyWhenExpected) {
  const GeotiffSupport support = geotiff_support();
  EXPECT_EQ(support.available, test::expect_geotiff()) << support.detail;
  if (!support.available) {
    EXPECT_EQ(support.detail.rfind("GeoTIFF support needs GDAL: ", 0), 0u) << support.detail;
  }
}

TEST(GeoTiffTest, GdalErrorsBecomeOneLineErrorsAndStderrStaysQuiet) {
  ScratchDir dir;
  write_text(dir.file("not.tif"), "this is not a TIFF\n");
  testing::internal::CaptureStderr();
  const std::string what = error_of([&] { read_geotiff(dir.file("not.tif")); });
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(what.rfind(dir.file("not.tif") + ": ", 0), 0u) << what;
  EXPECT_EQ(err, "");
  if (!test::expect_geotiff()) {
    EXPECT_NE(what.find("GeoTIFF support needs GDAL: "), std::string::npos) << what;
  }
  const std::string missing = error_of([&] { read_geotiff(dir.file("missing.tif")); });
  EXPECT_EQ(missing.rfind(dir.file("missing.tif") + ": ", 0), 0u) << missing;
  if (test::expect_geotiff()) {
    // An ASCII grid is not a GeoTIFF even though GDAL could read it.
    write_text(dir.file("grid.tif"), "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n5\n");
    EXPECT_NE(error_of([&] { read_geotiff(dir.file("grid.tif")); }).find(dir.file("grid.tif")), std::string::npos);
  }
}

}  // namespace
}  // namespace starnav
