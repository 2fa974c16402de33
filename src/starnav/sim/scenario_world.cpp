// The scenario's world section: terrain (a file or a generator, with pits and mounds), the
// occupancy map of an indoor world, and the obstacles.
#include <cctype>
#include <set>

#include "starnav/core/angle.hpp"
#include "starnav/sim/scenario_document.hpp"

namespace starnav::scenario_detail {

namespace {

struct NoKeys {};

const SectionDecl<NoKeys>& world_decl() {
  static const SectionDecl<NoKeys> d = [] {
    SectionDecl<NoKeys> s;
    s.id = "world";
    s.title = "world";
    s.structural = {
        {"terrain", "mapping", "none (no ground)", "", "", "exactly one of `file` or `generate`, plus optional `features` (world.terrain)"},
        {"occupancy_map", "path, or mapping", "none", "", "",
         "an indoor world from a map_server map (YAML + image, relative to the scenario): every occupied cell a wall "
         "(world.occupancy_map)"},
        {"obstacles", "list of mappings", "[]", "", "", "obstacles (world.obstacles[i])"},
    };
    return s;
  }();
  return d;
}

const SectionDecl<ScenarioOccupancyWorld>& occupancy_decl() {
  static const SectionDecl<ScenarioOccupancyWorld> d = [] {
    SectionDecl<ScenarioOccupancyWorld> s;
    s.id = "world.occupancy_map";
    s.title = "world.occupancy_map";
    s.table.text("file", &ScenarioOccupancyWorld::file, "the map_server YAML, relative to the scenario's folder")
        .real("wall_height_m", &ScenarioOccupancyWorld::wall_height_m, closed(0.01, 100.0), "m",
              "height of the walls standing on z = 0 (above any 2D LiDAR's mount)");
    s.required = {"file"};
    return s;
  }();
  return d;
}

const SectionDecl<ScenarioTerrain>& terrain_decl() {
  static const SectionDecl<ScenarioTerrain> d = [] {
    SectionDecl<ScenarioTerrain> s;
    s.id = "world.terrain";
    s.title = "world.terrain";
    s.table.text("file", &ScenarioTerrain::file,
                 "an elevation map starnav reads (docs/formats.md), relative to the scenario's folder; instead of `generate`");
    s.table.default_rule("file", "none");
    s.structural = {
        {"generate", "mapping", "none", "", "", "a generated terrain (world.terrain.generate); instead of `file`"},
        {"features", "list of mappings", "[]", "", "", "with `file`: pits and mounds (world.terrain.features[i])"},
    };
    return s;
  }();
  return d;
}

// A generated terrain's keys, read into one struct: the common keys and each kind's.
struct GenerateKeys {
  std::string kind;
  double resolution_m = 0.05;
  double origin_yaw_rad = 0.0;
  std::uint64_t seed = 0;
  double z_m = 0.0;
  HillsOptions hills;
  RoadOptions road;
  std::string road_class = "C";
};

const SectionDecl<GenerateKeys>& generate_decl() {
  static const SectionDecl<GenerateKeys> d = [] {
    SectionDecl<GenerateKeys> s;
    s.id = "world.terrain.generate";
    s.title = "world.terrain.generate";
    s.table
        .choice(
            "kind", {"flat", "hills", "road"}, [](GenerateKeys& g, const std::string& k) { g.kind = k; },
            [](const GenerateKeys& g) { return g.kind; }, "the generator (docs/terrain.md); the keys of each kind below")
        .real("resolution_m", &GenerateKeys::resolution_m, positive(), "m", "metres per cell")
        .real("origin_yaw_deg", &GenerateKeys::origin_yaw_rad, any_value(), "deg", "map rotation about its origin", kDeg);
    declare_seed(s.table, "seed", &GenerateKeys::seed,
                 "hills, road: the generator's seed; when absent the scenario's (so --seed changes the terrain)");
    s.table.default_rule("seed", "sim.seed");
    s.required = {"kind"};
    s.structural = {
        {"size_m", "[W, H]", "required", "both > 0", "m", "the map's size; at most 16,000,000 cells at resolution_m"},
        {"origin_m", "[x, y]", "[0, 0]", "", "m", "world position of the map's lower-left corner"},
        {"features", "list of mappings", "[]", "", "", "pits and mounds (world.terrain.features[i])"},
    };
    return s;
  }();
  return d;
}

const SectionDecl<GenerateKeys>& flat_decl() {
  static const SectionDecl<GenerateKeys> d = [] {
    SectionDecl<GenerateKeys> s;
    s.id = "world.terrain.generate.flat";
    s.title = "world.terrain.generate (kind: flat)";
    s.table.real("z_m", &GenerateKeys::z_m, any_value(), "m", "the height everywhere");
    return s;
  }();
  return d;
}

const SectionDecl<GenerateKeys>& hills_decl() {
  static const SectionDecl<GenerateKeys> d = [] {
    SectionDecl<GenerateKeys> s;
    s.id = "world.terrain.generate.hills";
    s.title = "world.terrain.generate (kind: hills)";
    const auto h = [](auto member) { return [member](GenerateKeys& g) -> double& { return g.hills.*member; }; };
    s.table.real("amplitude", h(&HillsOptions::amplitude), non_negative(), "", "scales every height")
        .real("hills_per_100m2", h(&HillsOptions::hills_per_100m2), non_negative(), "1/(100 m^2)", "hill density")
        .real("roughness_m", h(&HillsOptions::roughness_m), non_negative(), "m", "standard deviation of the small-scale roughness")
        .real("roughness_correlation_m", h(&HillsOptions::roughness_correlation_m), positive(), "m", "the roughness's blur sigma");
    s.structural = {
        {"hill_height_m", "[min, max]", "[0.5, 1]", "", "m", "a hill's height"},
        {"hill_sigma_m", "[min, max]", "[0.6, 1.5]", "", "m", "Gaussian width of a hill"},
    };
    return s;
  }();
  return d;
}

const SectionDecl<GenerateKeys>& road_decl() {
  static const SectionDecl<GenerateKeys> d = [] {
    SectionDecl<GenerateKeys> s;
    s.id = "world.terrain.generate.road";
    s.title = "world.terrain.generate (kind: road)";
    const auto r = [](auto member) {
      return [member](GenerateKeys& g) -> std::remove_reference_t<decltype(g.road.*member)>& { return g.road.*member; };
    };
    // Lower case is accepted too (the class is a letter of GB/T 7031).
    s.table.choice(
        "class", {"A", "B", "C", "D", "E", "F", "G", "H"}, [](GenerateKeys& g, const std::string& c) { g.road_class = c; },
        [](const GenerateKeys& g) { return g.road_class; }, "road class (GB/T 7031 / ISO 8608)", false);
    s.table.real("gd_n0_m3", r(&RoadOptions::gd_n0), non_negative(), "m^3", "Gd(n0); 0: the class's")
        .choice(
            "method", {"directional", "paper"},
            [](GenerateKeys& g, const std::string& m) { g.road.method = parse_road_method(m); },
            [](const GenerateKeys& g) { return std::string(road_method_name(g.road.method)); }, "spec section 3")
        .real("n0_per_m", r(&RoadOptions::n0), positive(), "1/m", "reference spatial frequency")
        .real("waviness", r(&RoadOptions::waviness), positive(), "", "W")
        .integer("intervals", r(&RoadOptions::intervals), closed(1, kMaxRoadIntervals), "", "m: frequency intervals")
        .integer("directions", r(&RoadOptions::directions), closed(1, kMaxRoadDirections), "",
                 "K: directions (method directional only)")
        .real("blur_sigma_cells", r(&RoadOptions::blur_sigma_cells), positive(), "cells", "the blur (method paper only)");
    s.structural = {{"band_per_m", "[n1, n2]", "[0.011, 2.83]", "0 < n1 < n2", "1/m", "frequency band (clipped to the grid)"}};
    return s;
  }();
  return d;
}

struct FeatureKeys {
  TerrainFeature feature;
};

const SectionDecl<FeatureKeys>& feature_decl() {
  static const SectionDecl<FeatureKeys> d = [] {
    SectionDecl<FeatureKeys> s;
    s.id = "world.terrain.features";
    s.title = "world.terrain.features[i]";
    s.table
        .choice(
            "kind", {"pit", "mound"},
            [](FeatureKeys& f, const std::string& k) {
              f.feature.kind = k == "pit" ? TerrainFeature::Kind::Pit : TerrainFeature::Kind::Mound;
            },
            [](const FeatureKeys& f) { return std::string(f.feature.kind == TerrainFeature::Kind::Pit ? "pit" : "mound"); },
            "a pit lowers the ground, a mound raises it (raised cosine)")
        .real("radius_m", [](FeatureKeys& f) -> double& { return f.feature.radius_m; }, positive(), "m", "its radius")
        .real("depth_m", [](FeatureKeys& f) -> double& { return f.feature.depth_m; }, positive(), "m",
              "the pit's depth or the mound's height");
    s.required = {"kind", "radius_m", "depth_m"};
    s.structural = {{"centre_m", "[x, y]", "required", "", "m", "its centre in the world"}};
    return s;
  }();
  return d;
}

// An obstacle's keys: the common ones and every kind's shape.
struct ObstacleKeys {
  ScenarioObstacle o;
  Box box;
  Cylinder cylinder;
  Prism prism;
  Sphere sphere;
  SlopeStep slope_step;
  UndulatingGround undulating;
  RoundConvex round_convex;
  Gravel gravel;
};

const std::vector<std::string>& obstacle_kinds() {
  static const std::vector<std::string> k = {"box",   "cylinder", "prism", "sphere", "slope_step", "undulating_ground",
                                             "round_convex", "gravel"};
  return k;
}

const SectionDecl<ObstacleKeys>& obstacle_decl() {
  static const SectionDecl<ObstacleKeys> d = [] {
    SectionDecl<ObstacleKeys> s;
    s.id = "world.obstacles";
    s.title = "world.obstacles[i]";
    const auto o = [](auto member) { return [member](ObstacleKeys& k) -> auto& { return k.o.*member; }; };
    s.table
        .choice(
            "kind", obstacle_kinds(), [](ObstacleKeys& k, const std::string& v) { k.o.kind = v; },
            [](const ObstacleKeys& k) { return k.o.kind; }, "the shape; each kind's keys below")
        .text("name", o(&ScenarioObstacle::name), "unique; used in events and pictures")
        .real("appear_s", o(&ScenarioObstacle::appear_s), any_value(), "s", "the obstacle exists from this time ...")
        .real("disappear_s", o(&ScenarioObstacle::disappear_s), any_value(), "s",
              "... until this one (later than appear_s); outside that interval sensors and the robot do not see it");
    s.table.default_rule("name", "KIND_INDEX").default_rule("disappear_s", "never");
    s.required = {"kind"};
    s.structural = {
        {"position_m", "[x, y] or [x, y, z]", "required", "", "m",
         "the centre of the obstacle's footprint on the ground; without z, the terrain height under (x, y) (0 without terrain)"},
        {"velocity_mps", "[vx, vy] or [vx, vy, vz]", "none", "", "m/s", "constant velocity from appear_s on"},
        {"waypoints", "list of mappings", "none", "", "",
         "the position over time (world.obstacles[i].waypoints[j]): piecewise linear, held at the first before its time "
         "and at the last after; times strictly increasing. Exclusive with velocity_mps"},
    };
    return s;
  }();
  return d;
}

// The yaw, roll and pitch of a shape, in degrees.
template <class Shape>
void declare_yaw(ParamTable<ObstacleKeys>& t, Shape ObstacleKeys::*shape) {
  t.real("yaw_deg", [shape](ObstacleKeys& k) -> double& { return (k.*shape).yaw; }, any_value(), "deg",
         "heading about z (0: the direction of travel across it is +x)", kDeg);
}

template <class Shape>
auto shape_member(Shape ObstacleKeys::*shape, auto member) {
  return [shape, member](ObstacleKeys& k) -> auto& { return (k.*shape).*member; };
}

const SectionDecl<ObstacleKeys>& obstacle_kind_decl(const std::string& kind) {
  static const std::vector<SectionDecl<ObstacleKeys>> decls = [] {
    std::vector<SectionDecl<ObstacleKeys>> all;
    const auto make = [&](const std::string& kind) -> SectionDecl<ObstacleKeys>& {
      all.emplace_back();
      all.back().id = "world.obstacles." + kind;
      all.back().title = "world.obstacles[i] (kind: " + kind + ")";
      return all.back();
    };
    {
      auto& s = make("box");
      declare_yaw(s.table, &ObstacleKeys::box);
      s.table.real("roll_deg", shape_member(&ObstacleKeys::box, &Box::roll), any_value(), "deg", "roll about x", kDeg)
          .real("pitch_deg", shape_member(&ObstacleKeys::box, &Box::pitch), any_value(), "deg", "pitch about y", kDeg);
      s.structural = {{"size_m", "[x, y, z]", "required", "each > 0", "m", "the box's centre is size_z / 2 above position_m"}};
    }
    {
      auto& s = make("cylinder");
      s.table.real("radius_m", shape_member(&ObstacleKeys::cylinder, &Cylinder::radius), positive(), "m", "vertical axis")
          .real("height_m", shape_member(&ObstacleKeys::cylinder, &Cylinder::height), positive(), "m",
                "position_m is the bottom disc's centre");
      s.required = {"radius_m", "height_m"};
    }
    {
      auto& s = make("prism");
      declare_yaw(s.table, &ObstacleKeys::prism);
      s.table.real("base_width_m", shape_member(&ObstacleKeys::prism, &Prism::base_width), positive(), "m",
                   "the triangle's base, along the prism's x")
          .real("height_m", shape_member(&ObstacleKeys::prism, &Prism::height), positive(), "m", "the apex's height")
          .real("length_m", shape_member(&ObstacleKeys::prism, &Prism::length), positive(), "m", "extrusion along the prism's y")
          .real("apex_offset_m", shape_member(&ObstacleKeys::prism, &Prism::apex_offset), any_value(), "m",
                "the apex's x in the prism frame, in [-base_width_m / 2, base_width_m / 2]");
      s.required = {"base_width_m", "height_m", "length_m"};
    }
    {
      auto& s = make("sphere");
      s.table.real("radius_m", shape_member(&ObstacleKeys::sphere, &Sphere::radius), positive(), "m",
                   "position_m is its lowest point");
      s.required = {"radius_m"};
    }
    {
      auto& s = make("slope_step");
      declare_yaw(s.table, &ObstacleKeys::slope_step);
      const auto m = [](auto member) { return shape_member(&ObstacleKeys::slope_step, member); };
      s.table.real("width_m", m(&SlopeStep::width), positive(), "m", "across the direction of travel")
          .real("ramp_length_m", m(&SlopeStep::ramp_length), positive(), "m", "horizontal length of each ramp")
          .real("ramp_height_m", m(&SlopeStep::ramp_height), positive(), "m", "the platforms' height")
          .real("platform_length_m", m(&SlopeStep::platform_length), positive(), "m", "each of the two platforms")
          .real("step_height_m", m(&SlopeStep::step_height), positive(), "m", "the middle box above the platforms")
          .real("step_length_m", m(&SlopeStep::step_length), positive(), "m", "the middle box's length")
          .real("depth_m", m(&SlopeStep::depth), non_negative(), "m", "the boxes reach this far below position_m");
    }
    {
      auto& s = make("undulating_ground");
      declare_yaw(s.table, &ObstacleKeys::undulating);
      const auto m = [](auto member) { return shape_member(&ObstacleKeys::undulating, member); };
      s.table.integer("count", m(&UndulatingGround::count), closed(1, 1000), "", "ridges")
          .real("base_width_m", m(&UndulatingGround::base_width), positive(), "m", "along x, per ridge")
          .real("height_m", m(&UndulatingGround::height), positive(), "m", "a ridge's height")
          .real("width_m", m(&UndulatingGround::width), positive(), "m", "across");
    }
    {
      auto& s = make("round_convex");
      declare_yaw(s.table, &ObstacleKeys::round_convex);
      const auto m = [](auto member) { return shape_member(&ObstacleKeys::round_convex, member); };
      s.table.real("radius_m", m(&RoundConvex::radius), positive(), "m", "the cylinder on the box")
          .real("cylinder_height_m", m(&RoundConvex::cylinder_height), positive(), "m", "its height")
          .real("depth_m", m(&RoundConvex::depth), non_negative(), "m", "the box reaches this far below position_m");
      s.structural = {{"box_size_m", "[x, y, z]", "[1.2, 1.2, 0.04]", "each > 0", "m", "the box"}};
    }
    {
      auto& s = make("gravel");
      declare_yaw(s.table, &ObstacleKeys::gravel);
      const auto m = [](auto member) { return shape_member(&ObstacleKeys::gravel, member); };
      s.table.real("length_m", m(&Gravel::length), positive(), "m", "the field's length")
          .real("width_m", m(&Gravel::width), positive(), "m", "the field's width")
          .integer("count", m(&Gravel::count), closed(1, 100000), "",
                   "pieces (at most 1,000,000 over all gravel fields of a scenario)")
          .real("size_min_m", m(&Gravel::size_min), positive(), "m", "smallest piece")
          .real("size_max_m", m(&Gravel::size_max), positive(), "m", "largest piece (>= size_min_m)")
          .real("sphere_fraction", m(&Gravel::sphere_fraction), closed(0.0, 1.0), "", "the share of spheres (the rest boxes)")
          .real("embed", m(&Gravel::embed), ParamRange{0.0, 1.0, false, true}, "", "how deep a piece sinks, as a fraction of its size");
      declare_seed(s.table, "seed", m(&Gravel::seed), "the pieces' seed; when absent the scenario's");
      s.table.default_rule("seed", "sim.seed");
      s.table.boolean("follow_terrain", m(&Gravel::follow_terrain), "pieces rest on the terrain under them");
    }
    return all;
  }();
  for (const SectionDecl<ObstacleKeys>& d : decls)
    if (d.id == "world.obstacles." + kind) return d;
  return decls.front();
}

struct WaypointKeys {
  double t_s = 0.0;
};

const SectionDecl<WaypointKeys>& waypoint_decl() {
  static const SectionDecl<WaypointKeys> d = [] {
    SectionDecl<WaypointKeys> s;
    s.id = "world.obstacles.waypoints";
    s.title = "world.obstacles[i].waypoints[j]";
    s.table.real("t_s", &WaypointKeys::t_s, any_value(), "s", "the time of this position (strictly increasing)");
    s.required = {"t_s"};
    s.structural = {{"position_m", "[x, y] or [x, y, z]", "required", "", "m", "without z, the obstacle's height"}};
    return s;
  }();
  return d;
}

TerrainFeature parse_feature(const Value& v, const Doc& doc) {
  Fields f(v, doc);
  require_all(f, feature_decl());
  FeatureKeys k;
  apply_section(f, feature_decl(), k, {"kind"});
  const std::vector<double> c = f.required("centre_m").numbers(2, 2);
  k.feature.centre = Vec2(c[0], c[1]);
  apply_section(f, feature_decl(), k);
  return k.feature;
}

void parse_features(const Value& v, const Doc& doc, std::vector<TerrainFeature>& out) {
  const std::size_t n = v.list("features");
  for (std::size_t i = 0; i < n; ++i) out.push_back(parse_feature(v.element(i), doc));
}

void parse_generate(Fields& g, ScenarioTerrain& t, const Doc& doc) {
  GenerateKeys k;
  require_all(g, generate_decl());
  apply_section(g, generate_decl(), k, {"kind"});
  const SectionDecl<GenerateKeys>& kind = k.kind == "flat" ? flat_decl() : k.kind == "hills" ? hills_decl() : road_decl();
  t.kind = k.kind == "flat" ? ScenarioTerrain::Kind::Flat : k.kind == "hills" ? ScenarioTerrain::Kind::Hills : ScenarioTerrain::Kind::Road;

  const std::vector<double> size = g.required("size_m").numbers(2, 2);
  if (!(size[0] > 0.0) || !(size[1] > 0.0)) g.fail_at("size_m", "width and height must be > 0");
  Pose2 origin;
  if (auto o = g.take("origin_m")) {
    const std::vector<double> p = o->numbers(2, 2);
    origin = Pose2(p[0], p[1], 0.0);
  }
  if (auto fl = g.take("features")) parse_features(*fl, doc, t.features);
  HillsOptions& h = k.hills;
  RoadOptions& r = k.road;
  if (t.kind == ScenarioTerrain::Kind::Hills) {
    if (auto v = g.take("hill_height_m")) {
      const auto p = v->numbers(2, 2);
      h.hill_height_min_m = p[0];
      h.hill_height_max_m = p[1];
    }
    if (auto v = g.take("hill_sigma_m")) {
      const auto p = v->numbers(2, 2);
      h.hill_sigma_min_m = p[0];
      h.hill_sigma_max_m = p[1];
    }
  }
  if (t.kind == ScenarioTerrain::Kind::Road) {
    if (auto v = g.take("band_per_m")) {
      const auto b = v->numbers(2, 2);
      if (!(b[0] > 0.0) || !(b[1] > b[0])) v->fail("need 0 < n1 < n2");
      r.n1 = b[0];
      r.n2 = b[1];
    }
  }
  apply_section(g, {&generate_decl(), &kind}, k);
  origin.yaw = k.origin_yaw_rad;
  t.seed_given = g.has("seed");
  t.flat_z_m = k.z_m;
  try {
    const GridGeometry geometry = terrain_geometry(size[0], size[1], k.resolution_m, origin);
    // The simulator keeps several layers per cell (heights, surface, height pyramid): a small
    // file must not be able to ask for tens of gigabytes.
    if (geometry.cell_count() > kMaxTerrainCells)
      throw Error("the terrain would have " + std::to_string(geometry.cell_count()) + " cells; the simulator takes at most " +
                      std::to_string(kMaxTerrainCells) + " (a coarser resolution_m or a smaller size_m)",
                  {}, 0, "size_m");
  } catch (const Error& e) {
    g.fail_at(e.field() == "resolution" ? "resolution_m" : "size_m", e.message());
  }
  for (auto* geometry : {&h.width_m, &r.width_m}) *geometry = size[0];
  for (auto* geometry : {&h.height_m, &r.height_m}) *geometry = size[1];
  h.resolution = r.resolution = k.resolution_m;
  h.origin = r.origin = origin;
  h.seed = r.seed = k.seed;

  if (t.kind == ScenarioTerrain::Kind::Hills) {
    try {
      h.validate();
    } catch (const Error& e) {
      rethrow_at(e, doc, g.line(), g.field());
    }
  } else if (t.kind == ScenarioTerrain::Kind::Road) {
    if (g.has("class")) {
      const std::string& c = k.road_class;
      if (c.size() != 1) g.fail_at("class", "unknown road class '" + c + "' (A..H)");
      try {
        road_class_gd_n0(c[0], "class");
      } catch (const Error& e) {
        g.fail_at("class", e.message());
      }
      r.road_class = static_cast<char>(std::toupper(static_cast<unsigned char>(c[0])));
    }
    // Each method's own knob is refused with the other method rather than silently ignored.
    if (g.has("directions") && r.method != RoadMethod::Directional)
      g.fail_at("directions", "only for method directional (the paper method has no directions)");
    if (g.has("blur_sigma_cells") && r.method != RoadMethod::Paper)
      g.fail_at("blur_sigma_cells", "only for method paper (the directional method does not blur)");
    try {
      r.validate();
    } catch (const Error& e) {
      rethrow_at(e, doc, g.line(), g.field());
    }
  }
  t.hills = h;
  t.road = r;
}

ScenarioTerrain parse_terrain(const Value& v, const Doc& doc) {
  Fields f(v, doc);
  ScenarioTerrain t;
  t.source = {v.line(), v.field()};
  const bool has_file = f.has("file"), has_gen = f.has("generate");
  if (has_file == has_gen) f.fail("give exactly one of 'file' or 'generate'");
  if (has_file) {
    t.kind = ScenarioTerrain::Kind::File;
    apply_section(f, terrain_decl(), t, {"file"});
    if (t.file.empty()) f.fail_at("file", "empty path");
    t.resolved_file = resolve_path(doc, t.file);
    t.source = {f.line_of("file"), f.path("file")};
    if (auto fl = f.take("features")) parse_features(*fl, doc, t.features);
  } else {
    Value gv = f.required("generate");
    Fields g(gv, doc);
    if (gv.node().IsNull()) gv.fail("expected a mapping with at least 'kind' and 'size_m'");
    parse_generate(g, t, doc);
    t.source = {gv.line(), gv.field()};
    // A generated terrain takes its features inside 'generate:'; say so rather than list 'features' as allowed.
    if (auto fl = f.take("features")) fl->fail("with 'generate', put 'features' inside 'generate:'");
  }
  apply_section(f, terrain_decl(), t);
  return t;
}

// Parses the keys shared by every obstacle kind and the kind's own; the shape sits at z = 0.
ScenarioObstacle parse_obstacle(const Value& v, std::size_t index, const Doc& doc) {
  Fields f(v, doc);
  if (v.node().IsNull()) v.fail("expected an obstacle (a mapping with kind, position_m, ...)");
  ObstacleKeys k;
  ScenarioObstacle& o = k.o;
  o.source = {v.line(), v.field()};
  require_all(f, obstacle_decl());
  apply_section(f, obstacle_decl(), k, {"kind"});
  const SectionDecl<ObstacleKeys>& kind = obstacle_kind_decl(o.kind);
  o.name = o.kind + "_" + std::to_string(index);
  bool had_z = false;
  const Vec3 pos = xyz_or_xy(f.required("position_m"), 0.0, &had_z);
  o.position = pos.head<2>();
  if (had_z) o.z = pos.z();
  require_all(f, kind);
  const auto sizes = [](const Value& s) {
    const auto sz = s.numbers(3, 3);
    for (double c : sz)
      if (!(c > 0.0)) s.fail("every size must be > 0");
    return Vec3(sz[0], sz[1], sz[2]);
  };
  if (o.kind == "box") k.box.size = sizes(f.required("size_m"));
  if (o.kind == "round_convex")
    if (auto s = f.take("box_size_m")) k.round_convex.box_size = sizes(*s);

  const bool has_vel = f.has("velocity_mps"), has_wp = f.has("waypoints");
  if (has_vel && has_wp) f.fail_at("waypoints", "give either velocity_mps or waypoints, not both");
  if (auto vel = f.take("velocity_mps")) o.velocity = xyz_or_xy(*vel, 0.0);
  if (auto wp = f.take("waypoints")) {
    if (!wp->node().IsSequence() || wp->node().size() == 0)
      wp->fail("expected a list of {t_s, position_m}, found " + node_kind(wp->node()));
    for (std::size_t i = 0; i < wp->node().size(); ++i) {
      const Value e = wp->element(i);
      Fields w(e, doc);
      if (e.node().IsNull()) e.fail("expected {t_s, position_m}");
      require_all(w, waypoint_decl());
      WaypointKeys wk;
      ScenarioObstacle::Point p;
      bool wz = false;
      const Vec3 q = xyz_or_xy(w.required("position_m"), 0.0, &wz);
      apply_section(w, waypoint_decl(), wk);
      p.t_s = wk.t_s;
      p.xy = q.head<2>();
      if (wz) p.z = q.z();
      if (!o.waypoints.empty() && !(p.t_s > o.waypoints.back().t_s)) w.fail_at("t_s", "waypoint times must increase strictly");
      o.waypoints.push_back(p);
    }
  }
  apply_section(f, {&obstacle_decl(), &kind}, k);
  if (f.has("name") && o.name.empty()) f.fail_at("name", "must not be empty");
  if (f.has("disappear_s") && !(o.disappear_s > o.appear_s)) f.fail_at("disappear_s", "must be later than appear_s");

  if (o.kind == "box") {
    k.box.center = Vec3(0, 0, 0.5 * k.box.size.z());
    o.shape = k.box;
  } else if (o.kind == "cylinder") {
    o.shape = k.cylinder;
  } else if (o.kind == "prism") {
    const Prism& p = k.prism;
    if (p.apex_offset < -0.5 * p.base_width || p.apex_offset > 0.5 * p.base_width)
      f.fail_at("apex_offset_m", "must be in [" + Value::fmt(-0.5 * p.base_width) + ", " + Value::fmt(0.5 * p.base_width) +
                                     "] (half the base width either side)");
    o.shape = p;
  } else if (o.kind == "sphere") {
    k.sphere.center = Vec3(0, 0, k.sphere.radius);
    o.shape = k.sphere;
  } else if (o.kind == "slope_step") {
    o.shape = k.slope_step;
  } else if (o.kind == "undulating_ground") {
    o.shape = k.undulating;
  } else if (o.kind == "round_convex") {
    o.shape = k.round_convex;
  } else {
    if (k.gravel.size_max < k.gravel.size_min) f.fail_at("size_max_m", "must be >= size_min_m");
    o.gravel_seed_given = f.has("seed");
    o.shape = k.gravel;
  }
  return o;
}

}  // namespace

Obstacle place_obstacle(const ScenarioObstacle& s, double ground_z, const TerrainSurface* ground, std::uint64_t seed) {
  const double z = s.z.value_or(ground_z);
  const Vec3 at(s.position.x(), s.position.y(), z);
  Obstacle o;
  std::visit(
      [&](const auto& shape) {
        using T = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<T, Box> || std::is_same_v<T, Cylinder> || std::is_same_v<T, Prism> ||
                      std::is_same_v<T, Sphere>) {
          o.parts.push_back(translated(Primitive(shape), at));
        } else if constexpr (std::is_same_v<T, SlopeStep>) {
          SlopeStep c = shape;
          c.position = at;
          o = make_slope_step(c);
        } else if constexpr (std::is_same_v<T, UndulatingGround>) {
          UndulatingGround c = shape;
          c.position = at;
          o = make_undulating_ground(c);
        } else if constexpr (std::is_same_v<T, RoundConvex>) {
          RoundConvex c = shape;
          c.position = at;
          o = make_round_convex(c);
        } else {
          Gravel c = shape;
          c.position = at;
          if (!s.gravel_seed_given) c.seed = seed;
          o = make_gravel(c, ground);
        }
      },
      s.shape);
  o.name = s.name;
  o.anchor = at;
  o.appear = s.appear_s;
  o.disappear = s.disappear_s;
  o.velocity = s.velocity;
  for (const auto& w : s.waypoints) o.waypoints.push_back({w.t_s, Vec3(w.xy.x(), w.xy.y(), w.z.value_or(z))});
  return o;
}

void parse_world(const Value& v, ScenarioSpec& s) {
  const Doc& doc = v.doc();
  Fields w(v, doc);
  if (auto t = w.take("terrain")) s.terrain = parse_terrain(*t, doc);
  if (auto m = w.take("occupancy_map")) {
    ScenarioOccupancyWorld o;
    if (m->node().IsMap()) {
      Fields mf(*m, doc);
      require_all(mf, occupancy_decl());
      apply_section(mf, occupancy_decl(), o);
      if (o.file.empty()) mf.fail_at("file", "empty path");
      o.source = {mf.line_of("file"), mf.path("file")};
    } else {
      o.file = m->string();
      if (o.file.empty()) m->fail("empty path");
      o.source = {m->line(), m->field()};
    }
    o.resolved_file = resolve_path(doc, o.file);
    s.occupancy_map = o;
  }
  if (auto ol = w.take("obstacles")) {
    const std::size_t n = ol->list("obstacles");
    std::set<std::string> names;
    long long gravel_pieces = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Value e = ol->element(i);
      ScenarioObstacle o = parse_obstacle(e, i, doc);
      if (!names.insert(o.name).second) throw Error("duplicate obstacle name '" + o.name + "'", doc.file, e.line(), e.field() + ".name");
      const Gravel* gravel = std::get_if<Gravel>(&o.shape);
      if (gravel) {
        gravel_pieces += gravel->count;
        if (gravel_pieces > kMaxGravelPieces)
          throw Error("the gravel fields so far have " + std::to_string(gravel_pieces) + " pieces; a scenario may have at most " +
                          std::to_string(kMaxGravelPieces),
                      doc.file, e.line(), e.field() + ".count");
      }
      // The library's own checks (composite limits, motions) at this obstacle's line. Gravel is
      // checked with one piece: its pieces are generated by build_world, not here (count may be
      // 100000, and a YAML alias repeats an obstacle for a few bytes).
      try {
        if (gravel) {
          ScenarioObstacle one_piece = o;
          std::get<Gravel>(one_piece.shape).count = 1;
          validate(place_obstacle(one_piece, 0.0, nullptr, s.seed));
        } else {
          validate(place_obstacle(o, 0.0, nullptr, s.seed));
        }
      } catch (const Error& err) {
        rethrow_at(err, doc, e.line(), e.field());
      }
      s.obstacles.push_back(std::move(o));
    }
  }
  NoKeys none;
  apply_section(w, world_decl(), none);
}

std::vector<ScenarioKeySection> world_sections() {
  std::vector<ScenarioKeySection> out = {world_decl().describe(), terrain_decl().describe(), generate_decl().describe(),
                                         flat_decl().describe(),  hills_decl().describe(),   road_decl().describe(),
                                         feature_decl().describe(), occupancy_decl().describe(), obstacle_decl().describe()};
  for (const std::string& kind : obstacle_kinds()) out.push_back(obstacle_kind_decl(kind).describe());
  out.push_back(waypoint_decl().describe());
  return out;
}

}  // namespace starnav::scenario_detail
