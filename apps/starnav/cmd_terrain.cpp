// starnav terrain generate: seeded terrains (hills, road-PSD stochastic ground) in every
// elevation format, with a metadata sidecar FILE.terrain.json (docs/terrain.md).
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/terrain/terrain_generator.hpp"
#include "starnav/terrain/terrain_metadata.hpp"

namespace starnav::cli {

namespace {

struct TerrainGenerateOptions {
  std::string kind;
  std::string road_class;
  std::string method;
  std::string size_m;
  std::string resolution;
  std::string seed = "0";
  std::string amplitude;
  std::string band;
  std::string intervals;
  std::string directions;
  std::string blur_cells;
  std::vector<std::string> pits;
  std::vector<std::string> mounds;
  std::string out;
  bool force = false;
  bool json = false;
};

double parse_number(const std::string& text, const std::string& flag) {
  double v = 0.0;
  if (!parse_double(text, v)) throw Error("expected a number, got '" + text + "'", {}, 0, flag);
  return v;
}

double parse_positive(const std::string& text, const std::string& flag) {
  const double v = parse_number(text, flag);
  if (!(v > 0.0)) throw Error("must be > 0, got '" + text + "'", {}, 0, flag);
  return v;
}

int parse_count(const std::string& text, const std::string& flag, int lo, int hi) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 9)
    throw Error("expected an integer " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + text + "'", {}, 0,
                flag);
  const int v = std::atoi(text.c_str());
  if (v < lo || v > hi)
    throw Error("expected an integer " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + text + "'", {}, 0,
                flag);
  return v;
}

TerrainFeature parse_feature(const std::string& text, TerrainFeature::Kind kind, const std::string& flag) {
  const char* what = kind == TerrainFeature::Kind::Pit ? "X,Y,RADIUS,DEPTH (metres)" : "X,Y,RADIUS,HEIGHT (metres)";
  const std::vector<double> v = parse_number_list(text, flag, 4, what);
  if (!(v[2] > 0.0) || !(v[3] > 0.0)) throw Error(std::string("radius and depth must be > 0 in ") + what, {}, 0, flag);
  TerrainFeature f;
  f.kind = kind;
  f.centre = Vec2(v[0], v[1]);
  f.radius_m = v[2];
  f.depth_m = v[3];
  return f;
}

void require_kind(bool given, bool allowed, const std::string& flag, const char* kind) {
  if (given && !allowed) throw Error(std::string("only for --kind ") + kind, {}, 0, flag);
}

void run_terrain_generate(const TerrainGenerateOptions& o) {
  if (o.kind != "hills" && o.kind != "road")
    throw Error("unknown kind '" + o.kind + "' (hills, road)", {}, 0, "--kind");
  const bool road = o.kind == "road";
  require_kind(!o.road_class.empty(), road, "--class", "road");
  require_kind(!o.method.empty(), road, "--method", "road");
  require_kind(!o.band.empty(), road, "--band", "road");
  require_kind(!o.intervals.empty(), road, "--intervals", "road");
  require_kind(!o.directions.empty(), road, "--directions", "road");
  require_kind(!o.blur_cells.empty(), road, "--blur-cells", "road");
  require_kind(!o.amplitude.empty(), !road, "--amplitude", "hills");

  const Vec2 size = parse_xy(o.size_m, "--size-m");
  if (!(size.x() > 0.0) || !(size.y() > 0.0)) throw Error("width and height must be > 0", {}, 0, "--size-m");
  const double resolution = parse_positive(o.resolution, "--resolution");
  const std::uint64_t seed = parse_unsigned(o.seed, "--seed", "a non-negative integer");
  std::vector<TerrainFeature> features;
  for (const auto& p : o.pits) features.push_back(parse_feature(p, TerrainFeature::Kind::Pit, "--pit"));
  for (const auto& m : o.mounds) features.push_back(parse_feature(m, TerrainFeature::Kind::Mound, "--mound"));

  // Output checks before any work.
  const MapFormat format = output_map_format(o.out, true);
  if (format == MapFormat::MovingAi || format == MapFormat::RosMap || format == MapFormat::GeoTiff)
    throw Error("not a writable elevation format (use .yaml, .asc, .csv, .raw)", o.out, 0, "--out");
  for (const std::string& f : map_output_files(o.out, format)) check_output_path(f, o.force, "--out");
  const std::string meta_path = o.out + ".terrain.json";
  check_output_path(meta_path, o.force, "--out");
  std::vector<CommandFile> files;
  add_map_files(files, o.out, format, std::nullopt, "--out");
  files.push_back({meta_path, "--out (written beside " + o.out + ")"});
  check_distinct_files(files);

  // Geometry errors name the CLI flags.
  try {
    terrain_geometry(size.x(), size.y(), resolution);
  } catch (const Error& e) {
    throw Error(e.message(), {}, 0, e.field() == "resolution" ? "--resolution" : "--size-m");
  }

  std::string meta;
  double sigma2 = 0.0;  // road: the heights' variance
  LoadedMap out;
  out.format = format;
  if (!road) {
    HillsOptions h;
    h.width_m = size.x();
    h.height_m = size.y();
    h.resolution = resolution;
    h.seed = seed;
    if (!o.amplitude.empty()) {
      h.amplitude = parse_number(o.amplitude, "--amplitude");
      if (h.amplitude < 0.0) throw Error("must be >= 0", {}, 0, "--amplitude");
    }
    h.features = features;
    out.map = generate_hills(h);
    meta = hills_metadata(h, out.elevation(), o.out, map_format_name(format));
  } else {
    RoadOptions r;
    r.width_m = size.x();
    r.height_m = size.y();
    r.resolution = resolution;
    r.seed = seed;
    if (!o.road_class.empty()) {
      if (o.road_class.size() != 1) throw Error("unknown road class '" + o.road_class + "' (A..H)", {}, 0, "--class");
      road_class_gd_n0(o.road_class[0], "--class");
      r.road_class = static_cast<char>(std::toupper(static_cast<unsigned char>(o.road_class[0])));
    }
    if (!o.method.empty()) r.method = parse_road_method(o.method, "--method");
    if (!o.band.empty()) {
      const std::vector<double> b = parse_number_list(o.band, "--band", 2, "N1,N2 (1/m)");
      if (!(b[0] > 0.0) || !(b[1] > b[0])) throw Error("need 0 < N1 < N2", {}, 0, "--band");
      r.n1 = b[0];
      r.n2 = b[1];
    }
    if (!o.intervals.empty()) r.intervals = parse_count(o.intervals, "--intervals", 1, kMaxRoadIntervals);
    if (!o.directions.empty() && r.method != RoadMethod::Directional)
      throw Error("only for --method directional (the paper method has no directions)", {}, 0, "--directions");
    if (!o.blur_cells.empty() && r.method != RoadMethod::Paper)
      throw Error("only for --method paper (the directional method does not blur)", {}, 0, "--blur-cells");
    if (!o.directions.empty()) r.directions = parse_count(o.directions, "--directions", 1, kMaxRoadDirections);
    if (!o.blur_cells.empty()) {
      r.blur_sigma_cells = parse_number(o.blur_cells, "--blur-cells");
      if (r.blur_sigma_cells < 0.0) throw Error("must be >= 0", {}, 0, "--blur-cells");
    }
    r.features = features;
    RoadTerrain t;
    try {
      t = generate_road(r);
    } catch (const Error& e) {
      rethrow_with_flag(e, {{"blur_sigma_cells", "--blur-cells"}});
    }
    meta = road_metadata(r, t, o.out, map_format_name(format));
    sigma2 = t.spectrum.sigma2;
    out.map = std::move(t.map);
  }
  const ElevationMap& map = out.elevation();

  save_map(out, o.out, format);
  write_text_file(meta_path, meta, "--out");
  if (o.json) {
    std::cout << meta;
  } else {
    std::cout << "wrote " << o.out << " (" << map_format_name(format) << ", " << map.width() << " x " << map.height()
              << " cells)";
    if (road) std::cout << ", sigma^2 = " << sigma2 << " m^2";
    std::cout << "; metadata " << meta_path << "\n";
  }
}

}  // namespace

void register_terrain_commands(CLI::App& app, Context& ctx) {
  auto* terrain = app.add_subcommand("terrain", "generate terrains (elevation maps)");
  terrain->require_subcommand(1);

  auto o = std::make_shared<TerrainGenerateOptions>();
  auto* gen = terrain->add_subcommand(
      "generate", "seeded terrain: hills (Gaussian hills + roughness) or road (ISO 8608 / GB/T 7031 PSD class)");
  gen->add_option("--kind", o->kind, "hills | road")->required();
  gen->add_option("--class", o->road_class, "road class A..H (road; default C)");
  gen->add_option("--method", o->method, "directional (default) | paper (road)");
  gen->add_option("--size-m", o->size_m, "W,H: map size in metres")->required();
  gen->add_option("--resolution", o->resolution, "metres per cell")->required();
  gen->add_option("--seed", o->seed, "random seed (default 0)");
  gen->add_option("--amplitude", o->amplitude, "height scale (hills; default 1)");
  gen->add_option("--band", o->band, "N1,N2: spatial frequency band in 1/m (road; default 0.011,2.83)");
  gen->add_option("--intervals", o->intervals, "log-spaced frequency intervals (road; default 64)");
  gen->add_option("--directions", o->directions, "wave directions (road, directional; default 16)");
  gen->add_option("--blur-cells", o->blur_cells, "Gaussian blur sigma in cells (road, paper; default 2)");
  gen->add_option("--pit", o->pits, "X,Y,RADIUS,DEPTH: a pit (metres, world frame; repeatable)");
  gen->add_option("--mound", o->mounds, "X,Y,RADIUS,HEIGHT: a mound (metres, world frame; repeatable)");
  gen->add_option("--out", o->out, "output file: .yaml (16-bit PNG + YAML), .asc, .csv, .raw (Unity)")->required();
  gen->add_flag("--force", o->force, "overwrite existing outputs");
  gen->add_flag("--json", o->json, "print the metadata as JSON");
  gen->callback([o, &ctx] {
    run_terrain_generate(*o);
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
