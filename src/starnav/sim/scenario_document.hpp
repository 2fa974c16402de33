#pragma once
// Internal to sim/: reading a scenario document (scenario.cpp and its sections' files). A YAML
// value with its dotted field and line (Value), a mapping read key by key (Fields), and the
// declared sections: each mapping's scalar keys are a ParamTable over the struct it fills, with
// the keys that hand-written code reads (lists, nested mappings) listed beside it, so the
// parser, the unknown-key messages and docs/scenarios.md's tables come from one declaration.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/core/params.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/scenario_keys.hpp"
#include "starnav/sim/terrain_surface.hpp"

namespace starnav::scenario_detail {

int mark_line(const YAML::Node& n);
// "nothing", "a list", "a mapping" or the scalar quoted.
std::string node_kind(const YAML::Node& n);

// The reading context of one document: file name for errors, folder for relative paths.
struct Doc {
  std::string file;
  std::filesystem::path base_dir;
};

// A YAML value with its dotted field path and line, converted with checks that name both.
class Value {
 public:
  Value(const YAML::Node& node, std::string field, int line, const Doc& doc)
      : node_(node), field_(std::move(field)), line_(line), doc_(&doc) {}

  const YAML::Node& node() const { return node_; }
  const std::string& field() const { return field_; }
  int line() const { return line_; }
  const Doc& doc() const { return *doc_; }
  [[noreturn]] void fail(const std::string& message) const { throw Error(message, doc_->file, line_, field_); }

  double number() const;
  double in_range(double lo, double hi) const;
  std::string string() const;
  // A list of numbers with `lo`..`hi` entries.
  std::vector<double> numbers(std::size_t lo, std::size_t hi) const;
  Value element(std::size_t i) const;
  // Checks that the value is a list and returns its size ("expected a list of WHAT" otherwise).
  std::size_t list(const std::string& what) const;
  static std::string fmt(double v);

 private:
  YAML::Node node_;
  std::string field_;
  int line_;
  const Doc* doc_;
};

// A YAML mapping read key by key: every key must be taken, or it is unknown.
class Fields {
 public:
  Fields(const Value& v, const Doc& doc);

  bool has(const char* key) const { return find(key) != nullptr; }
  // The value of `key` (marked as read), or nothing.
  std::optional<Value> take(const char* key);
  Value required(const char* key);
  // Error "required key is missing" when `key` is absent (a declared key applied later).
  void require(const char* key) const;
  std::string path(const std::string& key) const { return field_.empty() ? key : field_ + "." + key; }
  bool taken(const std::string& key) const { return used_.count(key) > 0; }
  // Every key, in document order.
  std::vector<std::string> keys() const;
  int line() const { return line_; }
  int line_of(const std::string& key) const;
  const std::string& field() const { return field_; }
  const Doc& doc() const { return *doc_; }
  [[noreturn]] void fail(const std::string& message) const { throw Error(message, doc_->file, line_, field_); }
  // Error naming `key` (its line, its full field; "(--set)" when it came from the command line).
  [[noreturn]] void fail_at(const std::string& key, const std::string& message) const;

 private:
  struct Entry {
    std::string key;
    YAML::Node value;
    int line = 0;
  };
  const Entry* find(const std::string& key) const;

  std::string field_;
  int line_;
  const Doc* doc_;
  std::vector<Entry> entries_;
  std::set<std::string> used_;
};

// Re-raises a library validation error (whose field is the library's name) at a YAML location.
[[noreturn]] void rethrow_at(const Error& e, const Doc& doc, int line, const std::string& field_prefix);
Vec3 xyz_or_xy(const Value& v, double z_default, bool* had_z = nullptr);
// A setting for `key` from value `e` (its full field, "(--set)" when it has no line).
ParamSetting setting_of(const Value& e, const std::string& key);
// A sequence whose items are scalars or such sequences, at most `depth` levels deep (no
// parameter nests deeper than polygons' three).
bool is_value_list(const YAML::Node& node, int depth = 4);
// `node` (scalars and sequences) as one line of flow text: [[0, 0], [1, 0]]; a parameter's own
// parser reads the shape.
std::string flow_text(const YAML::Node& node);
// `path` resolved against the scenario's folder.
std::string resolve_path(const Doc& doc, const std::string& path);

// A key that hand-written code reads (a list, a nested mapping), documented beside the table's.
struct StructuralKey {
  std::string key;
  std::string type;           // "[x, y]", "mapping", "list of {t_s, position_m}"
  std::string default_value;  // "required" for a required key
  std::string range;
  std::string unit;
  std::string doc;
  bool leading = false;  // listed before the table's keys (docs and messages)
};

// One scenario mapping: its scalar keys declared with a ParamTable over `Config`, its other keys
// read by hand. `id` and `title` name it in docs/scenarios.md.
template <class Config>
struct SectionDecl {
  std::string id;     // "robot", "sensors.lidar", "world.obstacles.box"
  std::string title;  // the mapping as the user writes it: "world.obstacles[i] (kind: box)"
  ParamTable<Config> table;
  std::vector<StructuralKey> structural;
  Config defaults{};
  std::vector<std::string> required;  // declared keys that must be given

  std::vector<std::string> known() const {
    std::vector<std::string> k;
    for (const StructuralKey& s : structural)
      if (s.leading) k.push_back(s.key);
    for (const std::string& t : table.keys()) k.push_back(t);
    for (const StructuralKey& s : structural)
      if (!s.leading) k.push_back(s.key);
    return k;
  }
  bool is_required(const std::string& key) const {
    for (const std::string& r : required)
      if (r == key) return true;
    return false;
  }
  ScenarioKeySection describe(bool with_table_keys = true) const {
    ScenarioKeySection out;
    out.id = id;
    out.title = title;
    const auto structural_row = [](const StructuralKey& s) {
      return ScenarioKeyRow{s.key, s.type, s.default_value, s.range, s.unit, s.doc};
    };
    for (const StructuralKey& s : structural)
      if (s.leading) out.rows.push_back(structural_row(s));
    if (with_table_keys)
      for (const ParamSpec& p : table.specs(defaults)) {
        out.rows.push_back({p.key, param_type_name(p.type), is_required(p.key) ? "required" : p.default_value, p.range_text(),
                            p.unit, p.doc});
        out.specs.push_back(p);
      }
    for (const StructuralKey& s : structural)
      if (!s.leading) out.rows.push_back(structural_row(s));
    const ParamTable<Config>* t = &table;
    const Config d = defaults;
    out.apply = [t, d](const ParamSetting& setting) {
      Config c = d;
      t->apply(c, setting);
    };
    return out;
  }
};

// Error "required key is missing" for the first of `d`'s required keys that `f` lacks.
template <class Config>
void require_all(const Fields& f, const SectionDecl<Config>& d) {
  for (const std::string& r : d.required) f.require(r.c_str());
}

// Degrees: the scale of an angle written in degrees and stored in radians.
inline constexpr double kDeg = deg_to_rad(1.0);

// "expected a number", "expected true or false", ...: what a value of `type` is.
std::string expected_value(const ParamSpec& spec);

// Applies the values of `f`'s keys that the tables of `decls` declare (all not taken yet, or
// only those in `only`), in document order. A key no table declares and no hand-written code
// took is unknown: one error naming it and listing every known key of the mapping.
template <class Config>
void apply_section(Fields& f, std::initializer_list<const SectionDecl<Config>*> decls, Config& c,
                   std::initializer_list<const char*> only = {}) {
  for (const std::string& k : f.keys()) {
    if (f.taken(k)) continue;
    if (only.size() != 0 && std::none_of(only.begin(), only.end(), [&](const char* o) { return k == o; })) continue;
    const SectionDecl<Config>* owner = nullptr;
    for (const SectionDecl<Config>* d : decls)
      if (d->table.has(k)) owner = d;
    const Value v = *f.take(k.c_str());
    ParamSetting s = setting_of(v, k);
    if (!owner) {
      std::vector<std::string> known;
      for (const SectionDecl<Config>* d : decls)
        for (const std::string& n : d->known())
          if (std::find(known.begin(), known.end(), n) == known.end()) known.push_back(n);
      param_unknown_key(s, known);
    }
    if (!v.node().IsScalar())
      for (const ParamSpec& p : owner->table.specs(owner->defaults)) {
        if (p.key != k) continue;
        // A list parameter takes a list of values, in flow text for its own parser.
        const bool list = p.type == ParamType::Reals || p.type == ParamType::NameList || p.type == ParamType::Polygons;
        if (!list || !v.node().IsSequence() || !is_value_list(v.node())) v.fail(expected_value(p) + ", found " + node_kind(v.node()));
        s.value = flow_text(v.node());
      }
    owner->table.apply(c, s);
  }
}
template <class Config>
void apply_section(Fields& f, const SectionDecl<Config>& decl, Config& c, std::initializer_list<const char*> only = {}) {
  apply_section(f, {&decl}, c, only);
}

// A member by pointer, or a nested member by a lambda returning a reference.
template <class Config, class Access>
auto& member_of(Config& c, Access a) {
  if constexpr (std::is_member_object_pointer_v<Access>) return c.*a;
  else return a(c);
}

// A seed: any whole number from 0 to 2^64 - 1 (a ParamTable integer stops at 2^63 - 1).
template <class Config, class Access>
void declare_seed(ParamTable<Config>& t, const std::string& key, Access access, const std::string& doc) {
  ParamSpec spec{key, ParamType::Integer, {}, closed(0, 18446744073709551615.0), {}, "", doc};
  t.custom(
      spec,
      [access](Config& c, const ParamSetting& v) {
        const std::optional<std::uint64_t> x = parse_unsigned_text(v.value);
        if (!x)
          throw Error("expected a non-negative integer, found '" + one_line(v.value, 60) + "'", v.file, v.line,
                      v.field.empty() ? v.key : v.field);
        member_of(c, access) = *x;
      },
      [access](const Config& c) {
        Config copy = c;
        return std::to_string(member_of(copy, access));
      });
}

// The sections, each defined beside the code that reads it.
std::vector<ScenarioKeySection> top_sections();
std::vector<ScenarioKeySection> world_sections();
std::vector<ScenarioKeySection> robot_sections();
std::vector<ScenarioKeySection> navigation_sections();
std::vector<ScenarioKeySection> output_sections();

// The sections' readers (scenario_world.cpp, scenario_robot.cpp, scenario_navigation.cpp).
void parse_world(const Value& v, ScenarioSpec& s);
void parse_robot_and_vehicle(std::optional<Value> robot, std::optional<Value> vehicle, ScenarioSpec& s);
void parse_sensors(const Value& v, ScenarioSpec& s);
void parse_commands(const Value& v, ScenarioSpec& s);
void parse_route(const Value& v, ScenarioSpec& s);
void parse_events(const Value& v, ScenarioSpec& s);
ScenarioNavigation parse_navigation(const Value& v);
ScenarioSettings parse_settings_section(const Value& v);
void parse_metrics(const Value& v, ScenarioSpec& s);
void parse_outputs(const Value& v, ScenarioSpec& s);
// The obstacle posed at ground height `ground_z` (used when no z is given).
Obstacle place_obstacle(const ScenarioObstacle& s, double ground_z, const TerrainSurface* ground, std::uint64_t seed);

}  // namespace starnav::scenario_detail
