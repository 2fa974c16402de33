#include "starnav/sim/scenario_document.hpp"

#include <cctype>
#include <sstream>

#include "starnav/core/number_text.hpp"

namespace starnav::scenario_detail {

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

namespace {

bool is_special_float(std::string_view t) {
  std::string lower;
  for (const char c : t) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return lower == ".inf" || lower == "+.inf" || lower == "-.inf" || lower == ".nan" || lower == "inf" ||
         lower == "-inf" || lower == "nan";
}

}  // namespace

double Value::number() const {
  if (!node_.IsScalar()) fail("expected a number, found " + node_kind(node_));
  if (is_special_float(node_.Scalar())) fail("must be finite, got " + node_.Scalar());
  const std::optional<double> v = parse_real_text(node_.Scalar());
  if (!v) fail("expected a number, found " + node_kind(node_));
  return *v;
}

double Value::in_range(double lo, double hi) const {
  const double v = number();
  if (v < lo || v > hi) fail("must be in [" + fmt(lo) + ", " + fmt(hi) + "], got " + node_.Scalar());
  return v;
}

std::string Value::string() const {
  if (!node_.IsScalar()) fail("expected text, found " + node_kind(node_));
  return node_.Scalar();
}

std::vector<double> Value::numbers(std::size_t lo, std::size_t hi) const {
  const std::string want = lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi);
  if (!node_.IsSequence()) fail("expected a list of " + want + " numbers, found " + node_kind(node_));
  if (node_.size() < lo || node_.size() > hi) fail("expected a list of " + want + " numbers, found " + std::to_string(node_.size()));
  std::vector<double> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(element(i).number());
  return out;
}

Value Value::element(std::size_t i) const {
  const YAML::Node e = node_[i];
  const int l = mark_line(e);
  return Value(e, field_ + "[" + std::to_string(i) + "]", l > 0 ? l : line_, *doc_);
}

std::size_t Value::list(const std::string& what) const {
  if (!node_.IsSequence()) fail("expected a list of " + what + ", found " + node_kind(node_));
  return node_.size();
}

std::string Value::fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

Fields::Fields(const Value& v, const Doc& doc) : field_(v.field()), line_(v.line()), doc_(&doc) {
  const YAML::Node& n = v.node();
  if (n.IsNull()) return;  // `imu:` with nothing after it: all defaults
  if (!n.IsMap()) v.fail("expected a mapping (key: value lines), found " + node_kind(n));
  for (auto it = n.begin(); it != n.end(); ++it) {
    const int l = mark_line(it->first);
    if (!it->first.IsScalar()) throw Error("keys must be plain names", doc.file, l, v.field());
    const std::string key = it->first.Scalar();
    for (const Entry& e : entries_)
      if (e.key == key) throw Error("duplicate key", doc.file, l, path(key));
    // A key without a mark was set on the command line (--set): it has no line.
    entries_.push_back({key, it->second, it->first.Mark().is_null() ? 0 : l});
  }
}

const Fields::Entry* Fields::find(const std::string& key) const {
  for (const Entry& e : entries_)
    if (e.key == key) return &e;
  return nullptr;
}

std::optional<Value> Fields::take(const char* key) {
  const Entry* e = find(key);
  if (!e) return std::nullopt;
  used_.insert(key);
  return Value(e->value, path(key), e->line, *doc_);
}

Value Fields::required(const char* key) {
  auto v = take(key);
  if (!v) throw Error("required key is missing", doc_->file, line_, path(key));
  return *v;
}

void Fields::require(const char* key) const {
  if (!find(key)) throw Error("required key is missing", doc_->file, line_, path(key));
}

std::vector<std::string> Fields::keys() const {
  std::vector<std::string> k;
  for (const Entry& e : entries_) k.push_back(e.key);
  return k;
}

int Fields::line_of(const std::string& key) const {
  const Entry* e = find(key);
  return e ? e->line : line_;
}

void Fields::fail_at(const std::string& key, const std::string& message) const {
  const Entry* e = find(key);
  if (e && e->line == 0) throw Error(message, doc_->file, 0, path(key) + " (--set)");
  throw Error(message, doc_->file, e ? e->line : line_, path(key));
}

void rethrow_at(const Error& e, const Doc& doc, int line, const std::string& field_prefix) {
  std::string field = field_prefix;
  if (!e.field().empty()) field += (field.empty() ? "" : ".") + e.field();
  throw Error(e.message(), doc.file, line, field);
}

Vec3 xyz_or_xy(const Value& v, double z_default, bool* had_z) {
  const std::vector<double> p = v.numbers(2, 3);
  if (had_z) *had_z = p.size() == 3;
  return {p[0], p[1], p.size() == 3 ? p[2] : z_default};
}

ParamSetting setting_of(const Value& e, const std::string& key) {
  return {key, e.node().IsScalar() ? e.node().Scalar() : std::string(), e.doc().file, e.line(),
          e.line() > 0 ? e.field() : e.field() + " (--set)"};
}

// A sequence whose items are scalars or such sequences, at most `depth` levels deep (no
// parameter nests deeper than polygons' three).
bool is_value_list(const YAML::Node& node, int depth) {
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

std::string resolve_path(const Doc& doc, const std::string& path) {
  const std::filesystem::path p(path);
  return p.is_absolute() ? p.string() : (doc.base_dir / p).lexically_normal().string();
}

std::string expected_value(const ParamSpec& spec) {
  switch (spec.type) {
    case ParamType::Real: return "expected a number";
    case ParamType::Integer: return spec.range.lo >= 0 ? "expected a whole number" : "expected an integer";
    case ParamType::Boolean: return "expected true or false";
    case ParamType::Choice: return "expected one of " + spec.range_text();
    case ParamType::Text: return "expected text";
    case ParamType::NameList: return "expected a list of names";
    case ParamType::Polygons: return "expected polygons";
    case ParamType::Reals: return "expected a list of numbers";
  }
  return "expected a value";
}

}  // namespace starnav::scenario_detail
