#include "starnav/terrain/terrain_metadata.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace starnav {

namespace {

using json = nlohmann::ordered_json;

json feature_json(const TerrainFeature& f) {
  json j;
  j["kind"] = f.kind == TerrainFeature::Kind::Pit ? "pit" : "mound";
  j["centre_m"] = {f.centre.x(), f.centre.y()};
  j["radius_m"] = f.radius_m;
  j[f.kind == TerrainFeature::Kind::Pit ? "depth_m" : "height_m"] = f.depth_m;
  return j;
}

// The map's part (size, features, height range) and the file's; the document as text.
std::string finish(json& meta, const ElevationMap& map, const std::vector<TerrainFeature>& features,
                   const std::string& file, const std::string& format) {
  meta["width"] = map.width();
  meta["height"] = map.height();
  meta["resolution_m"] = map.resolution();
  meta["size_m"] = {map.geometry().width_m(), map.geometry().height_m()};
  json fj = json::array();
  for (const auto& f : features) fj.push_back(feature_json(f));
  meta["features"] = fj;
  const auto range = map.height_range();
  meta["z_min_m"] = range ? range->min : 0.0;
  meta["z_max_m"] = range ? range->max : 0.0;
  meta["file"] = file;
  meta["format"] = format;
  return meta.dump(2) + "\n";
}

}  // namespace

std::string hills_metadata(const HillsOptions& h, const ElevationMap& map, const std::string& file,
                           const std::string& format) {
  json meta;
  meta["kind"] = "hills";
  meta["seed"] = h.seed;
  meta["amplitude"] = h.amplitude;
  meta["hills_per_100m2"] = h.hills_per_100m2;
  meta["hill_height_m"] = {h.hill_height_min_m, h.hill_height_max_m};
  meta["hill_sigma_m"] = {h.hill_sigma_min_m, h.hill_sigma_max_m};
  meta["roughness_m"] = h.roughness_m;
  meta["roughness_correlation_m"] = h.roughness_correlation_m;
  return finish(meta, map, h.features, file, format);
}

std::string road_metadata(const RoadOptions& r, const RoadTerrain& t, const std::string& file, const std::string& format) {
  json meta;
  meta["kind"] = "road";
  meta["seed"] = r.seed;
  meta["class"] = std::string(1, r.road_class);
  meta["method"] = road_method_name(r.method);
  meta["gd_n0_m3"] = t.spectrum.gd_n0;
  meta["n0_per_m"] = r.n0;
  meta["waviness"] = r.waviness;
  meta["band_per_m"] = {r.n1, r.n2};
  meta["band_used_per_m"] = {t.spectrum.n_low, t.spectrum.n_high};
  meta["intervals"] = r.intervals;
  if (r.method == RoadMethod::Directional) meta["directions"] = r.directions;
  else meta["blur_sigma_cells"] = r.blur_sigma_cells;
  meta["sigma2_m2"] = t.spectrum.sigma2;
  meta["sigma_m"] = std::sqrt(t.spectrum.sigma2);
  return finish(meta, t.map, r.features, file, format);
}

}  // namespace starnav
