#pragma once
// Seeded terrain generators (docs/terrain.md):
//
//   hills  a smooth random surface: a sum of Gaussian hills (0.5-1.0 m high, a few metres wide)
//          plus small-scale roughness (Gaussian-blurred white noise), for the Liu 2024 experiment
//          (docs/papers/liu2024.md);
//   road   stochastic ground from a road-roughness PSD class (GB/T 7031 / ISO 8608, A-H) as in
//          docs/papers/li2019.md: Gd(n) = Gd(n0) (n / n0)^-W over a band clipped to what the grid
//          can hold, split into m log-spaced intervals; method `directional` (isotropic sum of
//          plane waves in K directions, the spectrum of the class) or `paper` (the paper's
//          per-cell random phase, blurred and rescaled);
//   features  pits and mounds: raised-cosine radial bumps added on top.
//
// Every random draw comes from starnav::Rng seeded with the options' seed: same options, same
// heights, bit for bit.
#include <cstdint>
#include <string>
#include <vector>

#include "starnav/core/geometry.hpp"
#include "starnav/core/params.hpp"
#include "starnav/map/elevation_map.hpp"

namespace starnav {

// The grid of a W x H metre map at a resolution: round(W / res) x round(H / res) cells, lower-left
// corner at `origin`. Throws Error naming "size_m" or "resolution" for non-positive or
// non-finite values and maps of less than one cell.
GridGeometry terrain_geometry(double width_m, double height_m, double resolution, const Pose2& origin = {});

// A pit (lowers) or mound (raises): dz(r) = -+ depth * (1 + cos(pi r / radius)) / 2 for r < radius.
struct TerrainFeature {
  enum class Kind : std::uint8_t { Pit, Mound };
  Kind kind = Kind::Mound;
  Vec2 centre{0, 0};     // world, metres
  double radius_m = 1.0;
  double depth_m = 0.5;  // depth of a pit / height of a mound, > 0
};
// Adds the feature to every observed cell whose centre lies within its radius. Throws Error for
// a non-positive or non-finite radius or depth ("radius_m", "depth_m").
void add_terrain_feature(ElevationMap& map, const TerrainFeature& feature);

struct HillsOptions {
  double width_m = 10.0;
  double height_m = 10.0;
  double resolution = 0.1;
  Pose2 origin{};
  std::uint64_t seed = 0;
  double amplitude = 1.0;            // multiplies every height (hills and roughness)
  double hills_per_100m2 = 12.0;     // number of hills = max(1, round(density * area / 100 m^2))
  double hill_height_min_m = 0.5;
  double hill_height_max_m = 1.0;
  double hill_sigma_min_m = 0.6;     // Gaussian sigma of a hill (its footprint is ~4 sigma wide)
  double hill_sigma_max_m = 1.5;
  double roughness_m = 0.01;         // standard deviation of the small-scale roughness
  double roughness_correlation_m = 0.2;  // Gaussian blur sigma of the roughness noise
  std::vector<TerrainFeature> features;
  void validate() const;  // Error naming the field
};
ElevationMap generate_hills(const HillsOptions& options);

enum class RoadMethod : std::uint8_t { Directional, Paper };
const char* road_method_name(RoadMethod m);  // "directional", "paper"
RoadMethod parse_road_method(const std::string& name, const std::string& field = "method");

// Gd(n0) of a road class 'A'..'H' (geometric mean of the class), m^3: A 16e-6 ... H 262144e-6.
// Throws Error naming `field` for anything else.
double road_class_gd_n0(char road_class, const std::string& field = "class");

// The road generator's counts, the same in the CLI and in scenario YAML (docs/terrain.md): its
// work grows with cells x intervals (x directions).
// The work a generator may plan, in elementary operations (a sine, an exponential or a
// multiply-add), estimated from the options before any is done: about a minute on one core.
inline constexpr double kMaxTerrainGenerationOperations = 1e10;
inline constexpr int kMaxRoadIntervals = 4096;
inline constexpr int kMaxRoadDirections = 1024;

struct RoadOptions {
  double width_m = 10.0;
  double height_m = 10.0;
  double resolution = 0.1;
  Pose2 origin{};
  std::uint64_t seed = 0;
  char road_class = 'C';
  double gd_n0 = 0.0;      // m^3; 0 = the class's value
  RoadMethod method = RoadMethod::Directional;
  double n0 = 0.1;         // reference spatial frequency, 1/m
  double n1 = 0.011;       // band, 1/m (clipped to [max(n1, 1/L), min(n2, 1/(2 res))])
  double n2 = 2.83;
  double waviness = 2.0;   // W
  int intervals = 64;      // m, 1..kMaxRoadIntervals
  int directions = 16;     // K (directional), 1..kMaxRoadDirections
  double blur_sigma_cells = 2.0;  // paper method
  std::vector<TerrainFeature> features;
  void validate() const;  // Error naming the field
};

// The discretised band: m log-spaced intervals between the clipped band edges, each with its
// centre (arithmetic midpoint) and width; sigma2 = sum Gd(n_i) dn_i.
struct RoadSpectrum {
  double gd_n0 = 0.0;   // m^3
  double n_low = 0.0;   // clipped band, 1/m
  double n_high = 0.0;
  std::vector<double> centres;  // n_i
  std::vector<double> widths;   // dn_i
  double sigma2 = 0.0;  // m^2
  double gd(double n) const;    // Gd(n)
  double n0 = 0.1;
  double waviness = 2.0;
};
// The spectrum for a map of width x height cells. Throws Error ("size_m") when the clipped band
// is empty (the map is too small or too coarse for it).
RoadSpectrum road_spectrum(const RoadOptions& options, int width_cells, int height_cells);

struct RoadTerrain {
  ElevationMap map;
  RoadSpectrum spectrum;
};
// Heights before features have expected mean 0 and expected variance spectrum.sigma2 at every cell.
RoadTerrain generate_road(const RoadOptions& options);

// The generators' options as declared parameters (the Python bindings' keyword arguments; the
// keys are the options' names, the origin as origin_x_m, origin_y_m, origin_yaw_deg; features are
// added apart, add_terrain_feature). Defaults are the structs'; validate() checks the rest.
const ParamTable<HillsOptions>& hills_params();
const ParamTable<RoadOptions>& road_params();

}  // namespace starnav
