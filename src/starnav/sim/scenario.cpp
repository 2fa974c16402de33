#include "starnav/sim/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/io/yaml_document.hpp"
#include "starnav/sim/occupancy_world.hpp"
#include "starnav/sim/terrain_surface.hpp"

namespace starnav {

namespace {

namespace fs = std::filesystem;

int mark_line(const YAML::Node& n) {
  if (!n.IsDefined()) return 0;
  const YAML::Mark m = n.Mark();
  return m.is_null() ? 0 : m.line + 1;
}

std::string node_kind(const YAML::Node& n) {
  if (n.IsNull()) return "nothing";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a mapping";
  return "'" + one_line(n.Scalar(), 60) + "'";
}

bool is_special_float(std::string_view t) {
  std::string lower;
  for (const char c : t) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return lower == ".inf" || lower == "+.inf" || lower == "-.inf" || lower == ".nan" || lower == "inf" ||
         lower == "-inf" || lower == "nan";
}


// The reading context of one document: file name for errors.
struct Doc {
  std::string file;
};

// A YAML value with its dotted field path and line, converted with checks that name both.
class Value {
 public:
  Value(const YAML::Node& node, std::string field, int line, const Doc& doc)
      : node_(node), field_(std::move(field)), line_(line), doc_(&doc) {}

  const YAML::Node& node() const { return node_; }
  const std::string& field() const { return field_; }
  int line() const { return line_; }
  [[noreturn]] void fail(const std::string& message) const { throw Error(message, doc_->file, line_, field_); }

  double number() const {
    if (!node_.IsScalar()) fail("expected a number, found " + node_kind(node_));
    if (is_special_float(node_.Scalar())) fail("must be finite, got " + node_.Scalar());
    const std::optional<double> v = parse_real_text(node_.Scalar());
    if (!v) fail("expected a number, found " + node_kind(node_));
    return *v;
  }
  double positive() const {
    const double v = number();
    if (!(v > 0.0)) fail("must be > 0, got " + node_.Scalar());
    return v;
  }
  double non_negative() const {
    const double v = number();
    if (v < 0.0) fail("must be >= 0, got " + node_.Scalar());
    return v;
  }
  double in_range(double lo, double hi) const {
    const double v = number();
    if (v < lo || v > hi) fail("must be in [" + fmt(lo) + ", " + fmt(hi) + "], got " + node_.Scalar());
    return v;
  }
  long long integer(long long lo, long long hi) const {
    if (!node_.IsScalar()) fail("expected an integer, found " + node_kind(node_));
    // A count (lo >= 0) takes no sign, as on the command line.
    const std::optional<std::int64_t> v = lo >= 0 ? parse_integer_in(node_.Scalar(), 0, std::numeric_limits<std::int64_t>::max())
                                                  : parse_integer_text(node_.Scalar());
    if (!v) fail(lo >= 0 ? "expected a whole number without a sign, found '" + node_.Scalar() + "'" : "expected an integer, found " + node_kind(node_));
    if (*v < lo || *v > hi) fail("must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + node_.Scalar());
    return *v;
  }
  std::uint64_t seed() const {
    if (!node_.IsScalar()) fail("expected a non-negative integer, found " + node_kind(node_));
    const std::optional<std::uint64_t> v = parse_unsigned_text(node_.Scalar());
    if (!v) fail("expected a non-negative integer, found " + node_kind(node_));
    return *v;
  }
  bool boolean() const {
    bool b = false;
    if (!node_.IsScalar() || !YAML::convert<bool>::decode(node_, b)) fail("expected true or false, found " + node_kind(node_));
    return b;
  }
  std::string string() const {
    if (!node_.IsScalar()) fail("expected text, found " + node_kind(node_));
    return node_.Scalar();
  }
  // A list of numbers with `lo`..`hi` entries.
  std::vector<double> numbers(std::size_t lo, std::size_t hi) const {
    const std::string want = lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi);
    if (!node_.IsSequence()) fail("expected a list of " + want + " numbers, found " + node_kind(node_));
    if (node_.size() < lo || node_.size() > hi)
      fail("expected a list of " + want + " numbers, found " + std::to_string(node_.size()));
    std::vector<double> out;
    for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(element(i).number());
    return out;
  }
  Value element(std::size_t i) const {
    const YAML::Node e = node_[i];
    const int l = mark_line(e);
    return Value(e, field_ + "[" + std::to_string(i) + "]", l > 0 ? l : line_, *doc_);
  }
  static std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }

 private:
  YAML::Node node_;
  std::string field_;
  int line_;
  const Doc* doc_;
};

// A YAML mapping read key by key: every key must be taken, or finish() names the first unknown.
class Fields {
 public:
  Fields(const Value& v, const Doc& doc);

  bool has(const char* key) const { return find(key) != nullptr; }
  // The value of `key` (marked as read), or nothing.
  std::optional<Value> take(const char* key) {
    const Entry* e = find(key);
    if (!e) return std::nullopt;
    used_.insert(key);
    return Value(e->value, path(key), e->line, *doc_);
  }
  Value required(const char* key) {
    auto v = take(key);
    if (!v) throw Error("required key is missing", doc_->file, line_, path(key));
    return *v;
  }
  double number(const char* key, double def) {
    auto v = take(key);
    return v ? v->number() : def;
  }
  double positive(const char* key, double def) {
    auto v = take(key);
    return v ? v->positive() : def;
  }
  double non_negative(const char* key, double def) {
    auto v = take(key);
    return v ? v->non_negative() : def;
  }
  double angle_deg(const char* key, double def_rad) {
    auto v = take(key);
    return v ? deg_to_rad(v->number()) : def_rad;
  }
  std::string path(const char* key) const { return field_.empty() ? std::string(key) : field_ + "." + key; }
  bool taken(const std::string& key) const { return used_.count(key) > 0; }
  // Every key, in document order.
  std::vector<std::string> keys() const {
    std::vector<std::string> k;
    for (const Entry& e : entries_) k.push_back(e.key);
    return k;
  }
  int line() const { return line_; }
  int line_of(const std::string& key) const {
    for (const Entry& e : entries_)
      if (e.key == key) return e.line;
    return line_;
  }
  const std::string& field() const { return field_; }
  [[noreturn]] void fail(const std::string& message) const { throw Error(message, doc_->file, line_, field_); }

  // Unknown keys are errors (the first one in the document).
  void finish(const char* known_hint = nullptr) const {
    for (const Entry& e : entries_)
      if (!used_.count(e.key)) {
        std::string msg = "unknown key";
        if (known_hint) msg += " (expected one of: " + std::string(known_hint) + ")";
        throw Error(msg, doc_->file, e.line, path(e.key.c_str()));
      }
  }

 private:
  struct Entry {
    std::string key;
    YAML::Node value;
    int line = 0;
  };
  const Entry* find(const char* key) const {
    for (const Entry& e : entries_)
      if (e.key == key) return &e;
    return nullptr;
  }

  std::string field_;
  int line_;
  const Doc* doc_;
  std::vector<Entry> entries_;
  std::set<std::string> used_;
};

Fields::Fields(const Value& v, const Doc& doc) : field_(v.field()), line_(v.line()), doc_(&doc) {
  const YAML::Node& n = v.node();
  if (n.IsNull()) return;  // `imu:` with nothing after it: all defaults
  if (!n.IsMap()) v.fail("expected a mapping (key: value lines), found " + node_kind(n));
  for (auto it = n.begin(); it != n.end(); ++it) {
    const int l = mark_line(it->first);
    if (!it->first.IsScalar()) throw Error("keys must be plain names", doc.file, l, v.field());
    const std::string key = it->first.Scalar();
    for (const Entry& e : entries_)
      if (e.key == key) throw Error("duplicate key", doc.file, l, path(key.c_str()));
    // A key without a mark was set on the command line (--set): it has no line.
    entries_.push_back({key, it->second, it->first.Mark().is_null() ? 0 : l});
  }
}

Fields fields_of(const Value& v, const Doc& doc) { return Fields(v, doc); }

// Re-raises a library validation error (whose field is the library's name) at a YAML location.
[[noreturn]] void rethrow_at(const Error& e, const Doc& doc, int line, const std::string& field_prefix) {
  std::string field = field_prefix;
  if (!e.field().empty()) field += (field.empty() ? "" : ".") + e.field();
  throw Error(e.message(), doc.file, line, field);
}

Vec3 xyz_or_xy(const Value& v, double z_default, bool* had_z = nullptr) {
  const std::vector<double> p = v.numbers(2, 3);
  if (had_z) *had_z = p.size() == 3;
  return {p[0], p[1], p.size() == 3 ? p[2] : z_default};
}

// ---- world -------------------------------------------------------------------------------------

TerrainFeature parse_feature(const Value& v, const Doc& doc) {
  Fields f = fields_of(v, doc);
  TerrainFeature t;
  const std::string kind = f.required("kind").string();
  if (kind == "pit") t.kind = TerrainFeature::Kind::Pit;
  else if (kind == "mound") t.kind = TerrainFeature::Kind::Mound;
  else throw Error("unknown feature kind '" + kind + "' (pit, mound)", doc.file, f.line_of("kind"), f.path("kind"));
  const std::vector<double> c = f.required("centre_m").numbers(2, 2);
  t.centre = Vec2(c[0], c[1]);
  t.radius_m = f.required("radius_m").positive();
  t.depth_m = f.required("depth_m").positive();
  f.finish("kind, centre_m, radius_m, depth_m");
  return t;
}

void parse_generate(Fields& g, ScenarioTerrain& t, const Doc& doc) {
  const Value kind_v = g.required("kind");
  const std::string kind = kind_v.string();
  if (kind == "flat") t.kind = ScenarioTerrain::Kind::Flat;
  else if (kind == "hills") t.kind = ScenarioTerrain::Kind::Hills;
  else if (kind == "road") t.kind = ScenarioTerrain::Kind::Road;
  else kind_v.fail("unknown terrain kind '" + kind + "' (flat, hills, road)");

  const std::vector<double> size = g.required("size_m").numbers(2, 2);
  if (!(size[0] > 0.0) || !(size[1] > 0.0)) throw Error("width and height must be > 0", doc.file, g.line_of("size_m"), g.path("size_m"));
  const double res = g.positive("resolution_m", 0.05);
  Pose2 origin;
  if (auto o = g.take("origin_m")) {
    const std::vector<double> p = o->numbers(2, 2);
    origin = Pose2(p[0], p[1], 0.0);
  }
  origin.yaw = g.angle_deg("origin_yaw_deg", 0.0);
  std::uint64_t seed = 0;
  if (auto s = g.take("seed")) {
    seed = s->seed();
    t.seed_given = true;
  }
  try {
    const GridGeometry geometry = terrain_geometry(size[0], size[1], res, origin);
    // The simulator keeps several layers per cell (heights, surface, height pyramid): a small
    // file must not be able to ask for tens of gigabytes.
    if (geometry.cell_count() > kMaxTerrainCells)
      throw Error("the terrain would have " + std::to_string(geometry.cell_count()) + " cells; the simulator takes at most " +
                      std::to_string(kMaxTerrainCells) + " (a coarser resolution_m or a smaller size_m)",
                  {}, 0, "size_m");
  } catch (const Error& e) {
    const std::string key = e.field() == "resolution" ? "resolution_m" : "size_m";
    throw Error(e.message(), doc.file, g.line_of(key), g.path(key.c_str()));
  }
  if (auto fl = g.take("features")) {
    if (!fl->node().IsSequence()) fl->fail("expected a list of features, found " + node_kind(fl->node()));
    for (std::size_t i = 0; i < fl->node().size(); ++i) t.features.push_back(parse_feature(fl->element(i), doc));
  }

  HillsOptions& h = t.hills;
  h.width_m = size[0];
  h.height_m = size[1];
  h.resolution = res;
  h.origin = origin;
  h.seed = seed;
  RoadOptions& r = t.road;
  r.width_m = size[0];
  r.height_m = size[1];
  r.resolution = res;
  r.origin = origin;
  r.seed = seed;

  if (t.kind == ScenarioTerrain::Kind::Flat) {
    t.flat_z_m = g.number("z_m", 0.0);
    g.finish("kind, size_m, resolution_m, origin_m, origin_yaw_deg, seed, features, z_m");
  } else if (t.kind == ScenarioTerrain::Kind::Hills) {
    h.amplitude = g.non_negative("amplitude", h.amplitude);
    h.hills_per_100m2 = g.non_negative("hills_per_100m2", h.hills_per_100m2);
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
    h.roughness_m = g.non_negative("roughness_m", h.roughness_m);
    h.roughness_correlation_m = g.positive("roughness_correlation_m", h.roughness_correlation_m);
    g.finish("kind, size_m, resolution_m, origin_m, origin_yaw_deg, seed, features, amplitude, hills_per_100m2, "
             "hill_height_m, hill_sigma_m, roughness_m, roughness_correlation_m");
    try {
      h.validate();
    } catch (const Error& e) {
      rethrow_at(e, doc, g.line(), g.field());
    }
  } else {
    if (auto v = g.take("class")) {
      const std::string c = v->string();
      if (c.size() != 1) v->fail("unknown road class '" + c + "' (A..H)");
      try {
        road_class_gd_n0(c[0], "class");
      } catch (const Error& e) {
        v->fail(e.message());
      }
      r.road_class = static_cast<char>(std::toupper(static_cast<unsigned char>(c[0])));
    }
    r.gd_n0 = g.non_negative("gd_n0_m3", r.gd_n0);
    if (auto v = g.take("method")) {
      try {
        r.method = parse_road_method(v->string(), v->field());
      } catch (const Error& e) {
        v->fail(e.message());
      }
    }
    r.n0 = g.positive("n0_per_m", r.n0);
    if (auto v = g.take("band_per_m")) {
      const auto b = v->numbers(2, 2);
      if (!(b[0] > 0.0) || !(b[1] > b[0])) v->fail("need 0 < n1 < n2");
      r.n1 = b[0];
      r.n2 = b[1];
    }
    r.waviness = g.positive("waviness", r.waviness);
    if (auto v = g.take("intervals")) r.intervals = static_cast<int>(v->integer(1, kMaxRoadIntervals));
    // Each method's own knob is refused with the other method rather than silently ignored.
    if (auto v = g.take("directions")) {
      if (r.method != RoadMethod::Directional) v->fail("only for method directional (the paper method has no directions)");
      r.directions = static_cast<int>(v->integer(1, kMaxRoadDirections));
    }
    if (auto v = g.take("blur_sigma_cells")) {
      if (r.method != RoadMethod::Paper) v->fail("only for method paper (the directional method does not blur)");
      r.blur_sigma_cells = v->positive();
    }
    g.finish("kind, size_m, resolution_m, origin_m, origin_yaw_deg, seed, features, class, gd_n0_m3, method, "
             "n0_per_m, band_per_m, waviness, intervals, directions, blur_sigma_cells");
    try {
      r.validate();
    } catch (const Error& e) {
      rethrow_at(e, doc, g.line(), g.field());
    }
  }
}

ScenarioTerrain parse_terrain(const Value& v, const Doc& doc, const fs::path& base_dir) {
  Fields f = fields_of(v, doc);
  ScenarioTerrain t;
  t.source = {v.line(), v.field()};
  const bool has_file = f.has("file"), has_gen = f.has("generate");
  if (has_file == has_gen) f.fail("give exactly one of 'file' or 'generate'");
  if (has_file) {
    const Value file = f.required("file");
    t.kind = ScenarioTerrain::Kind::File;
    t.file = file.string();
    if (t.file.empty()) file.fail("empty path");
    const fs::path p(t.file);
    t.resolved_file = p.is_absolute() ? p.string() : (base_dir / p).lexically_normal().string();
    t.source = {file.line(), file.field()};
    if (auto fl = f.take("features")) {
      if (!fl->node().IsSequence()) fl->fail("expected a list of features, found " + node_kind(fl->node()));
      for (std::size_t i = 0; i < fl->node().size(); ++i) t.features.push_back(parse_feature(fl->element(i), doc));
    }
  } else {
    Value gv = f.required("generate");
    Fields g = fields_of(gv, doc);
    if (gv.node().IsNull()) gv.fail("expected a mapping with at least 'kind' and 'size_m'");
    parse_generate(g, t, doc);
    t.source = {gv.line(), gv.field()};
    // A generated terrain takes its features inside 'generate:'; say so rather than list 'features' as allowed.
    if (auto fl = f.take("features")) fl->fail("with 'generate', put 'features' inside 'generate:'");
  }
  f.finish(has_file ? "file, features" : "generate");
  return t;
}

// Parses the keys shared by every obstacle kind and the kind's own; the shape sits at z = 0.
ScenarioObstacle parse_obstacle(const Value& v, std::size_t index, const Doc& doc) {
  Fields f = fields_of(v, doc);
  if (v.node().IsNull()) v.fail("expected an obstacle (a mapping with kind, position_m, ...)");
  ScenarioObstacle o;
  o.source = {v.line(), v.field()};
  const Value kind_v = f.required("kind");
  o.kind = kind_v.string();
  o.name = o.kind + "_" + std::to_string(index);
  if (auto n = f.take("name")) {
    o.name = n->string();
    if (o.name.empty()) n->fail("must not be empty");
  }
  bool had_z = false;
  const Vec3 pos = xyz_or_xy(f.required("position_m"), 0.0, &had_z);
  o.position = pos.head<2>();
  if (had_z) o.z = pos.z();

  const char* common = "name, kind, position_m, appear_s, disappear_s, velocity_mps, waypoints";
  std::string hint;
  const auto req_pos = [&](const char* key) { return f.required(key).positive(); };
  if (o.kind == "box") {
    Box b;
    const Value s = f.required("size_m");
    const auto sz = s.numbers(3, 3);
    for (double c : sz)
      if (!(c > 0.0)) s.fail("every size must be > 0");
    b.size = Vec3(sz[0], sz[1], sz[2]);
    b.yaw = f.angle_deg("yaw_deg", 0.0);
    b.roll = f.angle_deg("roll_deg", 0.0);
    b.pitch = f.angle_deg("pitch_deg", 0.0);
    b.center = Vec3(0, 0, 0.5 * b.size.z());
    o.shape = b;
    hint = ", size_m, yaw_deg, roll_deg, pitch_deg";
  } else if (o.kind == "cylinder") {
    Cylinder c;
    c.radius = req_pos("radius_m");
    c.height = req_pos("height_m");
    o.shape = c;
    hint = ", radius_m, height_m";
  } else if (o.kind == "prism") {
    Prism p;
    p.yaw = f.angle_deg("yaw_deg", 0.0);
    p.base_width = req_pos("base_width_m");
    p.height = req_pos("height_m");
    p.length = req_pos("length_m");
    if (auto a = f.take("apex_offset_m")) {
      p.apex_offset = a->in_range(-0.5 * p.base_width, 0.5 * p.base_width);
    }
    o.shape = p;
    hint = ", yaw_deg, base_width_m, height_m, length_m, apex_offset_m";
  } else if (o.kind == "sphere") {
    Sphere s;
    s.radius = req_pos("radius_m");
    s.center = Vec3(0, 0, s.radius);
    o.shape = s;
    hint = ", radius_m";
  } else if (o.kind == "slope_step") {
    SlopeStep s;
    s.yaw = f.angle_deg("yaw_deg", 0.0);
    s.width = f.positive("width_m", s.width);
    s.ramp_length = f.positive("ramp_length_m", s.ramp_length);
    s.ramp_height = f.positive("ramp_height_m", s.ramp_height);
    s.platform_length = f.positive("platform_length_m", s.platform_length);
    s.step_height = f.positive("step_height_m", s.step_height);
    s.step_length = f.positive("step_length_m", s.step_length);
    s.depth = f.non_negative("depth_m", s.depth);
    o.shape = s;
    hint = ", yaw_deg, width_m, ramp_length_m, ramp_height_m, platform_length_m, step_height_m, step_length_m, depth_m";
  } else if (o.kind == "undulating_ground") {
    UndulatingGround u;
    u.yaw = f.angle_deg("yaw_deg", 0.0);
    if (auto c = f.take("count")) u.count = static_cast<int>(c->integer(1, 1000));
    u.base_width = f.positive("base_width_m", u.base_width);
    u.height = f.positive("height_m", u.height);
    u.width = f.positive("width_m", u.width);
    o.shape = u;
    hint = ", yaw_deg, count, base_width_m, height_m, width_m";
  } else if (o.kind == "round_convex") {
    RoundConvex r;
    r.yaw = f.angle_deg("yaw_deg", 0.0);
    if (auto s = f.take("box_size_m")) {
      const auto sz = s->numbers(3, 3);
      for (double c : sz)
        if (!(c > 0.0)) s->fail("every size must be > 0");
      r.box_size = Vec3(sz[0], sz[1], sz[2]);
    }
    r.radius = f.positive("radius_m", r.radius);
    r.cylinder_height = f.positive("cylinder_height_m", r.cylinder_height);
    r.depth = f.non_negative("depth_m", r.depth);
    o.shape = r;
    hint = ", yaw_deg, box_size_m, radius_m, cylinder_height_m, depth_m";
  } else if (o.kind == "gravel") {
    Gravel g;
    g.yaw = f.angle_deg("yaw_deg", 0.0);
    g.length = f.positive("length_m", g.length);
    g.width = f.positive("width_m", g.width);
    if (auto c = f.take("count")) g.count = static_cast<int>(c->integer(1, 100000));
    g.size_min = f.positive("size_min_m", g.size_min);
    g.size_max = f.positive("size_max_m", g.size_max);
    if (g.size_max < g.size_min)
      throw Error("must be >= size_min_m", doc.file, f.line_of("size_max_m"), f.path("size_max_m"));
    if (auto s = f.take("sphere_fraction")) g.sphere_fraction = s->in_range(0.0, 1.0);
    if (auto s = f.take("embed")) {
      g.embed = s->number();
      if (!(g.embed >= 0.0 && g.embed < 1.0)) s->fail("must be in [0, 1), got " + s->node().Scalar());
    }
    if (auto s = f.take("seed")) {
      g.seed = s->seed();
      o.gravel_seed_given = true;
    }
    if (auto s = f.take("follow_terrain")) g.follow_terrain = s->boolean();
    o.shape = g;
    hint = ", yaw_deg, length_m, width_m, count, size_min_m, size_max_m, sphere_fraction, embed, seed, follow_terrain";
  } else {
    kind_v.fail("unknown obstacle kind '" + o.kind +
                "' (box, cylinder, prism, sphere, slope_step, undulating_ground, round_convex, gravel)");
  }

  o.appear_s = f.number("appear_s", 0.0);
  if (auto d = f.take("disappear_s")) {
    o.disappear_s = d->number();
    if (!(o.disappear_s > o.appear_s)) d->fail("must be later than appear_s");
  }
  const bool has_vel = f.has("velocity_mps"), has_wp = f.has("waypoints");
  if (has_vel && has_wp)
    throw Error("give either velocity_mps or waypoints, not both", doc.file, f.line_of("waypoints"), f.path("waypoints"));
  if (auto vel = f.take("velocity_mps")) o.velocity = xyz_or_xy(*vel, 0.0);
  if (auto wp = f.take("waypoints")) {
    if (!wp->node().IsSequence() || wp->node().size() == 0)
      wp->fail("expected a list of {t_s, position_m}, found " + node_kind(wp->node()));
    for (std::size_t i = 0; i < wp->node().size(); ++i) {
      const Value e = wp->element(i);
      Fields w = fields_of(e, doc);
      if (e.node().IsNull()) e.fail("expected {t_s, position_m}");
      ScenarioObstacle::Point p;
      p.t_s = w.required("t_s").number();
      bool wz = false;
      const Vec3 q = xyz_or_xy(w.required("position_m"), 0.0, &wz);
      p.xy = q.head<2>();
      if (wz) p.z = q.z();
      w.finish("t_s, position_m");
      if (!o.waypoints.empty() && !(p.t_s > o.waypoints.back().t_s))
        throw Error("waypoint times must increase strictly", doc.file, w.line_of("t_s"), w.path("t_s"));
      o.waypoints.push_back(p);
    }
  }
  f.finish((std::string(common) + hint).c_str());
  return o;
}

// The obstacle posed at ground height `ground_z` (used when no z is given).
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

// ---- robot, sensors ----------------------------------------------------------------------------

// A library validation error of the robot or vehicle at the line of the YAML key it names.
[[noreturn]] void rethrow_vehicle_error(const Error& e, const Doc& doc, const Fields* robot, const Fields* vehicle,
                                        int fallback_line) {
  std::string key = e.field();
  const Fields* section = nullptr;
  for (const auto& [prefix, f] : {std::pair<std::string, const Fields*>{"robot.", robot}, {"vehicle.", vehicle}})
    if (key.rfind(prefix, 0) == 0) {
      key = key.substr(prefix.size());
      section = f;
    }
  // The library names angles in radians; the scenario writes degrees.
  const auto to_deg = [](std::string k) {
    for (const auto& [rad, deg] : {std::pair<std::string, std::string>{"_radps", "_degps"}, {"_rad", "_deg"}})
      if (k.size() > rad.size() && k.compare(k.size() - rad.size(), rad.size(), rad) == 0)
        return k.substr(0, k.size() - rad.size()) + deg;
    return k;
  };
  if (section) {
    const std::string deg = to_deg(key);
    const std::string yaml_key = section->line_of(deg) != section->line() ? deg : key;
    throw Error(e.message(), doc.file, section->line_of(yaml_key),
                section->field().empty() ? yaml_key : section->field() + "." + yaml_key);
  }
  throw Error(e.message(), doc.file, fallback_line, e.field());
}

Pose3 parse_mount(const Value& v, const Doc& doc, double default_z) {
  Fields f = fields_of(v, doc);
  const Vec3 p(f.number("x_m", 0.0), f.number("y_m", 0.0), f.number("z_m", default_z));
  const double roll = f.angle_deg("roll_deg", 0.0), pitch = f.angle_deg("pitch_deg", 0.0), yaw = f.angle_deg("yaw_deg", 0.0);
  f.finish("x_m, y_m, z_m, roll_deg, pitch_deg, yaw_deg");
  return Pose3::from_rpy(p, roll, pitch, yaw);
}

ScenarioLidar parse_lidar(const Value& v, const Doc& doc, const RobotConfig& robot) {
  Fields f = fields_of(v, doc);
  ScenarioLidar l;
  l.source = {v.line(), v.field()};
  double res_deg = 0.2;
  if (auto r = f.take("horizontal_resolution_deg")) {
    res_deg = r->positive();
    // A 3D preset gets scan angle / resolution beams per line: at most what `beams` allows (and a
    // finer resolution would overflow the beam count).
    if (360.0 / res_deg > 1000000.0) r->fail("must be at least 0.00036 (360 deg / 1000000 beams, the most beams allows)");
    l.horizontal_resolution_deg = res_deg;
  }
  if (auto p = f.take("preset")) {
    l.preset = p->string();
    try {
      l.config = lidar_preset(l.preset, deg_to_rad(res_deg));
    } catch (const Error& e) {
      p->fail(e.message());
    }
  } else if (l.horizontal_resolution_deg > 0.0) {
    throw Error("only with a 3D preset", doc.file, f.line_of("horizontal_resolution_deg"), f.path("horizontal_resolution_deg"));
  }
  LidarConfig& c = l.config;
  if (auto b = f.take("beams")) c.beams = static_cast<int>(b->integer(1, 1000000));
  if (auto a = f.take("scan_angle_deg")) {
    const double deg = a->number();
    if (!(deg > 0.0 && deg <= 360.0)) a->fail("must be in (0, 360]");
    c.scan_angle = deg_to_rad(deg);
  }
  if (auto e = f.take("elevations_deg")) {
    if (!e->node().IsSequence() || e->node().size() == 0) e->fail("expected a list of elevations (top first), found " + node_kind(e->node()));
    c.elevations.clear();
    for (std::size_t i = 0; i < e->node().size(); ++i) {
      const double deg = e->element(i).in_range(-90.0, 90.0);
      c.elevations.push_back(deg_to_rad(deg));
    }
  }
  c.range_min = f.non_negative("range_min_m", c.range_min);
  if (auto r = f.take("range_max_m")) {
    c.range_max = r->positive();
    if (!(c.range_max > c.range_min)) r->fail("must be > range_min_m");
  } else if (!(c.range_max > c.range_min)) {
    throw Error("must be below range_max_m", doc.file, f.line_of("range_min_m"), f.path("range_min_m"));
  }
  c.rate_hz = f.positive("rate_hz", c.rate_hz);
  // Default mount: centred, 0.1 m above the top of the body.
  const double top = robot.ground_clearance_m + robot.body_height_m;
  c.mount = Pose3::from_rpy(Vec3(0, 0, top + 0.1), 0, 0, 0);
  if (auto m = f.take("mount")) c.mount = parse_mount(*m, doc, top + 0.1);
  c.noise_sigma = f.non_negative("noise_sigma_m", 0.0);
  if (auto d = f.take("dropout")) c.dropout = d->in_range(0.0, 1.0);
  bool self_filter = true;
  if (auto s = f.take("self_filter")) self_filter = s->boolean();
  const double margin = f.non_negative("self_filter_margin_m", 0.05);
  if (self_filter) {
    const Vec3 lo(-0.5 * robot.body_length_m, -0.5 * robot.body_width_m, robot.ground_clearance_m);
    const Vec3 hi(0.5 * robot.body_length_m, 0.5 * robot.body_width_m, top);
    c.self_filter = SelfFilterBox::around_body(lo, hi, c.mount, margin);
  }
  f.finish("preset, horizontal_resolution_deg, beams, scan_angle_deg, elevations_deg, range_min_m, range_max_m, "
           "rate_hz, mount, noise_sigma_m, dropout, self_filter, self_filter_margin_m");
  try {
    c.validate();
  } catch (const Error& e) {
    rethrow_at(e, doc, v.line(), v.field());
  }
  return l;
}

// ---- the document ------------------------------------------------------------------------------

ParamSetting setting_of(const Value& e, const std::string& key, const Doc& doc) {
  return {key, e.node().Scalar(), doc.file, e.line(), e.line() > 0 ? e.field() : e.field() + " (--set)"};
}

// A sequence of lower_snake_case names (component names), perhaps empty.
bool is_name_list(const YAML::Node& node) {
  for (const YAML::Node& item : node) {
    if (!item.IsScalar()) return false;
    const std::string& name = item.Scalar();
    if (name.empty() || !(name[0] >= 'a' && name[0] <= 'z')) return false;
    for (const char ch : name)
      if (!((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_')) return false;
  }
  return true;
}

// A sequence whose items are scalars or such sequences, at most `depth` levels deep (no
// parameter nests deeper than polygons' three).
bool is_value_list(const YAML::Node& node, int depth = 4) {
  if (depth == 0) return false;
  for (const YAML::Node& item : node)
    if (!item.IsScalar() && !(item.IsSequence() && is_value_list(item, depth - 1))) return false;
  return true;
}

// `node` (scalars and sequences) as one line of flow text: [[0, 0], [1, 0]].
std::string flow_text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  std::string s = "[";
  for (std::size_t i = 0; i < node.size(); ++i) s.append(i ? ", " : "").append(flow_text(node[i]));
  s += ']';
  return s;
}

// Every value of `f` not taken yet, as a setting with its dotted key (relative to `prefix`) and
// line, sections recursively; the navigation stack checks them against its components' declared
// parameters.
void collect_settings(Fields& f, const Doc& doc, const std::string& prefix, std::vector<ParamSetting>& out) {
  for (const std::string& k : f.keys()) {
    if (f.taken(k)) continue;
    const Value e = *f.take(k.c_str());
    const std::string key = prefix.empty() ? k : prefix + "." + k;
    if (e.node().IsMap()) {
      Fields section = fields_of(e, doc);
      collect_settings(section, doc, key, out);
    } else if (e.node().IsScalar()) {
      out.push_back(setting_of(e, key, doc));
    } else if (e.node().IsSequence() && is_name_list(e.node())) {
      // A list of names (navigation.recoveries: [rotate, back_up]) as one setting "rotate, back_up".
      ParamSetting s = setting_of(e, key, doc);
      s.value.clear();
      for (std::size_t i = 0; i < e.node().size(); ++i) s.value += (i ? ", " : "") + e.node()[i].Scalar();
      out.push_back(std::move(s));
    } else if (e.node().IsSequence() && is_value_list(e.node())) {
      // Nested lists of values (polygons: [[[0, 0], [1, 0], [1, 1]]]) in flow form; the
      // parameter's own parser reads the shape.
      ParamSetting s = setting_of(e, key, doc);
      s.value = flow_text(e.node());
      out.push_back(std::move(s));
    } else {
      e.fail("expected a value, a section of values or a list (of names or of lists of numbers), found " + node_kind(e.node()));
    }
  }
}

ScenarioGoal parse_goal(const Value& g, const Doc& doc) {
  ScenarioGoal goal;
  goal.source = {g.line(), g.field()};
  Fields gf = fields_of(g, doc);
  goal.position = Vec2(gf.required("x_m").number(), gf.required("y_m").number());
  if (auto y = gf.take("yaw_deg")) goal.yaw_rad = deg_to_rad(y->number());
  gf.finish("x_m, y_m, yaw_deg");
  return goal;
}

ScenarioNavigation parse_navigation(const Value& v, const Doc& doc) {
  ScenarioNavigation n;
  n.source = {v.line(), v.field()};
  Fields f = fields_of(v, doc);
  auto one = f.take("goal");
  auto many = f.take("goals");
  if (one && many) many->fail("give either goal or goals, not both");
  if (one) {
    n.goals.push_back(parse_goal(*one, doc));
  } else if (many) {
    if (!many->node().IsSequence() || many->node().size() < 1 || many->node().size() > 1000)
      many->fail("expected a list of 1 to 1,000 goals {x_m, y_m, yaw_deg}, found " + node_kind(many->node()));
    for (std::size_t i = 0; i < many->node().size(); ++i) n.goals.push_back(parse_goal(many->element(i), doc));
  } else {
    f.required("goal");  // the error names the missing field
  }
  n.goal = n.goals.front().position;
  n.goal_source = n.goals.front().source;
  if (auto l = f.take("laps")) n.laps = static_cast<int>(l->integer(1, 1000));
  if (auto m = f.take("manual")) {
    if (!m->node().IsSequence()) m->fail("expected a list of manual commands {t_s, duration_s, vx_mps, vy_mps, wz_degps}");
    for (std::size_t i = 0; i < m->node().size(); ++i) {
      const Value e = m->element(i);
      Fields mf = fields_of(e, doc);
      ScenarioManualCommand c;
      c.source = {e.line(), e.field()};
      c.t_s = mf.required("t_s").non_negative();
      c.duration_s = mf.required("duration_s").positive();
      c.twist.vx = mf.number("vx_mps", 0.0);
      c.twist.vy = mf.number("vy_mps", 0.0);
      c.twist.wz = deg_to_rad(mf.number("wz_degps", 0.0));
      mf.finish("t_s, duration_s, vx_mps, vy_mps, wz_degps");
      if (std::abs(c.twist.vx) > 10.0 || std::abs(c.twist.vy) > 10.0 || std::abs(c.twist.wz) > 20.0)
        e.fail("a manual command beyond 10 m/s or 1,146 deg/s");
      if (c.t_s > 1e6 || c.duration_s > 1e6) e.fail("t_s and duration_s must be at most 1e6 s");
      if (!n.manual.empty() && c.t_s < n.manual.back().t_s + n.manual.back().duration_s)
        e.fail("manual commands must be in time order and must not overlap");
      n.manual.push_back(c);
    }
  }
  collect_settings(f, doc, "", n.settings);  // everything else: the navigation's and its components' parameters
  return n;
}

ScenarioSettings parse_settings_section(const Value& v, const Doc& doc) {
  ScenarioSettings out;
  out.source = {v.line(), v.field()};
  if (!v.node().IsMap()) v.fail("expected a section (key: value lines), found " + node_kind(v.node()));
  Fields f = fields_of(v, doc);
  collect_settings(f, doc, "", out.settings);
  return out;
}

ScenarioSpec parse_document(const YAML::Node& root, const std::string& file) {
  Doc doc{file};
  ScenarioSpec s;
  s.file = file;
  if (!root.IsDefined() || root.IsNull()) throw Error("empty scenario (expected a mapping with world, robot, ...)", file, 1);
  const Value rv(root, "", mark_line(root) > 0 ? mark_line(root) : 1, doc);
  if (!root.IsMap()) rv.fail("a scenario is a mapping (key: value lines), found " + node_kind(root));
  Fields top = fields_of(rv, doc);
  const fs::path base_dir = fs::path(file).parent_path();

  if (auto v = top.take("name")) s.name = v->string();
  if (s.name.empty()) s.name = fs::path(file).stem().string();
  if (auto v = top.take("description")) s.description = v->string();

  // sim first: the script's length may set the duration.
  std::optional<double> duration;
  if (auto v = top.take("sim")) {
    Fields f = fields_of(*v, doc);
    if (auto d = f.take("dt_s")) {
      s.dt_s = d->positive();
      if (s.dt_s > 1.0) d->fail("must be at most 1 s");
    }
    if (auto d = f.take("duration_s")) duration = d->positive();
    if (auto d = f.take("seed")) s.seed = d->seed();
    f.finish("dt_s, duration_s, seed");
  }

  {
    Fields w = fields_of(top.required("world"), doc);
    if (auto t = w.take("terrain")) s.terrain = parse_terrain(*t, doc, base_dir);
    if (auto m = w.take("occupancy_map")) {
      ScenarioOccupancyWorld o;
      std::optional<Value> file;
      if (m->node().IsMap()) {
        Fields mf = fields_of(*m, doc);
        file = mf.required("file");
        if (auto h = mf.take("wall_height_m")) o.wall_height_m = h->in_range(0.01, 100.0);
        mf.finish("file, wall_height_m");
      } else {
        file = *m;
      }
      o.file = file->string();
      if (o.file.empty()) file->fail("empty path");
      const fs::path p(o.file);
      o.resolved_file = p.is_absolute() ? p.string() : (base_dir / p).lexically_normal().string();
      o.source = {file->line(), file->field()};
      s.occupancy_map = o;
    }
    if (auto ol = w.take("obstacles")) {
      if (!ol->node().IsSequence()) ol->fail("expected a list of obstacles, found " + node_kind(ol->node()));
      std::set<std::string> names;
      long long gravel_pieces = 0;
      for (std::size_t i = 0; i < ol->node().size(); ++i) {
        const Value e = ol->element(i);
        ScenarioObstacle o = parse_obstacle(e, i, doc);
        if (!names.insert(o.name).second) throw Error("duplicate obstacle name '" + o.name + "'", file, e.line(), e.field() + ".name");
        const Gravel* gravel = std::get_if<Gravel>(&o.shape);
        if (gravel) {
          gravel_pieces += gravel->count;
          if (gravel_pieces > kMaxGravelPieces)
            throw Error("the gravel fields so far have " + std::to_string(gravel_pieces) + " pieces; a scenario may have at most " +
                            std::to_string(kMaxGravelPieces),
                        file, e.line(), e.field() + ".count");
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
    w.finish("terrain, occupancy_map, obstacles");
  }

  std::optional<Fields> robot_fields, vehicle_fields;
  RobotConfig& rc = s.vehicle.robot;
  if (auto v = top.take("robot")) {
    s.robot_source = {v->line(), v->field()};
    robot_fields.emplace(fields_of(*v, doc));
    Fields& f = *robot_fields;
    if (auto d = f.take("drive")) {
      try {
        rc.drive = parse_drive_kind(d->string(), d->field());
      } catch (const Error& e) {
        d->fail(e.message());
      }
    }
    rc.half_track_m = f.positive("half_track_m", rc.half_track_m);
    rc.half_wheelbase_m = f.positive("half_wheelbase_m", rc.half_wheelbase_m);
    rc.wheel_radius_m = f.positive("wheel_radius_m", rc.wheel_radius_m);
    if (auto a = f.take("roller_angle_deg")) {
      const double deg = a->number();
      if (!(deg > 0.0 && deg < 90.0)) a->fail("must be in (0, 90)");
      rc.roller_angle_rad = deg_to_rad(deg);
    }
    rc.body_length_m = f.positive("body_length_m", rc.body_length_m);
    rc.body_width_m = f.positive("body_width_m", rc.body_width_m);
    rc.body_height_m = f.positive("body_height_m", rc.body_height_m);
    rc.ground_clearance_m = f.non_negative("ground_clearance_m", rc.ground_clearance_m);
    rc.max_wheel_speed_radps = f.positive("max_wheel_speed_radps", rc.max_wheel_speed_radps);
    rc.max_wheel_accel_radps2 = f.positive("max_wheel_accel_radps2", rc.max_wheel_accel_radps2);
    rc.actuator_lag_s = f.non_negative("actuator_lag_s", rc.actuator_lag_s);
    if (auto a = f.take("max_steer_deg")) {
      const double deg = a->number();
      if (!(deg > 0.0 && deg < 90.0)) a->fail("must be in (0, 90)");
      rc.max_steer_rad = deg_to_rad(deg);
    }
    if (auto a = f.take("max_steer_rate_degps")) rc.max_steer_rate_radps = deg_to_rad(a->positive());
    rc.max_step_m = f.non_negative("max_step_m", rc.max_step_m);
    s.start_source = {v->line(), "robot.start"};
    if (auto st = f.take("start")) {
      s.start_source = {st->line(), st->field()};
      Fields sf = fields_of(*st, doc);
      s.start = Pose2(sf.number("x_m", 0.0), sf.number("y_m", 0.0), wrap_angle(sf.angle_deg("yaw_deg", 0.0)));
      sf.finish("x_m, y_m, yaw_deg");
    }
    f.finish("drive, half_track_m, half_wheelbase_m, wheel_radius_m, roller_angle_deg, body_length_m, body_width_m, "
             "body_height_m, ground_clearance_m, max_wheel_speed_radps, max_wheel_accel_radps2, actuator_lag_s, "
             "max_steer_deg, max_steer_rate_degps, max_step_m, start");
  }
  if (auto v = top.take("vehicle")) {
    vehicle_fields.emplace(fields_of(*v, doc));
    Fields& f = *vehicle_fields;
    s.vehicle.friction = f.positive("friction", s.vehicle.friction);
    s.vehicle.rough_slip_sigma = f.non_negative("rough_slip_sigma", s.vehicle.rough_slip_sigma);
    f.finish("friction, rough_slip_sigma");
  }
  try {
    s.vehicle.validate();
  } catch (const Error& e) {
    rethrow_vehicle_error(e, doc, robot_fields ? &*robot_fields : nullptr, vehicle_fields ? &*vehicle_fields : nullptr,
                          s.robot_source.line);
  }

  if (auto v = top.take("sensors")) {
    Fields f = fields_of(*v, doc);
    if (auto l = f.take("lidar")) s.lidar = parse_lidar(*l, doc, rc);
    if (auto ls = f.take("lidars")) {
      if (!ls->node().IsMap()) ls->fail("expected LiDARs by name (rear: {preset: ..., mount: ...}), found " + node_kind(ls->node()));
      if (!s.lidar) ls->fail("more LiDARs need the first one (sensors.lidar)");
      Fields g = fields_of(*ls, doc);
      for (const std::string& name : g.keys()) {
        const Value v = *g.take(name.c_str());
        const bool snake = !name.empty() && name[0] >= 'a' && name[0] <= 'z' &&
                           name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
        if (!snake || name == "lidar")
          v.fail("a LiDAR's name is lower_snake_case (its stream is lidar/NAME)");
        if (s.other_lidars.size() == kMaxOtherLidars) v.fail("more than " + std::to_string(kMaxOtherLidars) + " more LiDARs");
        ScenarioLidar l = parse_lidar(v, doc, rc);
        l.stream = "lidar/" + name;
        s.other_lidars.push_back(std::move(l));
      }
    }
    if (auto i = f.take("imu")) {
      Fields g = fields_of(*i, doc);
      ScenarioImu imu;
      imu.source = {i->line(), i->field()};
      ImuConfig& c = imu.config;
      c.rate_hz = g.positive("rate_hz", c.rate_hz);
      c.yaw_rate_noise_sigma_radps = g.non_negative("yaw_rate_noise_sigma_radps", c.yaw_rate_noise_sigma_radps);
      c.yaw_rate_bias_radps = g.number("yaw_rate_bias_radps", c.yaw_rate_bias_radps);
      c.yaw_noise_sigma_rad = g.non_negative("yaw_noise_sigma_rad", c.yaw_noise_sigma_rad);
      g.finish("rate_hz, yaw_rate_noise_sigma_radps, yaw_rate_bias_radps, yaw_noise_sigma_rad");
      try {
        c.validate();
      } catch (const Error& e) {
        rethrow_at(e, doc, i->line(), "sensors");
      }
      s.imu = imu;
    }
    if (auto i = f.take("encoders")) {
      Fields g = fields_of(*i, doc);
      ScenarioEncoders enc;
      enc.source = {i->line(), i->field()};
      enc.rate_hz = g.positive("rate_hz", enc.rate_hz);
      if (auto t = g.take("ticks_per_rev")) enc.config.ticks_per_rev = static_cast<int>(t->integer(1, 1 << 30));
      enc.config.slip_sigma = g.non_negative("slip_sigma", enc.config.slip_sigma);
      g.finish("rate_hz, ticks_per_rev, slip_sigma");
      try {
        enc.config.validate();
      } catch (const Error& e) {
        rethrow_at(e, doc, i->line(), "sensors");
      }
      s.encoders = enc;
    }
    if (auto b = f.take("bumper")) s.bumper = b->boolean();
    f.finish("lidar, lidars, imu, encoders, bumper");
  }

  if (auto v = top.take("commands")) {
    if (!v->node().IsSequence()) v->fail("expected a list of command segments, found " + node_kind(v->node()));
    double t = 0.0;
    for (std::size_t i = 0; i < v->node().size(); ++i) {
      const Value e = v->element(i);
      if (e.node().IsNull()) e.fail("expected a segment {duration_s or until_s, vx_mps, vy_mps, wz_radps}");
      Fields f = fields_of(e, doc);
      CommandSegment c;
      c.line = e.line();
      c.start_s = t;
      const bool has_d = f.has("duration_s"), has_u = f.has("until_s");
      if (has_d == has_u) e.fail("give exactly one of duration_s or until_s");
      if (has_d) {
        const Value d = f.required("duration_s");
        c.end_s = t + d.positive();
        // The sum can overflow to infinity, or a tiny duration can vanish beside a large t.
        if (!std::isfinite(c.end_s)) d.fail("the script's end overflows (" + Value::fmt(t) + " s + " + d.node().Scalar() + " s)");
        if (!(c.end_s > t)) d.fail("too short to end after the previous segment's end (" + Value::fmt(t) + " s)");
      } else {
        const Value u = f.required("until_s");
        c.end_s = u.number();
        if (!(c.end_s > t)) u.fail("must be later than the previous segment's end (" + Value::fmt(t) + " s)");
      }
      c.twist.vx = f.number("vx_mps", 0.0);
      c.twist.vy = f.number("vy_mps", 0.0);
      c.twist.wz = f.number("wz_radps", 0.0);
      f.finish("duration_s, until_s, vx_mps, vy_mps, wz_radps");
      t = c.end_s;
      s.commands.push_back(c);
    }
  }
  if (auto v = top.take("route")) {
    if (!s.commands.empty()) v->fail("a route and a command script: give one of them");
    Fields f = fields_of(*v, doc);
    ScenarioRoute r;
    r.source = {v->line(), v->field()};
    const Value w = f.required("waypoints_m");
    if (!w.node().IsSequence() || w.node().size() < 2) w.fail("expected a list of at least 2 points [x, y], found " + node_kind(w.node()));
    for (std::size_t i = 0; i < w.node().size(); ++i) {
      const auto p = w.element(i).numbers(2, 2);
      r.waypoints.emplace_back(p[0], p[1]);
    }
    r.speed_mps = f.positive("speed_mps", r.speed_mps);
    if (auto n = f.take("laps")) r.laps = static_cast<int>(n->integer(1, 1000));
    r.clearance_m = f.non_negative("clearance_m", r.clearance_m);
    f.finish("waypoints_m, speed_mps, laps, clearance_m");
    if (!s.occupancy_map) v->fail("a route is planned on world.occupancy_map, which the scenario lacks");
    s.route = r;
  }
  if (duration) s.duration_s = *duration;
  else if (!s.commands.empty()) s.duration_s = s.commands.back().end_s;
  else throw Error("required when there are no commands", file, top.line_of("sim"), "sim.duration_s");

  if (auto v = top.take("motion_mode")) {
    s.motion_mode = v->string();
    s.motion_mode_source = {v->line(), v->field()};
    if (s.motion_mode != "auto" && s.motion_mode != "turn_then_drive" && s.motion_mode != "holonomic" &&
        s.motion_mode != "pure_pursuit")
      v->fail("unknown motion mode '" + s.motion_mode + "' (auto, turn_then_drive, holonomic, pure_pursuit)");
  }
  if (auto v = top.take("navigation")) {
    s.navigation = parse_navigation(*v, doc);
    if (s.route) throw Error("a navigation scenario has no route (the navigation stack drives)", file, s.route->source.line, "route");
    if (!s.commands.empty())
      throw Error("a navigation scenario has no command script (the navigation stack drives)", file,
                  top.line_of("commands"), "commands");
  }
  if (auto v = top.take("localization")) {
    // A scripted run may carry a chain too: it runs beside the script and records its estimate.
    s.localization = parse_settings_section(*v, doc);
  }

  if (auto v = top.take("events")) {
    if (!v->node().IsSequence()) v->fail("expected a list of events, found " + node_kind(v->node()));
    for (std::size_t i = 0; i < v->node().size(); ++i) {
      const Value e = v->element(i);
      Fields f = fields_of(e, doc);
      ScenarioTeleport t;
      t.source = {e.line(), e.field()};
      t.t_s = f.required("t_s").non_negative();
      if (!s.teleports.empty() && t.t_s < s.teleports.back().t_s) e.fail("events must be in time order");
      const Value to = f.required("teleport");
      Fields g = fields_of(to, doc);
      t.to = Pose2(g.number("x_m", 0.0), g.number("y_m", 0.0), deg_to_rad(g.number("yaw_deg", 0.0)));
      g.finish("x_m, y_m, yaw_deg");
      f.finish("t_s, teleport");
      s.teleports.push_back(t);
    }
  }

  if (auto v = top.take("metrics")) {
    Fields f = fields_of(*v, doc);
    if (auto r = f.take("reference_line_m")) {
      if (!r->node().IsSequence() || r->node().size() < 2)
        r->fail("expected a list of at least 2 points [x, y], found " + node_kind(r->node()));
      for (std::size_t i = 0; i < r->node().size(); ++i) {
        const auto p = r->element(i).numbers(2, 2);
        s.reference_line.emplace_back(p[0], p[1]);
      }
    }
    f.finish("reference_line_m");
  }

  if (auto v = top.take("outputs")) {
    Fields f = fields_of(*v, doc);
    if (auto n = f.take("trajectory_every_n_steps")) s.outputs.trajectory_every_n_steps = static_cast<int>(n->integer(1, 1000000));
    if (auto pc = f.take("point_clouds")) {
      Fields g = fields_of(*pc, doc);
      const Value fmt = g.required("format");
      try {
        s.outputs.point_clouds = parse_cloud_format(fmt.string(), fmt.field());
      } catch (const Error& e) {
        fmt.fail(e.message());
      }
      if (auto n = g.take("every_n_scans")) s.outputs.clouds_every_n_scans = static_cast<int>(n->integer(1, 1000000));
      g.finish("format, every_n_scans");
      if (s.outputs.point_clouds != ScenarioOutputs::CloudFormat::None && !s.lidar)
        throw Error("point clouds need sensors.lidar", file, pc->line(), pc->field());
    }
    if (auto lf = f.take("lidar_frames")) {
      Fields g = fields_of(*lf, doc);
      s.outputs.lidar_frames_every_n_scans = 1;
      if (auto n = g.take("every_n_scans")) s.outputs.lidar_frames_every_n_scans = static_cast<int>(n->integer(1, 1000000));
      g.finish("every_n_scans");
      if (!s.lidar) throw Error("LiDAR frames need sensors.lidar", file, lf->line(), lf->field());
    }
    f.finish("trajectory_every_n_steps, point_clouds, lidar_frames");
  }

  top.finish("name, description, world, robot, vehicle, sensors, sim, commands, route, events, motion_mode, navigation, localization, metrics, outputs");
  // A sensor samples at most once per simulation step: a faster rate would only repeat the
  // same state, and an absurd one (1e300 Hz) would never finish a step.
  const double max_rate_hz = 1.0 / s.dt_s * (1.0 + 1e-9);
  const auto check_rate = [&](double rate_hz, const ScenarioSource& src, const std::string& field) {
    if (rate_hz > max_rate_hz)
      throw Error("is " + format_number(rate_hz) + " Hz, more than one sample per simulation step (1 / sim.dt_s = " +
                      format_number(1.0 / s.dt_s) + " Hz)",
                  file, src.line, field);
  };
  if (s.lidar) check_rate(s.lidar->config.rate_hz, s.lidar->source, "sensors.lidar.rate_hz");
  for (const ScenarioLidar& l : s.other_lidars) check_rate(l.config.rate_hz, l.source, l.source.field + ".rate_hz");
  if (s.imu) check_rate(s.imu->config.rate_hz, s.imu->source, "sensors.imu.rate_hz");
  if (s.encoders) check_rate(s.encoders->rate_hz, s.encoders->source, "sensors.encoders.rate_hz");
  check_simulation_steps(s, "sim.duration_s");
  return s;
}

}  // namespace

BodyTwist ScenarioSpec::command_at(double t) const {
  const int i = segment_at(t);
  return i < 0 ? BodyTwist{} : commands[static_cast<std::size_t>(i)].twist;
}

int ScenarioSpec::segment_at(double t) const {
  // Segments are consecutive from 0: the first whose end lies beyond t.
  const auto it = std::upper_bound(commands.begin(), commands.end(), t,
                                   [](double v, const CommandSegment& c) { return v < c.end_s; });
  if (it == commands.end() || t < 0.0) return -1;
  return static_cast<int>(it - commands.begin());
}

namespace {

// A copy of `n` without marks: values set on the command line have no line in the file.
YAML::Node unmarked(const YAML::Node& n) {
  if (n.IsScalar()) return YAML::Node(n.Scalar());
  if (n.IsSequence()) {
    YAML::Node out(YAML::NodeType::Sequence);
    for (const auto& e : n) out.push_back(unmarked(e));
    return out;
  }
  if (n.IsMap()) {
    YAML::Node out(YAML::NodeType::Map);
    for (auto it = n.begin(); it != n.end(); ++it) out[it->first.Scalar()] = unmarked(it->second);
    return out;
  }
  return YAML::Node();
}

void apply_override(YAML::Node& root, const ScenarioOverride& o, const std::string& file) {
  const std::string field = "--set " + o.key;
  std::vector<std::string> parts;
  for (std::size_t b = 0;;) {
    const std::size_t e = o.key.find('.', b);
    parts.push_back(o.key.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  for (const std::string& p : parts)
    if (p.empty() || p.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
      throw Error("a key is dotted lower_snake_case names (navigation.follower.look_ahead_m)", "", 0, field);
  if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw Error("the scenario is not a mapping", file, 0, field);
  YAML::Node node = root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = node[parts[i]];
    if (!child.IsDefined() || child.IsNull()) {
      node[parts[i]] = YAML::Node(YAML::NodeType::Map);
      child.reset(node[parts[i]]);
    } else if (!child.IsMap()) {
      throw Error("'" + parts[i] + "' is not a section of the scenario", file, 0, field);
    }
    node.reset(child);
  }
  YAML::Node value;
  try {
    value = load_yaml_document(o.value, "");
  } catch (const Error& e) {
    throw Error("not a YAML value: " + e.message(), "", 0, field);
  }
  // A fresh key (no mark): the value has no line in the file.
  node.remove(parts.back());
  node[parts.back()] = value.IsNull() && !o.value.empty() ? YAML::Node(o.value) : unmarked(value);
}

}  // namespace

ScenarioOverride parse_scenario_override(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw Error("expected KEY=VALUE, found '" + one_line(text, 60) + "'", "", 0, "--set");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

void check_user_overrides(std::span<const ScenarioOverride> overrides, std::span<const CommandOwnedKey> owned) {
  const auto under = [](const std::string& key, const std::string& prefix) {
    return key == prefix || key.rfind(prefix + ".", 0) == 0 || key.rfind(prefix + "[", 0) == 0;
  };
  for (std::size_t i = 0; i < overrides.size(); ++i) {
    const std::string& key = overrides[i].key;
    for (std::size_t j = 0; j < i; ++j)
      if (overrides[j].key == key) throw Error("given twice; give each key once", "", 0, key + " (--set)");
    for (const CommandOwnedKey& o : owned)
      if (under(key, o.key)) throw Error("the command sets " + o.key + " itself (" + o.why + ")", "", 0, key + " (--set)");
  }
}

ScenarioSpec parse_scenario(std::string_view yaml_text, const std::string& file, std::span<const ScenarioOverride> overrides) {
  YAML::Node root = load_yaml_document(yaml_text, file);
  for (const ScenarioOverride& o : overrides) apply_override(root, o, file);
  try {
    return parse_document(root, file);
  } catch (const YAML::Exception& e) {
    throw Error("invalid YAML: " + one_line(e.msg, 60), file, e.mark.is_null() ? 0 : e.mark.line + 1);
  } catch (const Error& e) {
    // A value from --set has no line: say where it came from.
    if (e.line() == 0 && !e.field().empty() && e.field().find("(--set)") == std::string::npos)
      for (const ScenarioOverride& o : overrides)
        if (e.field() == o.key || e.field().rfind(o.key + ".", 0) == 0 || e.field().rfind(o.key + "[", 0) == 0)
          throw Error(e.message(), e.file(), 0, e.field() + " (--set)");
    throw;
  }
}

void check_simulation_steps(const ScenarioSpec& spec, const std::string& field) {
  const double steps = spec.duration_s / spec.dt_s;
  if (!(steps <= kMaxSimulationSteps))
    throw Error(format_number(spec.duration_s) + " s at sim.dt_s " + format_number(spec.dt_s) + " s is " + format_number(steps) +
                    " steps, more than the " + format_number(kMaxSimulationSteps) + " a run may take",
                spec.file, 0, field);
  double rays = 0.0;
  std::vector<const ScenarioLidar*> lidars;
  if (spec.lidar) lidars.push_back(&*spec.lidar);
  for (const ScenarioLidar& l : spec.other_lidars) lidars.push_back(&l);
  for (const ScenarioLidar* lidar : lidars) {
    const LidarConfig& l = lidar->config;
    const double scans = std::floor(spec.duration_s * l.rate_hz) + 1.0;
    rays += scans * static_cast<double>(l.ray_count());
    if (!(rays <= kMaxSimulationLidarRays))
      throw Error(format_number(spec.duration_s) + " s of " + format_number(l.rate_hz) + " Hz scans of " +
                      std::to_string(l.ray_count()) + " rays is " + format_number(rays) + " rays, more than the " +
                      format_number(kMaxSimulationLidarRays) + " a run may cast",
                  spec.file, 0, field);
  }
}

ScenarioSpec load_scenario(const std::string& path, std::span<const ScenarioOverride> overrides) {
  const InputFileScope reading_path(path);
  return parse_scenario(read_yaml_file(path), path, overrides);
}

WorldDescription build_world(const ScenarioSpec& spec) {
  WorldDescription d;
  const ScenarioTerrain& t = spec.terrain;
  const auto fail = [&](const Error& e) -> void {
    throw Error(e.message() + (e.file().empty() || e.file() == t.resolved_file ? "" : " (" + e.file() + ")"), spec.file,
                t.source.line, t.source.field);
  };
  try {
    switch (t.kind) {
      case ScenarioTerrain::Kind::None:
        break;
      case ScenarioTerrain::Kind::File: {
        LoadedMap m;
        try {
          m = load_map(t.resolved_file);
        } catch (const Error& e) {
          // e.what() starts with the terrain file's own path (and line) where it has them.
          const std::string what = e.file().empty() ? t.resolved_file + ": " + e.what() : std::string(e.what());
          throw Error("cannot load the terrain: " + what, spec.file, t.source.line, t.source.field);
        }
        if (!m.is_elevation())
          throw Error("terrain file " + t.resolved_file + " is an occupancy map, not an elevation map", spec.file,
                      t.source.line, t.source.field);
        d.terrain = m.elevation();
        break;
      }
      case ScenarioTerrain::Kind::Flat: {
        ElevationMap m(terrain_geometry(t.hills.width_m, t.hills.height_m, t.hills.resolution, t.hills.origin));
        for (int iy = 0; iy < m.height(); ++iy)
          for (int ix = 0; ix < m.width(); ++ix) m.set_height(ix, iy, t.flat_z_m);
        d.terrain = std::move(m);
        break;
      }
      case ScenarioTerrain::Kind::Hills: {
        HillsOptions h = t.hills;
        if (!t.seed_given) h.seed = spec.seed;
        d.terrain = generate_hills(h);
        break;
      }
      case ScenarioTerrain::Kind::Road: {
        RoadOptions r = t.road;
        if (!t.seed_given) r.seed = spec.seed;
        d.terrain = generate_road(r).map;
        break;
      }
    }
    if (d.terrain)
      for (const TerrainFeature& f : t.features) add_terrain_feature(*d.terrain, f);
  } catch (const Error& e) {
    if (e.file() == spec.file) throw;
    fail(e);
  }

  std::optional<TerrainSurface> ground;
  if (d.terrain) {
    try {
      ground.emplace(*d.terrain);
    } catch (const Error& e) {
      fail(e);
    }
  }
  if (spec.occupancy_map) {
    const ScenarioOccupancyWorld& m = *spec.occupancy_map;
    try {
      RosMapMetadata meta;
      const OccupancyGrid grid = read_ros_map(m.resolved_file, &meta);
      Obstacle walls = occupancy_walls(grid, meta.occupied_thresh * 100.0, m.wall_height_m, "occupancy_map");
      if (!walls.parts.empty()) d.obstacles.push_back(std::move(walls));
    } catch (const Error& e) {
      const std::string what = e.file().empty() ? m.resolved_file + ": " + e.what() : std::string(e.what());
      throw Error("cannot make the world from the occupancy map: " + what, spec.file, m.source.line, m.source.field);
    }
  }
  for (const ScenarioObstacle& s : spec.obstacles) {
    double gz = 0.0;
    if (ground) {
      const double h = ground->height(s.position.x(), s.position.y());
      if (std::isfinite(h)) gz = h;
    }
    try {
      Obstacle o = place_obstacle(s, gz, ground ? &*ground : nullptr, spec.seed);
      validate(o);
      d.obstacles.push_back(std::move(o));
    } catch (const Error& e) {
      throw Error(e.message(), spec.file, s.source.line, s.source.field + (e.field().empty() ? "" : "." + e.field()));
    }
  }
  return d;
}

const char* cloud_format_name(ScenarioOutputs::CloudFormat f) {
  switch (f) {
    case ScenarioOutputs::CloudFormat::None:
      return "none";
    case ScenarioOutputs::CloudFormat::Ply:
      return "ply";
    case ScenarioOutputs::CloudFormat::Pcd:
      return "pcd";
  }
  return "none";
}

ScenarioOutputs::CloudFormat parse_cloud_format(const std::string& s, const std::string& field) {
  if (s == "none") return ScenarioOutputs::CloudFormat::None;
  if (s == "ply") return ScenarioOutputs::CloudFormat::Ply;
  if (s == "pcd") return ScenarioOutputs::CloudFormat::Pcd;
  throw Error("unknown point cloud format '" + s + "' (ply, pcd, none)", {}, 0, field);
}

}  // namespace starnav
