#include "starnav/sweep/sweep_file.hpp"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <set>

#include <yaml-cpp/yaml.h>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/io/yaml_document.hpp"

namespace starnav::sweep {

namespace fs = std::filesystem;

namespace {

// Names the table uses for its own columns; no axis or metric may take them.
const std::set<std::string> kReservedNames = {"id", "status", "exit_code", "wall_s", "cpu_s", "out", "reason"};

int line_of(const YAML::Node& node) { return node.Mark().is_null() ? 0 : node.Mark().line + 1; }

bool is_name(std::string_view s, bool dots) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || (dots && c == '.'))) return false;
  return s.back() != '.' && s.find("..") == std::string_view::npos;
}

// Built by append: g++ 12 warns falsely (-Wrestrict) on a literal + string here.
std::string quote_text(std::string_view s) {
  std::string out = "'";
  out.append(printable(s, 80)).append("'");
  return out;
}

// The reader of one sweep file: every key of every mapping checked against the keys it may have.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    throw Error(what, source_, line_of(node), key);
  }

  void check_keys(const YAML::Node& map, const std::string& prefix, std::initializer_list<const char*> known) const {
    for (auto it = map.begin(); it != map.end(); ++it) {
      const std::string key = it->first.IsScalar() ? it->first.Scalar() : std::string();
      if (std::none_of(known.begin(), known.end(), [&](const char* k) { return key == k; })) {
        std::string list;
        for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        fail(it->first, prefix.empty() ? printable(key, 60) : prefix + "." + printable(key, 60),
             "unknown key (known: " + list + ")");
      }
    }
  }

  std::string scalar(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "expected a single value (text or number)");
    const std::string& s = node.Scalar();
    if (s.find('\0') != std::string::npos) fail(node, key, "holds a NUL character");
    return s;
  }

  std::string name(const YAML::Node& node, const std::string& key, bool dots) const {
    const std::string s = scalar(node, key);
    if (!is_name(s, dots))
      fail(node, key,
           "expected a name of letters, digits and _" + std::string(dots ? " (dotted keys allowed)" : "") + ", got " + quote_text(s));
    return s;
  }

  bool boolean(const YAML::Node& node, const std::string& key) const {
    const std::string s = scalar(node, key);
    if (s == "true") return true;
    if (s == "false") return false;
    fail(node, key, "expected true or false, got " + quote_text(s));
  }

  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

// ---- decimal ranges -----------------------------------------------------------------------------

// A number written in decimal, as an exact integer in units of 10^-decimals.
struct Decimal {
  std::int64_t scaled = 0;
  int decimals = 0;
  bool integer = true;  // written without a point or exponent
};

constexpr int kMaxDecimals = 12;
constexpr std::int64_t kMaxScaled = std::int64_t{1} << 62;

std::optional<Decimal> parse_decimal(const std::string& text) {
  if (!parse_real_text(text)) return std::nullopt;
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) negative = text[i++] == '-';
  std::string digits;
  int decimals = 0;
  bool seen_point = false, integer = true;
  for (; i < text.size() && (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.'); ++i) {
    if (text[i] == '.') {
      seen_point = true;
      integer = false;
      continue;
    }
    digits += text[i];
    if (seen_point) ++decimals;
  }
  long long exponent = 0;
  if (i < text.size()) {  // e or E
    integer = false;
    const std::optional<std::int64_t> e = parse_integer_text(std::string_view(text).substr(i + 1));
    if (!e || *e < -100 || *e > 100) return std::nullopt;
    exponent = *e;
  }
  long long d = decimals - exponent;
  // Trailing zeros after the point carry no value: 0.50 is 0.5.
  while (d > 0 && digits.size() > 1 && digits.back() == '0' && decimals > 0) {
    digits.pop_back();
    --d;
    --decimals;
  }
  while (d < 0) {
    digits += '0';
    ++d;
  }
  if (d > kMaxDecimals) return std::nullopt;
  std::int64_t v = 0;
  for (char c : digits) {
    if (v > (kMaxScaled - (c - '0')) / 10) return std::nullopt;  // |value| <= 2^62
    v = v * 10 + (c - '0');
  }
  return Decimal{negative ? -v : v, static_cast<int>(d), integer};
}

std::int64_t rescale(std::int64_t v, int from_decimals, int to_decimals, bool& overflow) {
  for (int k = from_decimals; k < to_decimals; ++k) {
    if (v > kMaxScaled / 10 || v < -kMaxScaled / 10) {
      overflow = true;
      return 0;
    }
    v *= 10;
  }
  return v;
}

std::string decimal_text(std::int64_t scaled, int decimals) {
  const bool negative = scaled < 0;
  std::string digits = std::to_string(negative ? -scaled : scaled);
  if (decimals > 0) {
    if (digits.size() <= static_cast<std::size_t>(decimals)) digits.insert(0, static_cast<std::size_t>(decimals) + 1 - digits.size(), '0');
    digits.insert(digits.size() - static_cast<std::size_t>(decimals), ".");
    while (digits.back() == '0') digits.pop_back();
    if (digits.back() == '.') digits.pop_back();
  }
  return (negative ? "-" : "") + digits;
}

void read_range(const Reader& r, const YAML::Node& node, const std::string& key, SweepAxis& axis) {
  r.check_keys(node, key, {"from", "to", "count", "step"});
  if (!node["from"]) r.fail(node, key + ".from", "missing (a range needs from, and to or count)");
  if (static_cast<bool>(node["to"]) == static_cast<bool>(node["count"]))
    r.fail(node, key, "give exactly one of to and count");
  const auto number = [&](const char* k) {
    const YAML::Node n = node[k];
    const std::string text = r.scalar(n, key + "." + k);
    const std::optional<Decimal> d = parse_decimal(text);
    if (!d) r.fail(n, key + "." + k, "expected a decimal number below 2^62 with at most 12 decimals, got " + quote_text(text));
    return *d;
  };
  const Decimal from = number("from");
  const Decimal step = node["step"] ? number("step") : Decimal{1, 0, true};
  if (step.scaled <= 0) r.fail(node["step"], key + ".step", "must be > 0");
  int decimals = std::max(from.decimals, step.decimals);
  std::optional<Decimal> to;
  if (node["to"]) {
    to = number("to");
    decimals = std::max(decimals, to->decimals);
  }
  bool overflow = false;
  axis.range_from = rescale(from.scaled, from.decimals, decimals, overflow);
  axis.range_step = rescale(step.scaled, step.decimals, decimals, overflow);
  if (overflow) r.fail(node, key, "numbers too large for a range");
  axis.range_decimals = decimals;
  if (to) {
    const std::int64_t t = rescale(to->scaled, to->decimals, decimals, overflow);
    if (overflow) r.fail(node, key, "numbers too large for a range");
    if (t < axis.range_from) r.fail(node["to"], key + ".to", "must be >= from");
    // Both within +-2^62: the difference fits in 64 unsigned bits.
    const std::uint64_t count = (static_cast<std::uint64_t>(t) - static_cast<std::uint64_t>(axis.range_from)) /
                                    static_cast<std::uint64_t>(axis.range_step) + 1;
    if (count > kMaxSweepTasks) r.fail(node, key, "more than " + std::to_string(kMaxSweepTasks) + " values");
    axis.range_count = count;
  } else {
    const YAML::Node n = node["count"];
    const std::optional<std::uint64_t> c = parse_unsigned_text(r.scalar(n, key + ".count"));
    if (!c || *c == 0) r.fail(n, key + ".count", "expected a whole number >= 1, got " + quote_text(n.Scalar()));
    if (*c > kMaxSweepTasks) r.fail(n, key + ".count", "more than " + std::to_string(kMaxSweepTasks) + " values");
    axis.range_count = *c;
  }
  // The last value must stay representable.
  const std::uint64_t steps = axis.range_count - 1;
  if (steps > 0 && steps > (static_cast<std::uint64_t>(kMaxScaled) - static_cast<std::uint64_t>(axis.range_from)) /
                               static_cast<std::uint64_t>(axis.range_step))
    r.fail(node, key, "numbers too large for a range");
}

// ---- axes ---------------------------------------------------------------------------------------

SweepAxis read_axis(const Reader& r, const std::string& name, const YAML::Node& node, int name_line) {
  SweepAxis axis;
  axis.name = name;
  axis.line = name_line;
  const std::string key = "axes." + name;
  if (node.IsSequence()) {
    if (node.size() == 0) r.fail(node, key, "an empty list: give at least one value");
    axis.kind = SweepAxis::Kind::List;
    if (node[0].IsMap()) {
      // Zipped: a list of mappings with the same keys, each a row of fields.
      for (auto it = node[0].begin(); it != node[0].end(); ++it)
        axis.fields.push_back(r.name(it->first, key + "[0]", false));
      if (axis.fields.empty()) r.fail(node[0], key + "[0]", "an empty mapping: give the fields of the first entry");
    }
    std::set<std::string> seen;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const YAML::Node item = node[i];
      const std::string item_key = key + "[" + std::to_string(i) + "]";
      std::string row_key;
      if (axis.fields.empty()) {
        if (item.IsMap()) r.fail(item, item_key, "a mapping in a list of values (every entry a mapping, or none)");
        const std::string v = r.scalar(item, item_key);
        axis.texts.push_back(v);
        row_key = v;
      } else {
        if (!item.IsMap()) r.fail(item, item_key, "expected a mapping with the fields of the first entry");
        if (item.size() != axis.fields.size())
          r.fail(item, item_key, "expected the fields of the first entry (" + std::to_string(axis.fields.size()) + "), got " +
                                      std::to_string(item.size()));
        for (const std::string& f : axis.fields) {
          const YAML::Node v = item[f];
          if (!v) r.fail(item, item_key + "." + f, "missing (every entry has the fields of the first)");
          const std::string text = r.scalar(v, item_key + "." + f);
          axis.texts.push_back(text);
          row_key += text;
          row_key += '\0';
        }
      }
      if (!seen.insert(row_key).second) r.fail(item, item_key, "the same value twice (two tasks would be the same)");
    }
  } else if (node.IsMap()) {
    if (node["glob"]) {
      r.check_keys(node, key, {"glob"});
      axis.kind = SweepAxis::Kind::Glob;
      const YAML::Node g = node["glob"];
      std::vector<YAML::Node> items;
      if (g.IsSequence()) {
        if (g.size() == 0) r.fail(g, key + ".glob", "an empty list of patterns");
        for (std::size_t i = 0; i < g.size(); ++i) items.push_back(g[i]);
      } else {
        items.push_back(g);
      }
      for (const YAML::Node& p : items) {
        const std::string pattern = r.scalar(p, key + ".glob");
        if (pattern.empty()) r.fail(p, key + ".glob", "an empty pattern");
        axis.patterns.push_back(pattern);
      }
    } else {
      axis.kind = SweepAxis::Kind::Range;
      read_range(r, node, key, axis);
    }
  } else {
    r.fail(node, key, "expected a list of values, a range {from, to|count, step} or {glob: PATTERN}");
  }
  return axis;
}

// ---- templates ----------------------------------------------------------------------------------

TemplateArg parse_template(const Reader& r, const YAML::Node& node, const std::string& key,
                           const std::vector<SweepAxis>& axes, bool allow_out) {
  TemplateArg arg;
  arg.line = line_of(node);
  const std::string text = r.scalar(node, key);
  std::string literal;
  const auto flush = [&] {
    if (!literal.empty()) arg.parts.push_back({TemplatePart::Kind::Text, literal, 0, 0});
    literal.clear();
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '}') {
      if (i + 1 < text.size() && text[i + 1] == '}') {
        literal += '}';
        ++i;
        continue;
      }
      r.fail(node, key, "a lone '}' in " + quote_text(text) + " (write }} for a literal brace)");
    }
    if (c != '{') {
      literal += c;
      continue;
    }
    if (i + 1 < text.size() && text[i + 1] == '{') {
      literal += '{';
      ++i;
      continue;
    }
    const std::size_t close = text.find('}', i + 1);
    if (close == std::string::npos) r.fail(node, key, "an unclosed '{' in " + quote_text(text) + " (write {{ for a literal brace)");
    const std::string ref = text.substr(i + 1, close - i - 1);
    i = close;
    flush();
    if (ref == "out") {
      if (!allow_out) r.fail(node, key, "{out} is not known here");
      arg.parts.push_back({TemplatePart::Kind::Out, {}, 0, 0});
      continue;
    }
    // The longest axis name that the reference starts with: "query.start" is field start of
    // axis query, "navigation.planner" the dotted axis itself.
    bool found = false;
    for (std::size_t a = 0; a < axes.size() && !found; ++a) {
      const SweepAxis& ax = axes[a];
      if (ref == ax.name) {
        if (!ax.fields.empty())
          r.fail(node, key, "{" + printable(ref, 60) + "} names a zipped axis: name one of its fields ({" + ax.name + "." +
                                ax.fields[0] + "}, ...)");
        arg.parts.push_back({TemplatePart::Kind::Axis, {}, a, 0});
        found = true;
      } else if (!ax.fields.empty() && ref.size() > ax.name.size() + 1 && ref.compare(0, ax.name.size(), ax.name) == 0 &&
                 ref[ax.name.size()] == '.') {
        const std::string field = ref.substr(ax.name.size() + 1);
        const auto f = std::find(ax.fields.begin(), ax.fields.end(), field);
        if (f == ax.fields.end()) r.fail(node, key, "axis " + ax.name + " has no field " + quote_text(field));
        arg.parts.push_back({TemplatePart::Kind::Axis, {}, a, static_cast<std::size_t>(f - ax.fields.begin())});
        found = true;
      }
    }
    if (!found) {
      std::string names;
      for (const SweepAxis& ax : axes) names += (names.empty() ? "" : ", ") + ax.name;
      r.fail(node, key, "{" + printable(ref, 60) + "} is not an axis (axes: " + names + (allow_out ? "; and {out}" : "") + ")");
    }
  }
  flush();
  return arg;
}

bool valid_json_pointer(const std::string& p) {
  if (p.empty()) return true;
  if (p[0] != '/') return false;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p[i] == '~' && (i + 1 >= p.size() || (p[i + 1] != '0' && p[i + 1] != '1'))) return false;
  return true;
}

std::vector<std::string> read_name_list(const Reader& r, const YAML::Node& node, const std::string& key) {
  std::vector<std::string> out;
  if (node.IsScalar()) {
    out.push_back(r.name(node, key, true));
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string n = r.name(node[i], key + "[" + std::to_string(i) + "]", true);
      if (std::find(out.begin(), out.end(), n) != out.end()) r.fail(node[i], key, quote_text(n) + " given twice");
      out.push_back(n);
    }
  } else {
    r.fail(node, key, "expected a list of axis names");
  }
  return out;
}

}  // namespace

// ---- SweepAxis ----------------------------------------------------------------------------------

std::uint64_t SweepAxis::size() const {
  if (kind == Kind::Range) return range_count;
  return texts.size() / width();
}

std::string SweepAxis::value(std::uint64_t index, std::size_t field) const {
  if (kind == Kind::Range) {
    // In unsigned arithmetic (the sum is within +-2^62, the product alone need not be).
    const std::uint64_t v = static_cast<std::uint64_t>(range_from) + static_cast<std::uint64_t>(range_step) * index;
    return decimal_text(static_cast<std::int64_t>(v), range_decimals);
  }
  return texts.at(static_cast<std::size_t>(index) * width() + field);
}

std::vector<std::string> SweepAxis::columns() const {
  if (fields.empty()) return {name};
  std::vector<std::string> out;
  for (const std::string& f : fields) out.push_back(name + "." + f);
  return out;
}

void SweepAxis::take(std::uint64_t count) {
  if (count == 0) throw Error("must keep at least one value", {}, 0, name);
  if (count >= size()) return;
  if (kind == Kind::Range) {
    range_count = count;
  } else {
    texts.resize(static_cast<std::size_t>(count) * width());
  }
}

std::string SweepPlot::file_name() const {
  return metric + "-vs-" + x + (series.empty() ? "" : "-by-" + series) + ".svg";
}

std::vector<std::string> SweepSpec::axis_columns() const {
  std::vector<std::string> out;
  for (const SweepAxis& a : axes)
    for (std::string& c : a.columns()) out.push_back(std::move(c));
  return out;
}

std::optional<std::size_t> SweepSpec::axis_index(const std::string& n) const {
  for (std::size_t i = 0; i < axes.size(); ++i)
    if (axes[i].name == n) return i;
  return std::nullopt;
}

std::uint64_t SweepSpec::task_count() const {
  std::uint64_t n = 1;
  for (const SweepAxis& a : axes) {
    const std::uint64_t s = a.size();
    if (s == 0) return 0;
    if (n > kMaxSweepTasks / s)
      throw Error("the axes make more than " + std::to_string(kMaxSweepTasks) + " tasks", source, axes_line, "axes");
    n *= s;
  }
  return n;
}

// ---- the file -----------------------------------------------------------------------------------

namespace {

SweepSpec parse_sweep_yaml(std::string_view text, const std::string& source, const std::string& default_name) {
  const Reader r(source);
  const YAML::Node root = load_yaml_document(text, source);
  if (!root.IsMap()) throw Error("expected a mapping of keys (command, result, axes, metrics, ...)", source, line_of(root));
  r.check_keys(root, "",
               {"name", "command", "result", "result_exit_codes", "timeout_s", "keep_outputs", "axes", "metrics", "summary",
                "plots"});
  SweepSpec spec;
  spec.source = source;
  spec.name = default_name;
  if (const YAML::Node n = root["name"]) {
    spec.name = r.scalar(n, "name");
    if (spec.name.empty() || spec.name.size() > 100 ||
        !std::all_of(spec.name.begin(), spec.name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; }))
      r.fail(n, "name", "expected up to 100 letters, digits, '-', '_' or '.', got " + quote_text(spec.name));
  }

  // Axes first: the command's placeholders name them.
  const YAML::Node axes = root["axes"];
  if (!axes) throw Error("missing: the axes of the sweep (seeds, parameters, maps, ...)", source, 0, "axes");
  for (auto it = root.begin(); it != root.end(); ++it)
    if (it->first.IsScalar() && it->first.Scalar() == "axes") spec.axes_line = line_of(it->first);
  if (!axes.IsMap() || axes.size() == 0) r.fail(axes, "axes", "expected a mapping of axis names to their values");
  for (auto it = axes.begin(); it != axes.end(); ++it) {
    const std::string name = r.name(it->first, "axes", true);
    if (kReservedNames.count(name)) r.fail(it->first, "axes." + name, "is a column of the table; choose another name");
    for (const SweepAxis& other : spec.axes)
      for (const std::string& c : other.columns())
        if (c == name || name.rfind(c + ".", 0) == 0 || c.rfind(name + ".", 0) == 0)
          r.fail(it->first, "axes." + name, "clashes with the column " + c + " of axis " + other.name);
    spec.axes.push_back(read_axis(r, name, it->second, line_of(it->first)));
    for (const std::string& c : spec.axes.back().columns())
      if (kReservedNames.count(c)) r.fail(it->first, "axes." + name, "makes the column " + c + ", a column of the table");
  }
  spec.task_count();

  const YAML::Node command = root["command"];
  if (!command) throw Error("missing: the starnav command each task runs, as a list [SUBCOMMAND, ARG, ...]", source, 0, "command");
  spec.command_line = line_of(command);
  if (!command.IsSequence() || command.size() == 0)
    r.fail(command, "command", "expected a list: the starnav subcommand and its arguments, [plan, --map, ...]");
  std::vector<bool> used(spec.axes.size(), false);
  for (std::size_t i = 0; i < command.size(); ++i) {
    const std::string key = "command[" + std::to_string(i) + "]";
    spec.command.push_back(parse_template(r, command[i], key, spec.axes, true));
    for (const TemplatePart& p : spec.command.back().parts)
      if (p.kind == TemplatePart::Kind::Axis) used[p.axis] = true;
  }
  {
    const TemplateArg& first = spec.command.front();
    if (first.parts.size() != 1 || first.parts[0].kind != TemplatePart::Kind::Text)
      r.fail(command[0], "command[0]", "expected the starnav subcommand (plan, sim, bench, ...), without placeholders");
    if (first.parts[0].text == "starnav")
      r.fail(command[0], "command[0]", "give the subcommand and its arguments without 'starnav' ([plan, --map, ...])");
  }
  for (std::size_t a = 0; a < spec.axes.size(); ++a) {
    SweepAxis& ax = spec.axes[a];
    if (used[a]) continue;
    if (ax.name.find('.') != std::string::npos && ax.fields.empty()) {
      ax.as_set_option = true;
      continue;
    }
    throw Error("the command never uses this axis: name it as {" + ax.name + (ax.fields.empty() ? "" : "." + ax.fields[0]) +
                    "} in an argument" + (ax.fields.empty() ? " (or give a dotted parameter key, passed as --set KEY=VALUE)" : ""),
                source, ax.line, "axes." + ax.name);
  }

  if (const YAML::Node n = root["result"]) {
    spec.result = r.scalar(n, "result");
    const fs::path p(spec.result);
    if (spec.result.empty()) r.fail(n, "result", "expected stdout or a file in the task's output folder {out}");
    if (spec.result != "stdout") {
      if (p.is_absolute()) r.fail(n, "result", "expected a file in the task's output folder, relative to {out}, got " + quote_text(spec.result));
      for (const fs::path& part : p)
        if (part == "..") r.fail(n, "result", "must stay inside the task's output folder (no '..'), got " + quote_text(spec.result));
      if (spec.result.find('{') != std::string::npos)
        r.fail(n, "result", "a path relative to the task's output folder, without placeholders, got " + quote_text(spec.result));
    }
  }
  if (const YAML::Node n = root["result_exit_codes"]) {
    if (!n.IsSequence() || n.size() == 0) r.fail(n, "result_exit_codes", "expected a list of exit codes, e.g. [0, 1]");
    spec.result_exit_codes.clear();
    for (std::size_t i = 0; i < n.size(); ++i) {
      const std::string t = r.scalar(n[i], "result_exit_codes");
      const std::optional<std::uint64_t> v = parse_unsigned_text(t);
      if (!v || *v > 255) r.fail(n[i], "result_exit_codes", "expected an exit code 0..255, got " + quote_text(t));
      if (std::find(spec.result_exit_codes.begin(), spec.result_exit_codes.end(), static_cast<int>(*v)) != spec.result_exit_codes.end())
        r.fail(n[i], "result_exit_codes", t + " given twice");
      spec.result_exit_codes.push_back(static_cast<int>(*v));
    }
  }
  if (const YAML::Node n = root["timeout_s"]) {
    const std::string t = r.scalar(n, "timeout_s");
    const std::optional<double> v = parse_real_text(t);
    if (!v || *v < 0 || *v > 1e7) r.fail(n, "timeout_s", "expected seconds >= 0 (0: no limit), got " + quote_text(t));
    spec.timeout_s = *v;
  }
  if (const YAML::Node n = root["keep_outputs"]) spec.keep_outputs = r.boolean(n, "keep_outputs");

  const std::vector<std::string> columns = spec.axis_columns();
  const auto is_metric = [&](const std::string& m) {
    return m == "wall_s" || m == "cpu_s" ||
           std::any_of(spec.metrics.begin(), spec.metrics.end(), [&](const SweepMetric& x) { return x.name == m; });
  };
  if (const YAML::Node n = root["metrics"]) {
    if (!n.IsMap()) r.fail(n, "metrics", "expected a mapping of metric names to JSON pointers into the result (cost: /cost)");
    for (auto it = n.begin(); it != n.end(); ++it) {
      SweepMetric m;
      m.name = r.name(it->first, "metrics", true);
      m.line = line_of(it->first);
      const std::string key = "metrics." + m.name;
      if (kReservedNames.count(m.name)) r.fail(it->first, key, "is a column of the table; choose another name");
      if (std::find(columns.begin(), columns.end(), m.name) != columns.end()) r.fail(it->first, key, "is an axis column");
      const YAML::Node v = it->second;
      if (v.IsMap()) {
        r.check_keys(v, key, {"pointer", "when", "timing"});
        if (!v["pointer"]) r.fail(v, key + ".pointer", "missing: the JSON pointer into the result");
        if (const YAML::Node t = v["timing"]) m.timing = r.boolean(t, key + ".timing");
        if (const YAML::Node w = v["when"]) {
          m.when = r.scalar(w, key + ".when");
          if (m.when.empty() || !valid_json_pointer(m.when))
            r.fail(w, key + ".when", "expected a JSON pointer to a true/false value in the result, got " + quote_text(m.when));
        }
      }
      const YAML::Node pointer = v.IsMap() ? v["pointer"] : v;
      m.pointer = r.scalar(pointer, key);
      if (!valid_json_pointer(m.pointer))
        r.fail(pointer, key, "expected a JSON pointer (RFC 6901: /key/0/..., ~0 for ~ and ~1 for /), got " + quote_text(m.pointer));
      spec.metrics.push_back(std::move(m));
    }
  }

  if (const YAML::Node n = root["summary"]) {
    if (!n.IsMap()) r.fail(n, "summary", "expected a mapping {group_by, success, baseline}");
    r.check_keys(n, "summary", {"group_by", "success", "baseline"});
    if (const YAML::Node g = n["group_by"]) {
      spec.summary.group_by = read_name_list(r, g, "summary.group_by");
      for (const std::string& name : spec.summary.group_by)
        if (!spec.axis_index(name)) r.fail(g, "summary.group_by", quote_text(name) + " is not an axis");
    }
    if (const YAML::Node s = n["success"]) {
      spec.summary.success = r.name(s, "summary.success", true);
      if (!is_metric(spec.summary.success) || spec.summary.success == "wall_s" || spec.summary.success == "cpu_s")
        r.fail(s, "summary.success", quote_text(spec.summary.success) + " is not one of the metrics");
    }
    if (const YAML::Node b = n["baseline"]) {
      spec.summary.baseline = r.scalar(b, "summary.baseline");
      spec.summary.baseline_line = line_of(b);
      if (spec.summary.group_by.empty()) r.fail(b, "summary.baseline", "a baseline needs groups (summary.group_by)");
    }
  }

  if (const YAML::Node n = root["plots"]) {
    if (!n.IsSequence()) r.fail(n, "plots", "expected a list of plots [{metric, x, series, error}]");
    std::set<std::string> files;
    for (std::size_t i = 0; i < n.size(); ++i) {
      const YAML::Node p = n[i];
      const std::string key = "plots[" + std::to_string(i) + "]";
      if (!p.IsMap()) r.fail(p, key, "expected a mapping {metric, x, series, error}");
      r.check_keys(p, key, {"metric", "x", "series", "error"});
      SweepPlot plot;
      plot.line = line_of(p);
      if (!p["metric"]) r.fail(p, key + ".metric", "missing: the metric on the y axis");
      if (!p["x"]) r.fail(p, key + ".x", "missing: the axis on the x axis");
      plot.metric = r.name(p["metric"], key + ".metric", true);
      if (!is_metric(plot.metric)) r.fail(p["metric"], key + ".metric", quote_text(plot.metric) + " is not one of the metrics (nor wall_s, cpu_s)");
      plot.x = r.name(p["x"], key + ".x", true);
      const std::optional<std::size_t> xa = spec.axis_index(plot.x);
      if (!xa) r.fail(p["x"], key + ".x", quote_text(plot.x) + " is not an axis");
      if (!spec.axes[*xa].fields.empty()) r.fail(p["x"], key + ".x", "a zipped axis has no numeric values to plot against");
      if (spec.axes[*xa].kind == SweepAxis::Kind::Glob) r.fail(p["x"], key + ".x", "a glob axis has file names, not numbers");
      if (const YAML::Node s = p["series"]) {
        plot.series = r.name(s, key + ".series", true);
        if (!spec.axis_index(plot.series)) r.fail(s, key + ".series", quote_text(plot.series) + " is not an axis");
        if (plot.series == plot.x) r.fail(s, key + ".series", "is the x axis too");
      }
      if (const YAML::Node e = p["error"]) {
        const std::string t = r.scalar(e, key + ".error");
        if (t == "iqr") plot.error = ErrorBars::Iqr;
        else if (t == "sd") plot.error = ErrorBars::Sd;
        else if (t == "none") plot.error = ErrorBars::None;
        else r.fail(e, key + ".error", "expected iqr (median and quartiles), sd (mean and standard deviation) or none, got " + quote_text(t));
      }
      if (!files.insert(plot.file_name()).second) r.fail(p, key, "the same plot twice");
      spec.plots.push_back(std::move(plot));
    }
  }
  return spec;
}

}  // namespace

SweepSpec parse_sweep_file(std::string_view text, const std::string& source, const std::string& default_name) {
  try {
    return parse_sweep_yaml(text, source, default_name);
  } catch (const YAML::Exception& e) {
    // The checks above should leave yaml-cpp nothing to throw; if it does, still one line.
    throw Error("unexpected YAML structure: " + one_line(e.msg, 120), source, e.mark.is_null() ? 0 : e.mark.line + 1);
  }
}

SweepSpec read_sweep_file(const std::string& path) {
  const std::string text = read_input_file(path, std::uint64_t{1} << 24);
  SweepSpec spec = parse_sweep_file(text, path, fs::path(path).stem().string());
  resolve_globs(spec, fs::absolute(path).parent_path().string());
  return spec;
}

void resolve_globs(SweepSpec& spec, const std::string& base_dir) {
  for (SweepAxis& axis : spec.axes) {
    if (axis.kind != SweepAxis::Kind::Glob) continue;
    std::vector<std::string> paths;
    for (const std::string& pattern : axis.patterns) {
      const bool absolute = fs::path(pattern).is_absolute();
      std::string prefix = absolute ? std::string() : base_dir;
      if (!prefix.empty() && prefix.back() != '/') prefix += '/';
      ::glob_t g{};
      const int rc = ::glob((prefix + pattern).c_str(), GLOB_NOSORT, nullptr, &g);
      std::vector<std::string> found;
      for (std::size_t i = 0; rc == 0 && i < g.gl_pathc; ++i) {
        std::string p = g.gl_pathv[i];
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) continue;  // folders and the like are not inputs
        found.push_back(p.substr(prefix.size()));
      }
      ::globfree(&g);
      if (found.empty())
        throw Error("the pattern " + quote_text(pattern) + " matches no file (relative to " + base_dir + ")", spec.source, axis.line,
                    "axes." + axis.name + ".glob");
      paths.insert(paths.end(), found.begin(), found.end());
    }
    // Sorted by bytes, not by the locale, so every machine expands the same order.
    std::sort(paths.begin(), paths.end());
    if (const auto dup = std::adjacent_find(paths.begin(), paths.end()); dup != paths.end())
      throw Error("two patterns match " + quote_text(*dup), spec.source, axis.line, "axes." + axis.name + ".glob");
    axis.texts = std::move(paths);
    axis.kind = SweepAxis::Kind::List;
  }
  spec.task_count();
}

void check_axis_values(const SweepSpec& spec) {
  for (std::size_t i = 0; i < spec.plots.size(); ++i) {
    const SweepPlot& p = spec.plots[i];
    const SweepAxis& ax = spec.axes[*spec.axis_index(p.x)];
    for (std::uint64_t k = 0; k < ax.size() && ax.kind != SweepAxis::Kind::Range; ++k)
      if (!parse_real_text(ax.value(k)))
        throw Error("axis " + ax.name + " has a value that is not a number (" + quote_text(ax.value(k)) + "): nothing to plot against",
                    spec.source, p.line, "plots[" + std::to_string(i) + "].x");
  }
  if (spec.summary.baseline.empty()) return;
  // The groups are the combinations of the group_by axes' values.
  std::vector<std::size_t> group_axes;
  std::uint64_t combos = 1;
  for (const std::string& g : spec.summary.group_by) {
    group_axes.push_back(*spec.axis_index(g));
    combos *= spec.axes[group_axes.back()].size();
    if (combos > 1'000'000) return;  // too many to list here; merge checks
  }
  std::vector<std::uint64_t> idx(group_axes.size(), 0);
  std::vector<std::string> labels;
  for (std::uint64_t c = 0; c < combos; ++c) {
    std::uint64_t rest = c;
    for (std::size_t k = group_axes.size(); k-- > 0;) {
      const std::uint64_t n = spec.axes[group_axes[k]].size();
      idx[k] = rest % n;
      rest /= n;
    }
    std::vector<std::string> values;
    for (const SweepAxis& ax : spec.axes)
      for (std::size_t f = 0; f < ax.width(); ++f) values.emplace_back();
    std::size_t col = 0;
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      const auto at = std::find(group_axes.begin(), group_axes.end(), a);
      for (std::size_t f = 0; f < spec.axes[a].width(); ++f, ++col)
        if (at != group_axes.end()) values[col] = spec.axes[a].value(idx[static_cast<std::size_t>(at - group_axes.begin())], f);
    }
    const std::string label = group_label(spec, values);
    if (label == spec.summary.baseline) return;
    if (labels.size() < 8) labels.push_back(label);
  }
  std::string known;
  for (const std::string& l : labels) known += (known.empty() ? "" : "; ") + l;
  throw Error("no group is called " + quote_text(spec.summary.baseline) + " (groups: " + known + (combos > labels.size() ? "; ..." : "") + ")",
              spec.source, spec.summary.baseline_line, "summary.baseline");
}

std::string group_label(const SweepSpec& spec, const std::vector<std::string>& column_values) {
  if (spec.summary.group_by.empty()) return "all";
  std::string label;
  for (const std::string& g : spec.summary.group_by) {
    std::size_t col = 0;
    const std::size_t a = *spec.axis_index(g);
    for (std::size_t k = 0; k < a; ++k) col += spec.axes[k].width();
    std::string v;
    for (std::size_t f = 0; f < spec.axes[a].width(); ++f) v += (f ? " " : "") + column_values.at(col + f);
    if (!label.empty()) label += ", ";
    label += spec.summary.group_by.size() > 1 ? g + "=" + v : v;
  }
  return label;
}

}  // namespace starnav::sweep
