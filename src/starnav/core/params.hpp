#pragma once
// Declared parameters: a component states each of its parameters once (key, type, default, range
// or choices, unit, one-line doc) and binds it to a member of its configuration struct. Every
// front end is generated from that one declaration: scenario YAML sections, `--set key=value`
// on the command line, `--help` texts, validation errors and docs/parameters.md
// (docs/architecture.md, "Components").
//
//   ParamTable<PathFollowerConfig> t;
//   t.real("cruise_speed_mps", &PathFollowerConfig::cruise_speed_mps, positive(), "m/s", "nominal speed");
//   t.apply(config, {"cruise_speed_mps", "0.3", "e4.yaml", 12, "navigation.follower.cruise_speed_mps"});
//
// Values always arrive as text (a YAML scalar or the right side of --set), so the YAML file and
// the command line share one parser and one set of messages. A value outside its range, of the
// wrong type, or for an unknown key is an Error naming the file, the line and the full dotted key.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <type_traits>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"

namespace starnav {

enum class ParamType : std::uint8_t { Real, Integer, Boolean, Choice, NameList, Polygons, Text, Reals };
// "real", "integer", "boolean", "choice", "names", "polygons", "text", "reals"
const char* param_type_name(ParamType t);

// An interval for numbers; open or closed at each end, either end may be unbounded.
struct ParamRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool contains(double v) const;
  std::string text() const;  // "> 0", ">= 0", "[1, 255]", "(0, 90)", "any"
};
ParamRange any_value();
ParamRange positive();      // > 0
ParamRange non_negative();  // >= 0
ParamRange closed(double lo, double hi);
ParamRange open(double lo, double hi);

// What a user reads about a parameter (docs, --help, error messages).
struct ParamSpec {
  std::string key;  // relative to the component's section, may itself be dotted ("map.hit_gain")
  ParamType type = ParamType::Real;
  std::string default_value;  // as text, in the parameter's unit; or the rule that gives it
  ParamRange range;           // Real, Integer
  std::vector<std::string> choices;  // Choice, NameList
  std::string unit;           // of the value as written ("m", "m/s", "deg", "" for none)
  std::string doc;            // one line
  std::string range_text() const;  // the range, or "a | b | c" for choices, "true | false"
};

// One value given by the user, with where it came from (errors name it).
struct ParamSetting {
  std::string key;    // relative to the section being applied
  std::string value;  // text
  std::string file;   // scenario file, or "" for the command line
  int line = 0;
  std::string field;  // the full dotted key as the user wrote it ("navigation.follower.look_ahead_m", "--set ...")
};

// A list of names as a setting holds it: "a, b" (a YAML list [a, b] in a scenario; "" for none).
// Each name lower_snake_case; Error naming `setting` otherwise.
std::vector<std::string> parse_param_name_list(const ParamSetting& setting);
std::string format_param_name_list(const std::vector<std::string>& names);  // "[a, b]"

// Polygons as a setting holds them: a list of polygons, each a list of at least 3 points [x, y]
// ("[[[0, 0], [2, 0], [2, 1]]]"; a YAML list of lists in a scenario; "[]" for none). The
// polygon closes itself (the last point joins the first). At most kMaxParamPolygonVertices
// points in all. Error naming `setting` otherwise.
using ParamPolygon = std::vector<std::array<double, 2>>;
inline constexpr std::size_t kMaxParamPolygonVertices = 100000;
std::vector<ParamPolygon> parse_param_polygons(const ParamSetting& setting);
std::string format_param_polygons(const std::vector<ParamPolygon>& polygons);

// A list of numbers as a setting holds it: "[0.3, 0.5]" (a YAML list of numbers in a scenario;
// "[]" or "" for none, "" being how a scenario's empty list [] arrives). At most
// kMaxParamListNumbers numbers. Error naming `setting` otherwise.
inline constexpr std::size_t kMaxParamListNumbers = 100000;
std::vector<double> parse_param_reals(const ParamSetting& setting);
std::string format_param_reals(const std::vector<double>& values);  // "[0.3, 0.5]"

// Strict text -> value conversions shared by every table (Errors name `setting`).
double parse_param_real(const ParamSetting& setting);
// A count (an integer parameter whose range starts at 0 or above) takes no sign, as on the
// command line (core/number_text.hpp).
long long parse_param_integer(const ParamSetting& setting, bool count = false);
bool parse_param_boolean(const ParamSetting& setting);
std::string format_param_real(double v);  // shortest text that reads back the same double
// The text of a stored value in the user's unit (stored / scale): 12 significant digits when
// that text reads back to the same stored value ("15" for 15 degrees in radians), else the
// shortest exact text.
std::string format_param_scaled(double stored, double scale);

// The checks every ParamTable applies (params.cpp); errors name the setting's file, line and key.
void param_check_range(const ParamSetting& v, const ParamRange& r, double x);
// The same for the number at 0-based `index` of a list (the message names it 1-based).
void param_check_list_range(const ParamSetting& v, std::size_t index, const ParamRange& r, double x);
void param_check_choice(const ParamSetting& v, const std::vector<std::string>& choices);
[[noreturn]] void param_unknown_key(const ParamSetting& v, const std::vector<std::string>& known);

// The parameters of one configuration struct.
template <class Config>
class ParamTable {
 public:
  template <class Access>
  ParamTable& real(std::string key, Access access, ParamRange range, std::string unit, std::string doc,
                   double scale = 1.0) {
    ParamSpec s{std::move(key), ParamType::Real, {}, range, {}, std::move(unit), std::move(doc)};
    add(std::move(s),
        [access, scale, range](Config& c, const ParamSetting& v) {
          const double x = parse_param_real(v);
          param_check_range(v, range, x);
          ref(c, access) = x * scale;
        },
        [access, scale](const Config& c) { return format_param_scaled(cref(c, access), scale); });
    return *this;
  }

  template <class Access>
  ParamTable& integer(std::string key, Access access, ParamRange range, std::string unit, std::string doc) {
    ParamSpec s{std::move(key), ParamType::Integer, {}, range, {}, std::move(unit), std::move(doc)};
    add(std::move(s),
        [access, range](Config& c, const ParamSetting& v) {
          const long long x = parse_param_integer(v, range.lo >= 0);
          param_check_range(v, range, static_cast<double>(x));
          ref(c, access) = static_cast<std::remove_reference_t<decltype(ref(c, access))>>(x);
        },
        [access](const Config& c) { return std::to_string(cref(c, access)); });
    return *this;
  }

  template <class Access>
  ParamTable& boolean(std::string key, Access access, std::string doc) {
    ParamSpec s{std::move(key), ParamType::Boolean, {}, {}, {}, "", std::move(doc)};
    add(std::move(s), [access](Config& c, const ParamSetting& v) { ref(c, access) = parse_param_boolean(v); },
        [access](const Config& c) { return std::string(cref(c, access) ? "true" : "false"); });
    return *this;
  }

  // A name among `choices`, stored by `set` and read back by `get` (enums or strings). With
  // `strict` false the choices are only documented and `set` judges the name (component names,
  // whose deprecated aliases the registry still accepts).
  ParamTable& choice(std::string key, std::vector<std::string> choices, std::function<void(Config&, const std::string&)> set,
                     std::function<std::string(const Config&)> get, std::string doc, bool strict = true) {
    ParamSpec s{std::move(key), ParamType::Choice, {}, {}, choices, "", std::move(doc)};
    add(std::move(s),
        [choices, set, strict](Config& c, const ParamSetting& v) {
          if (strict) param_check_choice(v, choices);
          set(c, v.value);
        },
        std::move(get));
    return *this;
  }

  // An ordered list of names, each among `choices` (component names: with `strict` false the
  // choices are only documented and `set` judges each name).
  ParamTable& name_list(std::string key, std::vector<std::string> choices,
                        std::function<void(Config&, const std::vector<std::string>&)> set,
                        std::function<std::vector<std::string>(const Config&)> get, std::string doc, bool strict = true) {
    ParamSpec s{std::move(key), ParamType::NameList, {}, {}, choices, "", std::move(doc)};
    add(std::move(s),
        [choices, set, strict](Config& c, const ParamSetting& v) {
          const std::vector<std::string> names = parse_param_name_list(v);
          if (strict)
            for (const std::string& n : names) param_check_choice({v.key, n, v.file, v.line, v.field}, choices);
          set(c, names);
        },
        [get](const Config& c) { return format_param_name_list(get(c)); });
    return *this;
  }

  // Free text (a name, a path), stored as written.
  template <class Access>
  ParamTable& text(std::string key, Access access, std::string doc) {
    ParamSpec s{std::move(key), ParamType::Text, {}, {}, {}, "", std::move(doc)};
    add(std::move(s), [access](Config& c, const ParamSetting& v) { ref(c, access) = v.value; },
        [access](const Config& c) { return std::string(cref(c, access)); });
    return *this;
  }

  // Polygons in the map frame (see parse_param_polygons), in `unit`.
  template <class Access>
  ParamTable& polygons(std::string key, Access access, std::string unit, std::string doc) {
    ParamSpec s{std::move(key), ParamType::Polygons, {}, {}, {}, std::move(unit), std::move(doc)};
    add(std::move(s), [access](Config& c, const ParamSetting& v) { ref(c, access) = parse_param_polygons(v); },
        [access](const Config& c) { return format_param_polygons(cref(c, access)); });
    return *this;
  }

  // A list of numbers (see parse_param_reals), each within `range` (an Error names the setting
  // and the number's position), in `unit`; stored times `scale`.
  template <class Access>
  ParamTable& reals(std::string key, Access access, ParamRange range, std::string unit, std::string doc, double scale = 1.0) {
    ParamSpec s{std::move(key), ParamType::Reals, {}, range, {}, std::move(unit), std::move(doc)};
    add(std::move(s),
        [access, range, scale](Config& c, const ParamSetting& v) {
          std::vector<double> values = parse_param_reals(v);
          for (std::size_t i = 0; i < values.size(); ++i) {
            param_check_list_range(v, i, range, values[i]);
            values[i] *= scale;
          }
          ref(c, access) = std::move(values);
        },
        [access, scale](const Config& c) {
          std::vector<double> values = cref(c, access);
          for (double& x : values) x /= scale;
          return format_param_reals(values);
        });
    return *this;
  }

  // A parameter whose value the caller parses and checks itself (`set` throws Error naming the
  // setting, as parse_param_real does), for a rule no range states: "a whole number >= 0", a
  // list of numbers, a check against another setting. `spec.default_value` is read back by `get`.
  ParamTable& custom(ParamSpec spec, std::function<void(Config&, const ParamSetting&)> set,
                     std::function<std::string(const Config&)> get) {
    add(std::move(spec), std::move(set), std::move(get));
    return *this;
  }

  // Every parameter of `sub` under `prefix.` (or under its own key when `prefix` is empty),
  // bound to the nested configuration `access` gives.
  template <class Sub, class Access>
  ParamTable& nest(const std::string& prefix, const ParamTable<Sub>& sub, Access access) {
    const std::size_t strip = prefix.empty() ? 0 : prefix.size() + 1;
    for (const auto& e : sub.entries_) {
      ParamSpec s = e.spec;
      if (!prefix.empty()) s.key = prefix + "." + s.key;
      add(std::move(s),
          [set = e.set, access, strip](Config& c, const ParamSetting& v) {
            ParamSetting inner = v;
            inner.key = v.key.substr(strip);
            set(ref(c, access), inner);
          },
          [get = e.get, access](const Config& c) { return get(cref(c, access)); });
      entries_.back().rule = e.rule;
    }
    return *this;
  }

  // Replaces the default shown in docs when it comes from elsewhere (e.g. "robot.max_step_m").
  ParamTable& default_rule(const std::string& key, std::string rule) {
    for (Entry& e : entries_)
      if (e.spec.key == key) e.rule = std::move(rule);
    return *this;
  }

  // The declarations with the defaults of `defaults` filled in.
  std::vector<ParamSpec> specs(const Config& defaults = Config{}) const {
    std::vector<ParamSpec> out;
    for (const Entry& e : entries_) {
      ParamSpec s = e.spec;
      s.default_value = e.rule.empty() ? e.get(defaults) : e.rule;
      out.push_back(std::move(s));
    }
    return out;
  }
  bool has(const std::string& key) const {
    for (const Entry& e : entries_)
      if (e.spec.key == key) return true;
    return false;
  }

  // Applies one setting; an unknown key is an Error listing the known ones.
  void apply(Config& c, const ParamSetting& v) const {
    for (const Entry& e : entries_)
      if (e.spec.key == v.key) return e.set(c, v);
    param_unknown_key(v, keys());
  }
  void apply(Config& c, std::span<const ParamSetting> settings) const {
    for (const ParamSetting& v : settings) apply(c, v);
  }
  std::vector<std::string> keys() const {
    std::vector<std::string> k;
    for (const Entry& e : entries_) k.push_back(e.spec.key);
    return k;
  }

 private:
  struct Entry {
    ParamSpec spec;
    std::function<void(Config&, const ParamSetting&)> set;
    std::function<std::string(const Config&)> get;
    std::string rule;
  };
  void add(ParamSpec s, std::function<void(Config&, const ParamSetting&)> set, std::function<std::string(const Config&)> get) {
    entries_.push_back({std::move(s), std::move(set), std::move(get), {}});
  }
  // Members by pointer, nested members by a lambda returning a reference.
  template <class Access>
  static auto& ref(Config& c, Access a) {
    if constexpr (std::is_member_object_pointer_v<Access>) return c.*a;
    else return a(c);
  }
  template <class Access>
  static auto cref(const Config& c, Access a) {
    Config copy = c;
    return ref(copy, a);
  }

  std::vector<Entry> entries_;

  template <class>
  friend class ParamTable;
};


// Re-attributes an Error from a configuration's validate() (whose field is "key" or ends in
// ".key") to the setting that gave that key, so the message names the file, line and full key.
// Without such a setting, the error keeps its field and gets `file` (the scenario) when it had none.
[[noreturn]] void rethrow_at_setting(const Error& e, std::span<const ParamSetting> settings, const std::string& file = {});

// `defaults` with `settings` applied by `table`; an error names the setting that caused it (a
// component's factory starts with this).
template <class Config>
Config configured(const ParamTable<Config>& table, std::span<const ParamSetting> settings, const std::string& file,
                  Config defaults = Config{}) {
  try {
    table.apply(defaults, settings);
  } catch (const Error& e) {
    rethrow_at_setting(e, settings, file);
  }
  return defaults;
}

// A Markdown table of `specs` (key prefixed by `section.` when given): key | type | default |
// range | unit | meaning.
std::string params_markdown_table(const std::vector<ParamSpec>& specs, const std::string& section);

}  // namespace starnav
