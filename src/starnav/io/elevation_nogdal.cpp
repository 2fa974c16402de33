// GeoTIFF without GDAL: starnav was built with -DSTARNAV_WITH_GDAL=OFF (see elevation_gdal.cpp).
#include "starnav/core/error.hpp"
#include "starnav/io/elevation_io.hpp"

namespace starnav {

ElevationMap read_geotiff(const std::string& path) { return read_geotiff(path, nullptr); }

ElevationMap read_geotiff(const std::string& path, ElevationGeoref* /*georef*/) {
  throw Error("GeoTIFF support needs GDAL: rebuild with -DSTARNAV_WITH_GDAL=ON", path);
}

}  // namespace starnav
