// Elevation map files: PNG16 + YAML sidecar, ESRI ASCII grid, CSV, Unity RAW (GeoTIFF lives in
// elevation_gdal.cpp / elevation_nogdal.cpp). See docs/formats.md.
#include "starnav/io/elevation_io.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/output_file.hpp"
#include "starnav/core/text_lines.hpp"
#include "starnav/io/image.hpp"
#include "starnav/io/yaml_document.hpp"
#include "starnav/map/occupancy_grid.hpp"  // validate_geometry

namespace starnav {

namespace fs = std::filesystem;

namespace {

// The cell limit of validate_geometry (width * height <= INT_MAX).
constexpr double kQuantumCount = 65535.0;

// ---- small helpers -----------------------------------------------------------------------------

// A value from a file, printable inside a one-line error message.
std::string quote(std::string_view s) {
  std::string out = "'";
  const std::size_t limit = 40;
  for (std::size_t i = 0; i < s.size() && i < limit; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    out += (c < 0x20 || c == 0x7f) ? '?' : static_cast<char>(c);
  }
  if (s.size() > limit) out += "...";
  return out + "'";
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Rethrows an Error that names no file as one naming `path`.
template <class F>
auto attributed(const std::string& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error& e) {
    if (e.file().empty()) throw e.with_file(path);
    throw;
  }
}

enum class NumParse { Ok, NotNumber, NotFinite, OutOfRange };

// A whole token as a decimal number (optional sign, digits, fraction, exponent). nan/inf are
// recognised as numbers that are not finite.
NumParse parse_number(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && s.front() == '-') return NumParse::NotNumber;
  }
  if (s.empty()) return NumParse::NotNumber;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) return NumParse::OutOfRange;
  if (ec != std::errc() || ptr != end) {
    // YAML spells them .nan / .inf / -.inf.
    const std::string l = lower(s);
    if (l == ".nan" || l == ".inf" || l == "-.inf") return NumParse::NotFinite;
    return NumParse::NotNumber;
  }
  if (!std::isfinite(out)) return NumParse::NotFinite;
  return NumParse::Ok;
}

bool parse_integer(std::string_view s, long long& out) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && s.front() == '-') return false;
  }
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && ptr == end;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Splits on runs of blanks into `out` (cleared first).
void split_blanks(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

// Iterates the lines of a text (LF or CRLF), numbering them from 1.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(without_utf8_bom(text)) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t nl = text_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
    line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    line_start_ = pos_;
    pos_ = nl == std::string_view::npos ? text_.size() : nl + 1;
    ++number_;
    return true;
  }
  int number() const { return number_; }
  std::size_t line_start() const { return line_start_; }  // offset of the current line

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_start_ = 0;
  int number_ = 0;
};

// ---- quantisation shared by PNG16 and RAW -------------------------------------------------------

struct Quantisation {
  double z_min = 0.0;
  double z_max = 0.0;
  bool has_nodata = false;  // nodata value 0, observed heights 1..65535
  std::vector<std::uint16_t> values;  // row-major, iy = 0 first
};

// Quantises the observed heights over their range; when some cells are unobserved, value 0 is
// kept for them and the observed heights use 1..65535 (z_min is moved down by one quantum).
Quantisation quantise(const ElevationMap& map) {
  Quantisation q;
  const std::size_t n = map.cell_count();
  q.values.assign(n, 0);
  const auto range = map.height_range();
  q.has_nodata = map.observed_count() != n;
  if (!range) return q;  // nothing observed: all nodata, z range 0..0
  // The representative heights define the range (min/max spreads are not stored).
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    if (!map.observed_at_index(i)) continue;
    lo = std::min(lo, map.height_at_index(i));
    hi = std::max(hi, map.height_at_index(i));
  }
  const double span = hi - lo;
  if (!std::isfinite(span)) throw Error("height range too large to quantise to 16 bit", {}, 0, "z_max");
  const double first = q.has_nodata ? 1.0 : 0.0;
  const double steps = kQuantumCount - first;  // 65535 or 65534
  q.z_max = hi;
  q.z_min = q.has_nodata ? lo - span / steps : lo;
  if (!std::isfinite(q.z_min)) throw Error("height range too large to quantise to 16 bit", {}, 0, "z_min");
  for (std::size_t i = 0; i < n; ++i) {
    if (!map.observed_at_index(i)) continue;
    double v = kQuantumCount;  // a flat map: any value gives z_min == z_max
    if (span > 0) v = first + std::round((map.height_at_index(i) - lo) / span * steps);
    q.values[i] = static_cast<std::uint16_t>(std::clamp(v, first, kQuantumCount));
  }
  return q;
}

double dequantise(std::uint16_t v, double z_min, double z_max) {
  return z_min + static_cast<double>(v) / kQuantumCount * (z_max - z_min);
}

// ---- YAML with every key checked ----------------------------------------------------------------

class YamlKeys {
 public:
  YamlKeys(std::string path, const std::string& text) : path_(std::move(path)) {
    root_ = load_yaml_document(text, path_);
    if (!root_.IsMap()) throw Error("expected a YAML mapping of keys", path_);
  }

  const std::string& path() const { return path_; }
  bool has(const char* key) const { return static_cast<bool>(root_[key]); }

  YAML::Node get(const char* key) const {
    const YAML::Node node = root_[key];
    if (!node) throw Error("missing key", path_, 0, key);
    if (node.IsNull()) throw Error("key has no value", path_, line(node), key);
    return node;
  }
  int line(const YAML::Node& node) const { return node.Mark().line >= 0 ? node.Mark().line + 1 : 0; }

  double number(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) throw Error("must be a number", path_, line(node), field);
    double v = 0;
    switch (parse_number(trim(node.Scalar()), v)) {
      case NumParse::Ok: return v;
      case NumParse::NotFinite:
        throw Error("must be a finite number, got " + quote(node.Scalar()), path_, line(node), field);
      case NumParse::OutOfRange:
        throw Error("number out of range: " + quote(node.Scalar()), path_, line(node), field);
      case NumParse::NotNumber: break;
    }
    throw Error("must be a number, got " + quote(node.Scalar()), path_, line(node), field);
  }
  double number(const char* key) const { return number(get(key), key); }

  long long integer(const char* key, long long lo, long long hi) const {
    const YAML::Node node = get(key);
    long long v = 0;
    if (!node.IsScalar() || !parse_integer(trim(node.Scalar()), v))
      throw Error("must be a whole number, got " + quote(node.IsScalar() ? node.Scalar() : "(not a scalar)"), path_,
                  line(node), key);
    if (v < lo || v > hi)
      throw Error("must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + std::to_string(v), path_,
                  line(node), key);
    return v;
  }

  std::string string(const char* key) const {
    const YAML::Node node = get(key);
    if (!node.IsScalar() || node.Scalar().empty()) throw Error("must be a non-empty string", path_, line(node), key);
    return node.Scalar();
  }

  Pose2 origin() const {
    const YAML::Node node = get("origin");
    if (!node.IsSequence() || node.size() != 3)
      throw Error("must be a list of three numbers [x, y, yaw]", path_, line(node), "origin");
    return {number(node[0], "origin"), number(node[1], "origin"), number(node[2], "origin")};
  }

  double positive(const char* key) const {
    const double v = number(key);
    if (!(v > 0)) throw Error("must be positive, got " + format_height(v), path_, line(get(key)), key);
    return v;
  }

  Error error(const char* key, const std::string& message) const {
    return Error(message, path_, has(key) ? line(root_[key]) : 0, key);
  }

 private:
  std::string path_;
  YAML::Node root_;
};

std::string yaml_number(double v) { return format_height(v); }

// The z range keys of the PNG and RAW sidecars: finite, z_max >= z_min.
void read_z_range(const YamlKeys& y, double& z_min, double& z_max) {
  z_min = y.number("z_min");
  z_max = y.number("z_max");
  if (!(z_max >= z_min))
    throw y.error("z_max", "z_max (" + format_height(z_max) + ") must be >= z_min (" + format_height(z_min) + ")");
  if (!std::isfinite(z_max - z_min)) throw y.error("z_max", "z range too large");
}

// ---- .prj beside an .asc ------------------------------------------------------------------------

std::optional<std::string> read_prj_beside(const std::string& asc_path) {
  std::error_code ec;
  for (const char* ext : {".prj", ".PRJ"}) {
    fs::path p(asc_path);
    p.replace_extension(ext);
    // A projection is a line of WKT: a larger file is not one.
    if (fs::is_regular_file(p, ec)) return read_input_file(p.string(), std::uint64_t{1} << 20);
  }
  return std::nullopt;
}

// The first number after the quoted name in KEY["name",number,...], searching from `from`.
std::optional<double> wkt_number_after_name(const std::string& wkt, std::size_t bracket, int which = 0) {
  std::size_t q1 = wkt.find('"', bracket);
  if (q1 == std::string::npos) return std::nullopt;
  std::size_t q2 = wkt.find('"', q1 + 1);
  if (q2 == std::string::npos) return std::nullopt;
  std::size_t pos = q2 + 1;
  for (int k = 0; k <= which; ++k) {
    pos = wkt.find(',', pos);
    if (pos == std::string::npos) return std::nullopt;
    ++pos;
    std::size_t end = wkt.find_first_of(",]", pos);
    if (end == std::string::npos) return std::nullopt;
    double v = 0;
    if (k == which) {
      if (parse_number(trim(std::string_view(wkt).substr(pos, end - pos)), v) != NumParse::Ok) return std::nullopt;
      return v;
    }
    pos = end;
  }
  return std::nullopt;
}

struct PrjInfo {
  ElevationGeoref::Crs crs = ElevationGeoref::Crs::None;
  std::string name;
  double unit = 1.0;  // metres per unit (projected) or degrees per unit (geographic)
  double semi_major = 6378137.0;
  double inverse_flattening = 298.257223563;
};

PrjInfo classify_prj(const std::string& text) {
  PrjInfo info;
  const std::string t(trim(text));
  std::string up = t;
  for (char& c : up) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  auto starts = [&](const char* p) { return up.rfind(p, 0) == 0; };
  if (starts("GEOGCS") || starts("GEOGCRS") || starts("GEOGRAPHICCRS")) {
    info.crs = ElevationGeoref::Crs::Geographic;
  } else if (starts("PROJCS") || starts("PROJCRS") || starts("PROJECTEDCRS") || starts("LOCAL_CS") ||
             starts("ENGCRS")) {
    info.crs = ElevationGeoref::Crs::Projected;
  } else if (starts("PROJECTION")) {  // old ESRI .prj: "Projection GEOGRAPHIC", "Units DD"
    std::istringstream in(up);
    std::string key, value;
    in >> key >> value;
    info.crs = value == "GEOGRAPHIC" ? ElevationGeoref::Crs::Geographic : ElevationGeoref::Crs::Projected;
    if (info.crs == ElevationGeoref::Crs::Projected && (up.find("UNITS FEET") != std::string::npos))
      info.unit = 0.3048;
    return info;
  } else {
    return info;  // not recognised: no CRS
  }
  if (const auto q1 = t.find('"'); q1 != std::string::npos) {
    if (const auto q2 = t.find('"', q1 + 1); q2 != std::string::npos) info.name = t.substr(q1 + 1, q2 - q1 - 1);
  }
  // Ellipsoid of the datum.
  std::size_t sph = up.find("SPHEROID[");
  if (sph == std::string::npos) sph = up.find("ELLIPSOID[");
  if (sph != std::string::npos) {
    const auto a = wkt_number_after_name(t, sph, 0);
    const auto invf = wkt_number_after_name(t, sph, 1);
    if (a && invf && *a > 6.0e6 && *a < 7.0e6 && *invf > 0) {
      info.semi_major = *a;
      info.inverse_flattening = *invf;
    }
  }
  // The last UNIT[...] is the unit of the coordinate system (WKT1: PROJCS's linear unit, GEOGCS's
  // angular unit).
  const std::size_t unit = up.rfind("UNIT[");
  if (unit != std::string::npos) {
    if (const auto f = wkt_number_after_name(t, unit, 0); f && *f > 0) {
      info.unit = info.crs == ElevationGeoref::Crs::Geographic ? *f * 180.0 / kPi : *f;
      if (info.crs == ElevationGeoref::Crs::Geographic && std::abs(info.unit - 1.0) < 1e-9) info.unit = 1.0;
    }
  }
  return info;
}

// ---- ESRI ASCII grid ---------------------------------------------------------------------------

struct AscParsed {
  ElevationMap map;
  double x = 0, y = 0;  // lower-left corner as given (corner, after centre -> corner)
  double cellsize = 0;
};

AscParsed parse_asc_full(std::string_view text, const std::string& source) {
  LineReader lines(text);
  std::string_view line;
  std::vector<std::string_view> tok;

  struct Key {
    const char* name;
    bool seen = false;
    int line = 0;
    double value = 0;
  };
  enum { NCOLS, NROWS, XLLCORNER, XLLCENTER, YLLCORNER, YLLCENTER, CELLSIZE, DX, DY, NODATA, KEY_COUNT };
  Key keys[KEY_COUNT] = {{"ncols"},     {"nrows"},    {"xllcorner"}, {"xllcenter"}, {"yllcorner"},
                         {"yllcenter"}, {"cellsize"}, {"dx"},        {"dy"},        {"NODATA_value"}};
  auto key_index = [](const std::string& k) -> int {
    static const char* names[] = {"ncols",     "nrows",    "xllcorner", "xllcenter", "yllcorner",
                                  "yllcenter", "cellsize", "dx",        "dy",        "nodata_value"};
    for (int i = 0; i < KEY_COUNT; ++i)
      if (k == names[i]) return i;
    if (k == "nodata") return NODATA;
    return -1;
  };

  long long ncols = 0, nrows = 0;
  bool have_data = false;
  std::size_t data_offset = text.size();
  int data_line = 0;
  while (lines.next(line)) {
    split_blanks(line, tok);
    if (tok.empty()) continue;
    const std::string k = lower(tok[0]);
    const int idx = key_index(k);
    if (idx < 0) {
      double v = 0;
      if (parse_number(tok[0], v) == NumParse::NotNumber && std::isalpha(static_cast<unsigned char>(tok[0][0])))
        throw Error("unknown header key " + quote(tok[0]) +
                        " (expected ncols, nrows, xllcorner|xllcenter, yllcorner|yllcenter, cellsize, NODATA_value)",
                    source, lines.number());
      have_data = true;
      data_offset = lines.line_start();
      data_line = lines.number();
      break;
    }
    Key& key = keys[idx];
    if (key.seen) throw Error("given twice (first on line " + std::to_string(key.line) + ")", source, lines.number(), key.name);
    if (tok.size() != 2) throw Error("expected one value after the key", source, lines.number(), key.name);
    key.seen = true;
    key.line = lines.number();
    if (idx == NCOLS || idx == NROWS) {
      long long v = 0;
      if (!parse_integer(tok[1], v)) throw Error("must be a whole number, got " + quote(tok[1]), source, key.line, key.name);
      if (v <= 0) throw Error("must be positive, got " + std::to_string(v), source, key.line, key.name);
      if (v > std::numeric_limits<int>::max()) throw Error("too large: " + std::to_string(v), source, key.line, key.name);
      (idx == NCOLS ? ncols : nrows) = v;
      continue;
    }
    switch (parse_number(tok[1], key.value)) {
      case NumParse::Ok: break;
      case NumParse::NotFinite:
        throw Error("must be a finite number, got " + quote(tok[1]), source, key.line, key.name);
      case NumParse::OutOfRange: throw Error("number out of range: " + quote(tok[1]), source, key.line, key.name);
      case NumParse::NotNumber: throw Error("must be a number, got " + quote(tok[1]), source, key.line, key.name);
    }
    if ((idx == CELLSIZE || idx == DX || idx == DY) && !(key.value > 0))
      throw Error("must be positive, got " + quote(tok[1]), source, key.line, key.name);
  }
  const int at = have_data ? data_line : lines.number();
  for (int i : {NCOLS, NROWS})
    if (!keys[i].seen) throw Error("missing from the header", source, at, keys[i].name);
  if (keys[XLLCORNER].seen == keys[XLLCENTER].seen)
    throw Error(keys[XLLCORNER].seen ? "both xllcorner and xllcenter given" : "missing from the header (or xllcenter)",
                source, keys[XLLCORNER].seen ? keys[XLLCENTER].line : at, "xllcorner");
  if (keys[YLLCORNER].seen == keys[YLLCENTER].seen)
    throw Error(keys[YLLCORNER].seen ? "both yllcorner and yllcenter given" : "missing from the header (or yllcenter)",
                source, keys[YLLCORNER].seen ? keys[YLLCENTER].line : at, "yllcorner");
  double cellsize = 0;
  if (keys[CELLSIZE].seen) {
    if (keys[DX].seen || keys[DY].seen) throw Error("give either cellsize or dx/dy", source, keys[CELLSIZE].line, "cellsize");
    cellsize = keys[CELLSIZE].value;
  } else if (keys[DX].seen && keys[DY].seen) {
    if (keys[DX].value != keys[DY].value)
      throw Error("non-square cells (dx " + format_height(keys[DX].value) + ", dy " + format_height(keys[DY].value) +
                      ") are not supported",
                  source, keys[DY].line, "dy");
    cellsize = keys[DX].value;
  } else {
    throw Error("missing from the header", source, at, "cellsize");
  }

  const std::uint64_t count = static_cast<std::uint64_t>(ncols) * static_cast<std::uint64_t>(nrows);
  if (count > kMaxGridCells)
    throw Error("grid too large: " + std::to_string(ncols) + " x " + std::to_string(nrows) + " cells", source,
                keys[NCOLS].line, "ncols");
  // Every value takes at least one character and one separator: refuse a large grid before
  // allocating it when the file cannot hold its values (small ones get the precise row errors).
  const std::uint64_t data_bytes = text.size() - data_offset;
  if (count > (1u << 16) && count > (data_bytes + 1) / 2)
    throw Error("header promises " + std::to_string(ncols) + " x " + std::to_string(nrows) + " = " +
                    std::to_string(count) + " values but only " + std::to_string(data_bytes) +
                    " bytes of data follow (too few values)",
                source, keys[NCOLS].line, "ncols");

  const double x0 = keys[XLLCORNER].seen ? keys[XLLCORNER].value : keys[XLLCENTER].value - cellsize / 2;
  const double y0 = keys[YLLCORNER].seen ? keys[YLLCORNER].value : keys[YLLCENTER].value - cellsize / 2;
  GridGeometry geometry;
  geometry.width = static_cast<int>(ncols);
  geometry.height = static_cast<int>(nrows);
  geometry.resolution = cellsize;
  geometry.origin = Pose2(x0, y0, 0.0);
  AscParsed out{attributed(source, [&] { return ElevationMap(geometry); }), x0, y0, cellsize};
  ElevationMap& map = out.map;

  const bool has_nodata = keys[NODATA].seen;
  const double nodata = keys[NODATA].value;
  long long row = 0;
  int last_line = lines.number();
  bool first = have_data;
  while (first || lines.next(line)) {
    if (!first) split_blanks(line, tok);
    first = false;
    if (tok.empty()) continue;
    last_line = lines.number();
    if (row >= nrows)
      throw Error("more rows of values than nrows = " + std::to_string(nrows), source, lines.number(), "nrows");
    if (static_cast<long long>(tok.size()) != ncols)
      throw Error("row " + std::to_string(row + 1) + " has " + std::to_string(tok.size()) + " values, ncols is " +
                      std::to_string(ncols),
                  source, lines.number(), "ncols");
    const int iy = static_cast<int>(nrows - 1 - row);
    for (int ix = 0; ix < static_cast<int>(ncols); ++ix) {
      double v = 0;
      switch (parse_number(tok[static_cast<std::size_t>(ix)], v)) {
        case NumParse::Ok: break;
        case NumParse::NotFinite:
          throw Error("value " + quote(tok[static_cast<std::size_t>(ix)]) + " in column " + std::to_string(ix + 1) +
                          " is not finite (use NODATA_value for missing cells)",
                      source, lines.number());
        case NumParse::OutOfRange:
          throw Error("value " + quote(tok[static_cast<std::size_t>(ix)]) + " in column " + std::to_string(ix + 1) +
                          " is out of range",
                      source, lines.number());
        case NumParse::NotNumber:
          throw Error("value " + quote(tok[static_cast<std::size_t>(ix)]) + " in column " + std::to_string(ix + 1) +
                          " is not a number",
                      source, lines.number());
      }
      if (has_nodata && v == nodata) continue;  // unobserved
      map.set_height(ix, iy, v);
    }
    ++row;
  }
  if (row < nrows)
    throw Error("only " + std::to_string(row) + " rows of values, nrows is " + std::to_string(nrows) +
                    " (too few values)",
                source, last_line, "nrows");
  return out;
}

// ---- geographic coordinates ---------------------------------------------------------------------

double eccentricity_squared(double inverse_flattening) {
  const double f = 1.0 / inverse_flattening;
  return f * (2.0 - f);
}

}  // namespace

// ---- public helpers ------------------------------------------------------------------------------

std::string format_height(double value) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed);
  if (r.ec == std::errc() && r.ptr - buf <= 24) return std::string(buf, r.ptr);
  r = std::to_chars(buf, buf + sizeof buf, value);  // shortest of fixed and scientific
  return std::string(buf, r.ptr);
}

double metres_per_degree_latitude(double latitude_deg, double semi_major_m, double inverse_flattening) {
  const double e2 = eccentricity_squared(inverse_flattening);
  const double s = std::sin(latitude_deg * kPi / 180.0);
  const double m = semi_major_m * (1.0 - e2) / std::pow(1.0 - e2 * s * s, 1.5);  // meridional radius
  return m * kPi / 180.0;
}

double metres_per_degree_longitude(double latitude_deg, double semi_major_m, double inverse_flattening) {
  const double e2 = eccentricity_squared(inverse_flattening);
  const double phi = latitude_deg * kPi / 180.0;
  const double s = std::sin(phi);
  const double n = semi_major_m / std::sqrt(1.0 - e2 * s * s);  // prime-vertical radius
  return n * std::cos(phi) * kPi / 180.0;
}

GridGeometry georeferenced_geometry(int width, int height, ElevationGeoref& georef, double semi_major,
                             double inverse_flattening) {
  GridGeometry g;
  g.width = width;
  g.height = height;
  switch (georef.crs) {
    case ElevationGeoref::Crs::Geographic: {
      const double lat_lo = georef.y_min;
      const double lat_hi = georef.y_min + georef.cell_y * height;
      if (!(lat_lo >= -90.0 - 1e-9 && lat_hi <= 90.0 + 1e-9))
        throw Error("geographic grid reaches beyond latitude +-90 (" + format_height(lat_lo) + " .. " +
                        format_height(lat_hi) + ")",
                    {}, 0, "latitude");
      const double lat = 0.5 * (lat_lo + lat_hi);
      georef.centre_latitude_deg = lat;
      georef.metres_per_unit_x = metres_per_degree_longitude(lat, semi_major, inverse_flattening);
      georef.metres_per_unit_y = metres_per_degree_latitude(lat, semi_major, inverse_flattening);
      if (!(georef.metres_per_unit_x > 0))
        throw Error("geographic grid centred on a pole cannot be converted to metres", {}, 0, "latitude");
      g.resolution = std::sqrt(georef.cell_x * georef.metres_per_unit_x * georef.cell_y * georef.metres_per_unit_y);
      g.origin = Pose2(0.0, 0.0, 0.0);
      break;
    }
    case ElevationGeoref::Crs::Projected:
      g.resolution = georef.cell_x * georef.metres_per_unit_x;
      g.origin = Pose2(georef.x_min * georef.metres_per_unit_x, georef.y_min * georef.metres_per_unit_y, 0.0);
      break;
    case ElevationGeoref::Crs::None:
      georef.metres_per_unit_x = georef.metres_per_unit_y = 1.0;
      g.resolution = georef.cell_x;
      g.origin = Pose2(georef.x_min, georef.y_min, 0.0);
      break;
  }
  validate_geometry(g, "elevation map");
  return g;
}

// ---- ESRI ASCII grid ---------------------------------------------------------------------------

ElevationMap parse_asc(std::string_view text, const std::string& source) {
  return std::move(parse_asc_full(text, source).map);
}

ElevationMap read_asc(const std::string& path) { return read_asc(path, nullptr); }

ElevationMap read_asc(const std::string& path, ElevationGeoref* georef) {
  const InputFileScope reading_path(path);
  // The first header line decides before the rest is read: a file that does not start with an
  // ESRI ASCII grid key costs its first kilobytes only.
  const auto check_head = [&](std::string_view head, std::uint64_t) {
    LineReader lines(head);
    std::string_view line;
    std::vector<std::string_view> tok;
    while (lines.next(line)) {
      split_blanks(line, tok);
      if (tok.empty()) continue;
      const std::string k = lower(tok[0]);
      for (const char* key : {"ncols", "nrows", "xllcorner", "xllcenter", "yllcorner", "yllcenter", "cellsize", "dx", "dy",
                              "nodata_value", "nodata"})
        if (k == key) return;
      throw Error("expected an ESRI ASCII grid header line (ncols N), found '" + printable(line, 40) + "'", path,
                  lines.number());
    }
  };
  const std::string text = read_input_file(path, kMaxInputFileBytes, 4096, check_head);
  AscParsed parsed = parse_asc_full(text, path);
  ElevationGeoref g;
  g.x_min = parsed.x;
  g.y_min = parsed.y;
  g.cell_x = g.cell_y = parsed.cellsize;
  PrjInfo prj;
  if (const auto prj_text = read_prj_beside(path)) prj = classify_prj(*prj_text);
  g.crs = prj.crs;
  g.crs_name = prj.name;
  if (prj.crs == ElevationGeoref::Crs::Geographic) {
    // Coordinates in units of prj.unit degrees.
    g.x_min *= prj.unit;
    g.y_min *= prj.unit;
    g.cell_x *= prj.unit;
    g.cell_y *= prj.unit;
  } else if (prj.crs == ElevationGeoref::Crs::Projected) {
    g.metres_per_unit_x = g.metres_per_unit_y = prj.unit;
  }
  if (g.crs != ElevationGeoref::Crs::None) {
    const GridGeometry geometry = attributed(path, [&] {
      return georeferenced_geometry(parsed.map.width(), parsed.map.height(), g, prj.semi_major,
                                     prj.inverse_flattening);
    });
    parsed.map.mutable_geometry() = geometry;
  } else {
    g.metres_per_unit_x = g.metres_per_unit_y = 1.0;
  }
  if (georef) *georef = g;
  return std::move(parsed.map);
}

void write_asc(const ElevationMap& map, const std::string& path) {
  const GridGeometry& g = map.geometry();
  if (g.width <= 0 || g.height <= 0) throw Error("cannot write an empty elevation map", path);
  if (g.origin.yaw != 0.0)
    throw Error("an ESRI ASCII grid cannot be rotated: origin yaw must be 0", path, 0, "origin");
  // A NODATA_value no observed height uses.
  double nodata = -9999.0;
  if (const auto range = map.height_range()) {
    bool clash = false;
    for (std::size_t i = 0; i < map.cell_count() && !clash; ++i)
      clash = map.observed_at_index(i) && map.height_at_index(i) == nodata;
    if (clash) {
      double lo = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < map.cell_count(); ++i)
        if (map.observed_at_index(i)) lo = std::min(lo, map.height_at_index(i));
      nodata = std::floor(lo) - 1.0;
      if (!std::isfinite(nodata) || !(nodata < lo))
        throw Error("no value is left for NODATA_value below the lowest height", path, 0, "NODATA_value");
    }
  }
  std::string out;
  out.reserve(map.cell_count() * 10 + 200);
  out += "ncols        " + std::to_string(g.width) + "\n";
  out += "nrows        " + std::to_string(g.height) + "\n";
  out += "xllcorner    " + format_height(g.origin.x) + "\n";
  out += "yllcorner    " + format_height(g.origin.y) + "\n";
  out += "cellsize     " + format_height(g.resolution) + "\n";
  out += "NODATA_value " + format_height(nodata) + "\n";
  const std::string nodata_text = format_height(nodata);
  for (int iy = g.height - 1; iy >= 0; --iy) {
    for (int ix = 0; ix < g.width; ++ix) {
      if (ix) out += ' ';
      out += map.observed_at(ix, iy) ? format_height(map.height_at(ix, iy)) : nodata_text;
    }
    out += '\n';
  }
  write_file_atomically(path, out);
}

// ---- CSV -------------------------------------------------------------------------------------

namespace {

// One field of an elevation CSV: its height, or nothing for an empty field (an unobserved cell);
// Error naming the line and column.
std::optional<double> csv_height(std::string_view field, const std::string& source, int line, int ix) {
  field = trim(field);
  if (field.empty()) return std::nullopt;
  double v = 0;
  const std::string col = "column " + std::to_string(ix + 1);
  switch (parse_number(field, v)) {
    case NumParse::Ok: return v;
    case NumParse::NotFinite:
      throw Error("value " + quote(field) + " is not finite (leave the field empty for an unobserved cell)", source, line, col);
    case NumParse::OutOfRange: throw Error("value " + quote(field) + " is out of range", source, line, col);
    case NumParse::NotNumber: break;
  }
  throw Error("value " + quote(field) + " is not a number", source, line, col);
}

}  // namespace

ElevationMap parse_elevation_csv(std::string_view text, const std::string& source, double resolution, Pose2 origin) {
  text = without_utf8_bom(text);
  // The rows are counted before anything is stored: every line (the last may lack its '\n'), and
  // with several columns trailing blank lines end the file (for one column a blank line is an
  // unobserved cell).
  std::uint64_t lines = 0, last_filled = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t nl = text.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
    ++lines;
    if (!trim(text.substr(pos, end - pos)).empty()) last_filled = lines;
    pos = end + 1;
  }
  if (lines == 0) throw Error("empty CSV: no rows", source);
  const std::string_view first = text.substr(0, text.find('\n'));
  const std::uint64_t width = static_cast<std::uint64_t>(std::count(first.begin(), first.end(), ',')) + 1;
  const std::uint64_t rows = width > 1 ? last_filled : lines;
  if (rows == 0) throw Error("empty CSV: no rows", source);
  if (width > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) || rows > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ||
      width * rows > kMaxGridCells)
    throw Error("grid too large: " + std::to_string(width) + " x " + std::to_string(rows) + " cells, more than " +
                    std::to_string(kMaxGridCells),
                source);
  GridGeometry geometry;
  geometry.width = static_cast<int>(width);
  geometry.height = static_cast<int>(rows);
  geometry.resolution = resolution;
  geometry.origin = origin;
  ElevationMap map = attributed(source, [&] { return ElevationMap(geometry); });
  const int height = geometry.height;
  LineReader reader(text);
  std::string_view line;
  for (int r = 0; r < height && reader.next(line); ++r) {
    const int iy = height - 1 - r;
    std::size_t pos = 0;
    int ix = 0;
    while (true) {
      const std::size_t comma = line.find(',', pos);
      if (static_cast<std::uint64_t>(ix) >= width)
        throw Error("row has more fields than the first row (" + std::to_string(width) + ")", source, reader.number());
      const auto v = csv_height(line.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos), source,
                                reader.number(), ix);
      if (v) map.set_height(ix, iy, *v);
      ++ix;
      if (comma == std::string_view::npos) break;
      pos = comma + 1;
    }
    if (static_cast<std::uint64_t>(ix) != width)
      throw Error("row has " + std::to_string(ix) + " fields, the first row has " + std::to_string(width), source, reader.number());
  }
  return map;
}

ElevationMap read_elevation_csv(const std::string& path, double resolution, Pose2 origin) {
  const InputFileScope reading_path(path);
  // The rows in the head are judged before the rest is read (their whole fields heights or empty,
  // as many as the first row's, no NUL byte): a file of another kind costs its head.
  const auto check_head = [&](std::string_view head, std::uint64_t size) {
    head = without_utf8_bom(head);
    const bool cut = head.size() < size;
    std::size_t width = 0;
    int line_no = 0;
    for (std::size_t pos = 0; pos < head.size();) {
      const std::size_t nl = head.find('\n', pos);
      std::string_view row = head.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
      ++line_no;
      const bool whole = nl != std::string_view::npos || !cut;
      if (!whole) {
        const std::size_t last_comma = row.rfind(',');
        // The cut field is left out, unless it is the first row's only one: no height is that long.
        if (last_comma == std::string_view::npos && line_no == 1)
          throw Error("value " + quote(row) + " is not a number (a field longer than " + std::to_string(kTextHeadBytes) + " bytes)", path,
                      1, "column 1");
        row = last_comma == std::string_view::npos ? std::string_view() : row.substr(0, last_comma);
      }
      if (!row.empty() && row.back() == '\r') row.remove_suffix(1);
      // A blank line may end a file of several columns.
      if (!(line_no > 1 && width > 1 && trim(row).empty())) {
        std::size_t fields = 0;
        for (std::size_t at = 0;; at = row.find(',', at) + 1) {
          if (line_no > 1 && fields == width)
            throw Error("row has more fields than the first row (" + std::to_string(width) + ")", path, line_no);
          const std::size_t comma = row.find(',', at);
          csv_height(row.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at), path, line_no,
                     static_cast<int>(fields++));
          if (comma == std::string_view::npos) break;
        }
        if (line_no == 1) width = fields;
        else if (whole && fields != width)
          throw Error("row has " + std::to_string(fields) + " fields, the first row has " + std::to_string(width), path, line_no);
      }
      if (nl == std::string_view::npos) break;
      pos = nl + 1;
    }
    const std::size_t nul = head.find('\0');
    if (nul != std::string_view::npos) throw Error("byte " + std::to_string(nul) + " is a NUL: binary data, not an elevation CSV", path);
  };
  const std::string text = read_input_file(path, kMaxInputFileBytes, kTextHeadBytes, check_head);
  return parse_elevation_csv(text, path, resolution, origin);
}

void write_elevation_csv(const ElevationMap& map, const std::string& path) {
  if (map.width() <= 0 || map.height() <= 0) throw Error("cannot write an empty elevation map", path);
  std::string out;
  out.reserve(map.cell_count() * 10);
  for (int iy = map.height() - 1; iy >= 0; --iy) {
    for (int ix = 0; ix < map.width(); ++ix) {
      if (ix) out += ',';
      if (map.observed_at(ix, iy)) out += format_height(map.height_at(ix, iy));
    }
    out += '\n';
  }
  write_file_atomically(path, out);
}

// ---- PNG16 + YAML ------------------------------------------------------------------------------

ElevationMap read_elevation_yaml(const std::string& yaml_path, std::string* companion) {
  const InputFileScope reading_yaml_path(yaml_path);
  const YamlKeys y(yaml_path, read_yaml_file(yaml_path));
  // The sidecar of a Unity RAW export also has z_min/z_max: read the RAW it describes.
  if (y.has("format") && y.string("format") == "unity_raw") {
    const std::string suffix = ".yaml";
    if (yaml_path.size() > suffix.size() && yaml_path.ends_with(suffix)) {
      const std::string raw = yaml_path.substr(0, yaml_path.size() - suffix.size());
      if (companion) *companion = raw;
      return read_unity_raw(raw);
    }
    throw y.error("format", "a Unity RAW sidecar must be named <raw file>.yaml");
  }
  const std::string image_name = y.string("image");
  const int image_line = y.line(y.get("image"));
  const double resolution = y.positive("resolution");
  const Pose2 origin = y.origin();
  double z_min = 0, z_max = 0;
  read_z_range(y, z_min, z_max);
  // -1 / 0: key absent (std::optional here trips g++ 12's -Wmaybe-uninitialized).
  const long long nodata = y.has("nodata") ? y.integer("nodata", 0, 65535) : -1;
  const long long want_w = y.has("width") ? y.integer("width", 1, std::numeric_limits<int>::max()) : 0;
  const long long want_h = y.has("height") ? y.integer("height", 1, std::numeric_limits<int>::max()) : 0;

  fs::path image_path(image_name);
  if (image_path.is_relative()) image_path = fs::path(yaml_path).parent_path() / image_path;
  std::error_code ec;
  if (!fs::is_regular_file(image_path, ec))
    throw Error(quote(image_name) + " not found (looked for " + image_path.string() + ")", yaml_path,
                image_line, "image");
  if (companion) *companion = image_path.string();
  const GrayImage image = read_gray_image(image_path.string());  // its errors name the image file
  if (image.channels != 1 || image.max_value != 65535) {
    std::string kind;
    if (image.channels != 1) kind = std::to_string(image.channels) + "-channel";
    else if (image.max_value == 255) kind = "8-bit";
    else kind = "grey with max value " + std::to_string(image.max_value);
    throw Error(quote(image_name) + " is " + kind +
                    "; an elevation image must be 16-bit grayscale (1 channel, 0..65535)",
                yaml_path, image_line, "image");
  }
  if (want_w != 0 && want_w != image.width)
    throw y.error("width", "says " + std::to_string(want_w) + " but image " + quote(image_name) + " is " +
                               std::to_string(image.width) + " x " + std::to_string(image.height));
  if (want_h != 0 && want_h != image.height)
    throw y.error("height", "says " + std::to_string(want_h) + " but image " + quote(image_name) + " is " +
                                std::to_string(image.width) + " x " + std::to_string(image.height));
  if (image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw Error("image pixel count does not match its size", image_path.string());

  GridGeometry geometry;
  geometry.width = image.width;
  geometry.height = image.height;
  geometry.resolution = resolution;
  geometry.origin = origin;
  ElevationMap map = attributed(yaml_path, [&] { return ElevationMap(geometry); });
  for (int r = 0; r < image.height; ++r) {
    const int iy = image.height - 1 - r;
    for (int ix = 0; ix < image.width; ++ix) {
      const std::uint16_t v = image.at(ix, r);
      if (v == nodata) continue;
      map.set_height(ix, iy, dequantise(v, z_min, z_max));
    }
  }
  return map;
}

std::string elevation_yaml_image_path(const std::string& yaml_path) {
  fs::path image_path(yaml_path);
  image_path.replace_extension(".png");
  if (image_path == fs::path(yaml_path)) image_path += ".png";
  return image_path.string();
}

void write_elevation_yaml(const ElevationMap& map, const std::string& yaml_path) {
  if (map.width() <= 0 || map.height() <= 0) throw Error("cannot write an empty elevation map", yaml_path);
  const Quantisation q = attributed(yaml_path, [&] { return quantise(map); });
  const fs::path image_path(elevation_yaml_image_path(yaml_path));
  GrayImage image;
  image.width = map.width();
  image.height = map.height();
  image.max_value = 65535;
  image.channels = 1;
  image.pixels.resize(map.cell_count());
  for (int r = 0; r < map.height(); ++r) {
    const int iy = map.height() - 1 - r;
    for (int ix = 0; ix < map.width(); ++ix)
      image.pixels[static_cast<std::size_t>(r) * static_cast<std::size_t>(map.width()) + static_cast<std::size_t>(ix)] =
          q.values[map.geometry().index(ix, iy)];
  }
  write_png(image, image_path.string());
  const GridGeometry& g = map.geometry();
  std::string out;
  out += "# starnav elevation map: height = z_min + v / 65535 * (z_max - z_min)\n";
  out += "image: " + image_path.filename().string() + "\n";
  out += "resolution: " + yaml_number(g.resolution) + "\n";
  out += "origin: [" + yaml_number(g.origin.x) + ", " + yaml_number(g.origin.y) + ", " + yaml_number(g.origin.yaw) + "]\n";
  out += "z_min: " + yaml_number(q.z_min) + "\n";
  out += "z_max: " + yaml_number(q.z_max) + "\n";
  if (q.has_nodata) out += "nodata: 0\n";
  out += "width: " + std::to_string(g.width) + "\n";
  out += "height: " + std::to_string(g.height) + "\n";
  write_file_atomically(yaml_path, out);
}

// ---- Unity RAW ---------------------------------------------------------------------------------

std::string unity_raw_sidecar_path(const std::string& raw_path) { return raw_path + ".yaml"; }

namespace {

std::string raw_sidecar(const std::string& path) { return unity_raw_sidecar_path(path); }

// Largest RAW side whose square stays within kMaxGridCells.
constexpr long long kMaxRawSize = 32769;

long long unity_size_for(int w, int h) {
  const long long need = std::max(w, h);
  long long size = 2;  // 2^0 + 1
  while (size < need) size = (size - 1) * 2 + 1;
  return size;
}

bool is_unity_size(long long s) { return s >= 2 && ((s - 1) & (s - 2)) == 0; }

}  // namespace

int unity_raw_size(int width, int height) {
  if (width <= 0 || height <= 0) throw Error("map size must be positive");
  const long long size = unity_size_for(width, height);
  if (size > std::numeric_limits<int>::max()) throw Error("map too large for a Unity RAW");
  return static_cast<int>(size);
}

void write_unity_raw(const ElevationMap& map, const std::string& path) {
  const GridGeometry& g = map.geometry();
  if (g.width <= 0 || g.height <= 0) throw Error("cannot write an empty elevation map", path);
  const long long size = unity_size_for(g.width, g.height);
  if (size > kMaxRawSize)
    throw Error("a " + std::to_string(size) + " x " + std::to_string(size) + " RAW is too large (largest " +
                    std::to_string(kMaxRawSize) + ")",
                path);
  const Quantisation q = attributed(path, [&] { return quantise(map); });
  const std::size_t n = static_cast<std::size_t>(size);
  std::string bytes(n * n * 2, '\0');
  for (std::size_t ry = 0; ry < n; ++ry) {  // rows bottom first: raw row 0 is iy 0
    const int iy = static_cast<int>(std::min<std::size_t>(ry, static_cast<std::size_t>(g.height - 1)));
    for (std::size_t rx = 0; rx < n; ++rx) {
      const int ix = static_cast<int>(std::min<std::size_t>(rx, static_cast<std::size_t>(g.width - 1)));
      const std::uint16_t v = q.values[g.index(ix, iy)];
      const std::size_t at = (ry * n + rx) * 2;
      bytes[at] = static_cast<char>(v & 0xff);
      bytes[at + 1] = static_cast<char>(v >> 8);
    }
  }
  if (size != g.width || size != g.height)
    std::cerr << "starnav: warning: " << path << ": padded " << g.width << " x " << g.height << " to " << size
              << " x " << size << " for Unity (edge replication)\n";
  write_file_atomically(path, bytes);
  std::string y;
  y += "# starnav Unity RAW sidecar: 16-bit little-endian, rows bottom first, size x size samples;\n";
  y += "# height = z_min + v / 65535 * (z_max - z_min); cells beyond width/height are padding\n";
  y += "format: unity_raw\n";
  y += "byte_order: little\n";
  y += "size: " + std::to_string(size) + "\n";
  y += "width: " + std::to_string(g.width) + "\n";
  y += "height: " + std::to_string(g.height) + "\n";
  y += "resolution: " + yaml_number(g.resolution) + "\n";
  y += "origin: [" + yaml_number(g.origin.x) + ", " + yaml_number(g.origin.y) + ", " + yaml_number(g.origin.yaw) + "]\n";
  y += "z_min: " + yaml_number(q.z_min) + "\n";
  y += "z_max: " + yaml_number(q.z_max) + "\n";
  if (q.has_nodata) y += "nodata: 0\n";
  write_file_atomically(raw_sidecar(path), y);
}

ElevationMap read_unity_raw(const std::string& path) {
  const InputFileScope reading_path(path);
  const std::string sidecar = raw_sidecar(path);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error("file not found", path);
  if (!fs::is_regular_file(sidecar, ec))
    throw Error("sidecar " + sidecar + " not found (it gives size, resolution, origin and z range)", path);
  const YamlKeys y(sidecar, read_yaml_file(sidecar));
  if (y.has("format") && y.string("format") != "unity_raw")
    throw y.error("format", "must be unity_raw, got " + quote(y.string("format")));
  if (y.has("byte_order") && y.string("byte_order") != "little")
    throw y.error("byte_order", "only little-endian RAW is supported, got " + quote(y.string("byte_order")));
  const long long size = y.integer("size", 2, kMaxRawSize);
  if (!is_unity_size(size)) throw y.error("size", "must be 2^n + 1, got " + std::to_string(size));
  const long long width = y.integer("width", 1, size);
  const long long height = y.integer("height", 1, size);
  const double resolution = y.positive("resolution");
  const Pose2 origin = y.origin();
  double z_min = 0, z_max = 0;
  read_z_range(y, z_min, z_max);
  const long long nodata = y.has("nodata") ? y.integer("nodata", 0, 65535) : -1;  // -1: none

  const std::uint64_t want = static_cast<std::uint64_t>(size) * static_cast<std::uint64_t>(size) * 2;
  const std::uint64_t have = fs::file_size(path, ec);
  if (ec) throw Error("cannot read file size", path);
  if (have != want)
    throw Error("file has " + std::to_string(have) + " bytes, a " + std::to_string(size) + " x " +
                    std::to_string(size) + " 16-bit RAW has " + std::to_string(want) + " (wrong file size)",
                path);
  const std::string bytes = read_input_file(path);
  if (bytes.size() != want) throw Error("file changed size while reading", path);

  GridGeometry geometry;
  geometry.width = static_cast<int>(width);
  geometry.height = static_cast<int>(height);
  geometry.resolution = resolution;
  geometry.origin = origin;
  ElevationMap map = attributed(sidecar, [&] { return ElevationMap(geometry); });
  const std::size_t n = static_cast<std::size_t>(size);
  for (int iy = 0; iy < geometry.height; ++iy) {
    for (int ix = 0; ix < geometry.width; ++ix) {
      const std::size_t at = (static_cast<std::size_t>(iy) * n + static_cast<std::size_t>(ix)) * 2;
      const std::uint16_t v = static_cast<std::uint16_t>(static_cast<unsigned char>(bytes[at]) |
                                                         (static_cast<unsigned char>(bytes[at + 1]) << 8));
      if (v == nodata) continue;
      map.set_height(ix, iy, dequantise(v, z_min, z_max));
    }
  }
  return map;
}

}  // namespace starnav
