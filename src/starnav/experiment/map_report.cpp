#include "starnav/experiment/map_report.hpp"

#include <nlohmann/json.hpp>

namespace starnav {

std::string map_info_json(const LoadedMap& m, const std::string& file, const std::string& format, int indent) {
  const GridGeometry& g = m.geometry();
  nlohmann::ordered_json j;
  j["file"] = file.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(file);
  j["format"] = format.empty() ? std::string(map_format_name(m.format)) : format;
  j["width"] = g.width;
  j["height"] = g.height;
  j["resolution_m"] = g.resolution;
  j["origin"] = {g.origin.x, g.origin.y, g.origin.yaw};
  j["index_grid"] = g.y_down;
  if (m.is_elevation()) {
    const ElevationMap& e = m.elevation();
    const auto range = e.height_range();
    j["observed"] = e.observed_count();
    j["unobserved"] = e.cell_count() - e.observed_count();
    j["z_min_m"] = range ? nlohmann::ordered_json(range->min) : nlohmann::ordered_json(nullptr);
    j["z_max_m"] = range ? nlohmann::ordered_json(range->max) : nlohmann::ordered_json(nullptr);
  } else {
    const OccupancyCounts c = m.occupancy().counts(m.thresholds());
    j["free"] = c.free;
    j["occupied"] = c.occupied;
    j["unknown"] = c.unknown;
  }
  return j.dump(indent) + "\n";
}

}  // namespace starnav
