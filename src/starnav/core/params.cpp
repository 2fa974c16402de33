#include "starnav/core/params.hpp"

#include <string_view>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <system_error>

#include "starnav/core/error.hpp"
#include "starnav/core/number_text.hpp"

namespace starnav {

const char* param_type_name(ParamType t) {
  switch (t) {
    case ParamType::Real: return "real";
    case ParamType::Integer: return "integer";
    case ParamType::Boolean: return "boolean";
    case ParamType::Choice: return "choice";
    case ParamType::NameList: return "names";
    case ParamType::Polygons: return "polygons";
    case ParamType::Text: return "text";
    case ParamType::Reals: return "reals";
  }
  return "unknown";
}

std::vector<std::string> parse_param_name_list(const ParamSetting& setting) {
  std::vector<std::string> out;
  std::string_view text = setting.value;
  // A list written inline on the command line: [a, b]
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') text = text.substr(1, text.size() - 2);
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t'; };
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::size_t stop = comma == std::string_view::npos ? text.size() : comma;
    std::size_t a = start, b = stop;
    while (a < b && blank(text[a])) ++a;
    while (b > a && blank(text[b - 1])) --b;
    if (a < b) {
      for (std::size_t k = a; k < b; ++k) {
        const char ch = text[k];
        if (!((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_'))
          throw Error("expected a list of names (lower_snake_case), found '" + setting.value + "'", setting.file, setting.line,
                      setting.field);
      }
      out.emplace_back(text.substr(a, b - a));
    } else if (comma != std::string_view::npos) {
      throw Error("an empty name in the list '" + setting.value + "'", setting.file, setting.line, setting.field);
    }
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

std::string format_param_name_list(const std::vector<std::string>& names) {
  std::string s = "[";
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) s += ", ";
    s += names[i];
  }
  s += ']';
  return s;
}

namespace {

// A strict reader of nested lists of numbers ("[[[0, 0], [1, 0], [1, 1]]]"): brackets, commas,
// blanks and numbers only, so a typo is an error rather than a different shape.
class NumberListText {
 public:
  explicit NumberListText(const ParamSetting& setting) : setting_(setting), text_(setting.value) {}

  void expect(char ch, const char* what) {
    skip_blanks();
    if (at_ >= text_.size() || text_[at_] != ch) fail(std::string("expected ") + what);
    ++at_;
  }
  // After an item: true for another (a comma was read), false at the closing bracket (read too).
  bool more(const char* what) {
    skip_blanks();
    if (at_ < text_.size() && text_[at_] == ',') {
      ++at_;
      return true;
    }
    expect(']', what);
    return false;
  }
  bool closes_now() {
    skip_blanks();
    if (at_ < text_.size() && text_[at_] == ']') {
      ++at_;
      return true;
    }
    return false;
  }
  double number() {
    skip_blanks();
    std::size_t end = at_;
    while (end < text_.size() && text_[end] != ',' && text_[end] != ']' && text_[end] != '[' && text_[end] != ' ' &&
           text_[end] != '\t')
      ++end;
    const std::optional<double> x = parse_real_text(std::string(text_.substr(at_, end - at_)));
    if (!x) fail("expected a finite number");
    at_ = end;
    return *x;
  }
  void finish() {
    skip_blanks();
    if (at_ != text_.size()) fail("unexpected text after the list");
  }
  [[noreturn]] void fail(const std::string& what) const {
    std::string message = what;
    message.append(" at character ").append(std::to_string(at_ + 1)).append(" of '").append(one_line(setting_.value, 60)).append("'");
    throw Error(message, setting_.file, setting_.line, setting_.field.empty() ? setting_.key : setting_.field);
  }

 private:
  void skip_blanks() {
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t')) ++at_;
  }
  const ParamSetting& setting_;
  std::string_view text_;
  std::size_t at_ = 0;
};

}  // namespace

std::vector<ParamPolygon> parse_param_polygons(const ParamSetting& setting) {
  NumberListText t(setting);
  std::vector<ParamPolygon> out;
  std::size_t vertices = 0;
  t.expect('[', "'[' opening the list of polygons");
  if (!t.closes_now()) {
    do {
      ParamPolygon polygon;
      t.expect('[', "'[' opening a polygon (a list of points [x, y])");
      do {
        if (++vertices > kMaxParamPolygonVertices)
          t.fail("more than " + std::to_string(kMaxParamPolygonVertices) + " points in all");
        t.expect('[', "'[' opening a point [x, y]");
        const double x = t.number();
        t.expect(',', "',' between x and y");
        const double y = t.number();
        t.expect(']', "']' closing a point [x, y]");
        polygon.push_back({x, y});
      } while (t.more("',' or ']' after a point"));
      if (polygon.size() < 3) t.fail("a polygon needs at least 3 points, found " + std::to_string(polygon.size()));
      out.push_back(std::move(polygon));
    } while (t.more("',' or ']' after a polygon"));
  }
  t.finish();
  return out;
}

std::string format_param_polygons(const std::vector<ParamPolygon>& polygons) {
  std::string s = "[";
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    s += i ? ", [" : "[";
    for (std::size_t k = 0; k < polygons[i].size(); ++k) {
      s += k ? ", [" : "[";
      s.append(format_param_real(polygons[i][k][0])).append(", ").append(format_param_real(polygons[i][k][1])).append("]");
    }
    s += ']';
  }
  s += ']';
  return s;
}

std::vector<double> parse_param_reals(const ParamSetting& setting) {
  std::vector<double> out;
  // A scenario's empty YAML list arrives as the empty text of an empty list of names.
  if (setting.value.find_first_not_of(" \t") == std::string::npos) return out;
  NumberListText t(setting);
  t.expect('[', "'[' opening the list of numbers");
  if (!t.closes_now()) {
    do {
      if (out.size() >= kMaxParamListNumbers) t.fail("more than " + std::to_string(kMaxParamListNumbers) + " numbers");
      out.push_back(t.number());
    } while (t.more("',' or ']' after a number"));
  }
  t.finish();
  return out;
}

std::string format_param_reals(const std::vector<double>& values) {
  std::string s = "[";
  for (std::size_t i = 0; i < values.size(); ++i) s.append(i ? ", " : "").append(format_param_real(values[i]));
  s += ']';
  return s;
}

bool ParamRange::contains(double v) const {
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string ParamRange::text() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (!has_lo && !has_hi) return "any";
  if (!has_hi) return std::string(lo_open ? "> " : ">= ") + format_param_real(lo);
  if (!has_lo) return std::string(hi_open ? "< " : "<= ") + format_param_real(hi);
  return std::string(lo_open ? "(" : "[") + format_param_real(lo) + ", " + format_param_real(hi) + (hi_open ? ")" : "]");
}

ParamRange any_value() { return {}; }
ParamRange positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
ParamRange non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
ParamRange closed(double lo, double hi) { return {lo, hi, false, false}; }
ParamRange open(double lo, double hi) { return {lo, hi, true, true}; }

std::string ParamSpec::range_text() const {
  switch (type) {
    case ParamType::Boolean: return "true | false";
    case ParamType::Choice: {
      std::string s;
      for (const auto& c : choices) s += (s.empty() ? "" : " | ") + c;
      return s;
    }
    case ParamType::NameList: {
      std::string s;
      for (const auto& c : choices) s += (s.empty() ? "" : ", ") + c;
      return "a list of: " + s;
    }
    case ParamType::Polygons: return "lists of >= 3 points [x, y]";
    case ParamType::Text: return "any";
    case ParamType::Reals: return "a list of numbers, each " + range.text();
    default: return range.text();
  }
}

namespace {

[[noreturn]] void bad_value(const ParamSetting& v, const std::string& message) {
  throw Error(message, v.file, v.line, v.field.empty() ? v.key : v.field);
}

// Built by append: g++ 12 warns falsely (-Wrestrict) on a literal + string here.
std::string quoted(const std::string& text) {
  std::string out = "'";
  out.append(one_line(text, 60)).append("'");
  return out;
}

}  // namespace

double parse_param_real(const ParamSetting& v) {
  const std::string& s = v.value;
  if (const std::optional<double> x = parse_real_text(s)) return *x;
  bad_value(v, "expected a finite number, found " + quoted(s));
}

long long parse_param_integer(const ParamSetting& v, bool count) {
  const std::string& s = v.value;
  if (count) {
    const std::optional<std::uint64_t> u = parse_unsigned_text(s);
    if (!u || *u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      bad_value(v, "expected a whole number without a sign, found " + quoted(s));
    return static_cast<long long>(*u);
  }
  const std::optional<std::int64_t> x = parse_integer_text(s);
  if (!x) bad_value(v, "expected an integer, found " + quoted(s));
  return *x;
}

bool parse_param_boolean(const ParamSetting& v) {
  if (v.value == "true") return true;
  if (v.value == "false") return false;
  bad_value(v, "expected true or false, found " + quoted(v.value));
}

std::string format_param_real(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string format_param_scaled(double stored, double scale) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", stored / scale);
  double back = 0.0;
  const auto r = std::from_chars(buf, buf + std::strlen(buf), back);
  if (r.ec == std::errc() && back * scale == stored) return buf;
  return format_param_real(stored / scale);
}

void param_check_range(const ParamSetting& v, const ParamRange& r, double x) {
  if (!r.contains(x)) bad_value(v, "must be " + (r.text().front() == '[' || r.text().front() == '(' ? "in " + r.text() : r.text()) +
                                       ", found " + quoted(v.value));
}

void param_check_list_range(const ParamSetting& v, std::size_t index, const ParamRange& r, double x) {
  if (!r.contains(x))
    bad_value(v, "number " + std::to_string(index + 1) + " must be " +
                     (r.text().front() == '[' || r.text().front() == '(' ? "in " + r.text() : r.text()) + ", found " +
                     format_param_real(x) + " in " + quoted(v.value));
}

void param_check_choice(const ParamSetting& v, const std::vector<std::string>& choices) {
  std::string known;
  for (const auto& c : choices) {
    if (c == v.value) return;
    known += (known.empty() ? "" : ", ") + c;
  }
  bad_value(v, "unknown value " + quoted(v.value) + " (" + known + ")");
}

void param_unknown_key(const ParamSetting& v, const std::vector<std::string>& known) {
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  bad_value(v, "unknown key '" + one_line(v.key, 60) + "'" + (list.empty() ? " (this section takes no parameters)" : " (known: " + list + ")"));
}

void rethrow_at_setting(const Error& e, std::span<const ParamSetting> settings, const std::string& file) {
  const std::string& f = e.field();
  for (auto it = settings.rbegin(); it != settings.rend(); ++it) {
    const std::string& k = it->key;
    const bool match = f == k || (f.size() > k.size() && f.compare(f.size() - k.size(), k.size(), k) == 0 &&
                                  f[f.size() - k.size() - 1] == '.');
    if (match) throw Error(e.message(), it->file, it->line, it->field.empty() ? k : it->field);
  }
  if (e.file().empty() && !file.empty()) throw Error(e.message(), file, e.line(), e.field());
  throw e;
}

std::string params_markdown_table(const std::vector<ParamSpec>& specs, const std::string& section) {
  // A cell's text with its pipes escaped (choices are written "a | b").
  const auto cell = [](std::string t) {
    std::string out;
    for (char c : t) {
      if (c == '|') out += '\\';
      out += c;
    }
    return out;
  };
  std::string s = "| key | type | default | range | unit | meaning |\n|---|---|---|---|---|---|\n";
  for (const ParamSpec& p : specs) {
    const std::string key = section.empty() ? p.key : section + "." + p.key;
    s += "| `" + key + "` | " + param_type_name(p.type) + " | " + (p.default_value.empty() ? "\"\"" : "`" + p.default_value + "`") +
         " | " + cell(p.range_text()) + " | " + p.unit + " | " + cell(p.doc) + " |\n";
  }
  return s;
}

}  // namespace starnav
