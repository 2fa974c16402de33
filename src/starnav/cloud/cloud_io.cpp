#include "starnav/cloud/cloud_io.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/text_lines.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/logs/decompress.hpp"

namespace starnav {

namespace {

// A scalar field of a binary record: its type letter (F float, I signed, U unsigned), size in
// bytes and byte order.
struct ScalarType {
  char kind = 'F';
  std::size_t size = 4;
};

bool valid_scalar(const ScalarType& t) {
  if (t.kind == 'F') return t.size == 4 || t.size == 8;
  return (t.kind == 'I' || t.kind == 'U') && (t.size == 1 || t.size == 2 || t.size == 4 || t.size == 8);
}

double read_scalar(const char* p, const ScalarType& t, bool big_endian) {
  std::array<unsigned char, 8> b{};
  std::memcpy(b.data(), p, t.size);
  if (big_endian != (std::endian::native == std::endian::big)) std::reverse(b.begin(), b.begin() + static_cast<long>(t.size));
  if (t.kind == 'F') {
    if (t.size == 4) {
      float f;
      std::memcpy(&f, b.data(), 4);
      return f;
    }
    double d;
    std::memcpy(&d, b.data(), 8);
    return d;
  }
  std::uint64_t u = 0;
  std::memcpy(&u, b.data(), t.size);  // little-endian host: the low bytes
  if (t.kind == 'U') return static_cast<double>(u);
  const unsigned shift = static_cast<unsigned>(64 - 8 * t.size);
  return static_cast<double>(static_cast<std::int64_t>(u << shift) >> shift);
}

bool parse_count(std::string_view text, std::size_t& out) {
  const auto r = std::from_chars(text.data(), text.data() + text.size(), out);
  return r.ec == std::errc() && r.ptr == text.data() + text.size();
}

// A value of an ascii record: any number, nan and inf included (dropped later as non-finite).
bool parse_any_number(std::string_view text, double& out) {
  const auto r = std::from_chars(text.data(), text.data() + text.size(), out);
  return r.ec == std::errc() && r.ptr == text.data() + text.size();
}

// 0, 1 or 2 for a field or property named x, y or z; -1 for any other.
int xyz_axis(std::string_view name) {
  if (name.size() != 1) return -1;
  const std::size_t a = std::string_view("xyz").find(name[0]);
  return a == std::string_view::npos ? -1 : static_cast<int>(a);
}

void keep_point(PointCloudFile& f, double x, double y, double z) {
  if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) {
    f.points.emplace_back(x, y, z);
  } else {
    ++f.dropped_non_finite;
  }
}

[[noreturn]] void fail(const std::string& path, int line, const std::string& field, const std::string& what) {
  throw Error(what, path, line, field);
}

void check_point_count(std::size_t n, const std::string& path, int line, const std::string& field) {
  if (n > kMaxCloudPoints)
    fail(path, line, field, std::to_string(n) + " points is more than the limit of " + std::to_string(kMaxCloudPoints));
}

// The next header line of a text header starting at `pos`; false at the end of the bytes.
bool next_header_line(std::string_view bytes, std::size_t& pos, std::string_view& line) {
  if (pos >= bytes.size()) return false;
  std::size_t end = bytes.find('\n', pos);
  if (end == std::string_view::npos) end = bytes.size();
  line = bytes.substr(pos, end - pos);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos = std::min(bytes.size(), end + 1);
  return true;
}

}  // namespace

std::string lzf_decompress(std::string_view in, std::size_t size, const std::string& path) {
  std::string out;
  out.reserve(size);
  std::size_t i = 0;
  while (i < in.size()) {
    const auto ctrl = static_cast<unsigned char>(in[i++]);
    if (ctrl < 32) {
      const std::size_t run = std::size_t{ctrl} + 1;
      if (i + run > in.size() || out.size() + run > size) fail(path, 0, "DATA", "corrupt binary_compressed data (a literal run overflows)");
      out.append(in.substr(i, run));
      i += run;
    } else {
      std::size_t len = ctrl >> 5;
      if (len == 7) {
        if (i >= in.size()) fail(path, 0, "DATA", "corrupt binary_compressed data (truncated)");
        len += static_cast<unsigned char>(in[i++]);
      }
      if (i >= in.size()) fail(path, 0, "DATA", "corrupt binary_compressed data (truncated)");
      const std::size_t back = ((std::size_t{ctrl} & 0x1fU) << 8) + static_cast<unsigned char>(in[i++]) + 1;
      len += 2;
      if (back > out.size() || out.size() + len > size) fail(path, 0, "DATA", "corrupt binary_compressed data (a back reference overflows)");
      // Byte by byte: the copied range may overlap what it produces.
      const std::size_t from = out.size() - back;
      for (std::size_t k = 0; k < len; ++k) out.push_back(out[from + k]);
    }
  }
  if (out.size() != size)
    fail(path, 0, "DATA", "binary_compressed data decompresses to " + std::to_string(out.size()) + " bytes, not " +
                              std::to_string(size));
  return out;
}

namespace {

// What a PCD header says: the fields, the points and where the data starts.
struct PcdHeader {
  std::vector<std::string> fields;
  std::vector<std::size_t> sizes, counts;
  std::string types;
  std::size_t n = 0;                       // points
  std::string data;                        // ascii, binary or binary_compressed
  std::array<int, 3> field_of{-1, -1, -1};  // x, y, z: field index ...
  std::array<std::size_t, 3> offset_of{}, value_of{};  // ... byte offset in a record, value index in a line
  std::size_t record = 0, values = 0;      // bytes of a binary record, values of an ascii line
  std::size_t body = 0;                    // where the data starts
  int line_no = 0;                         // the DATA line
};

// `bytes` holds the header (the whole file, or its head: `head` true, so that a header running
// past it is said to); Error naming the line and field otherwise.
PcdHeader parse_pcd_header(std::string_view bytes, const std::string& path, bool head) {
  PcdHeader h;
  std::vector<std::string>& fields = h.fields;
  std::vector<std::size_t>& sizes = h.sizes;
  std::vector<std::size_t>& counts = h.counts;
  std::string& types = h.types;
  std::optional<std::size_t> width, height, points;
  std::string& data = h.data;
  std::size_t pos = 0;
  int line_no = 0;
  std::string_view line;
  const auto cut_short = [&] {
    fail(path, line_no, "DATA", "the header does not end within the first " + std::to_string(bytes.size()) + " bytes");
  };
  while (data.empty()) {
    if (!next_header_line(bytes, pos, line)) {
      if (head) cut_short();
      fail(path, line_no, "DATA", "the header ends without a DATA line");
    }
    ++line_no;
    // A head's last line may be cut: judged only by its first word.
    const bool cut = head && pos == bytes.size() && bytes.back() != '\n';
    if (line.empty() || line.front() == '#') {
      if (cut) cut_short();
      continue;
    }
    const std::vector<std::string_view> t = split_fields(line);
    if (t.empty()) {
      if (cut) cut_short();
      continue;
    }
    const std::string key(t[0]);
    if (cut && (key == "VERSION" || key == "VIEWPOINT" || key == "FIELDS" || key == "SIZE" || key == "COUNT" || key == "TYPE" ||
                key == "WIDTH" || key == "HEIGHT" || key == "POINTS" || key == "DATA"))
      cut_short();
    auto counts_of = [&](std::vector<std::size_t>& out) {
      out.clear();
      for (std::size_t k = 1; k < t.size(); ++k) {
        std::size_t v = 0;
        if (!parse_count(t[k], v)) fail(path, line_no, key, "'" + printable(t[k], 20) + "' is not a count");
        out.push_back(v);
      }
    };
    if (key == "VERSION" || key == "VIEWPOINT") {
      continue;
    } else if (key == "FIELDS") {
      fields.clear();
      for (std::size_t k = 1; k < t.size(); ++k) fields.emplace_back(t[k]);
    } else if (key == "SIZE") {
      counts_of(sizes);
    } else if (key == "COUNT") {
      counts_of(counts);
    } else if (key == "TYPE") {
      types.clear();
      for (std::size_t k = 1; k < t.size(); ++k) {
        if (t[k].size() != 1) fail(path, line_no, "TYPE", "'" + printable(t[k], 20) + "' is not F, I or U");
        types += t[k][0];
      }
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      std::size_t v = 0;
      if (t.size() != 2 || !parse_count(t[1], v)) fail(path, line_no, key, "needs one count");
      (key == "WIDTH" ? width : key == "HEIGHT" ? height : points) = v;
    } else if (key == "DATA") {
      if (t.size() != 2 || (t[1] != "ascii" && t[1] != "binary" && t[1] != "binary_compressed"))
        fail(path, line_no, "DATA", "must be ascii, binary or binary_compressed");
      data = std::string(t[1]);
    } else {
      fail(path, line_no, printable(key, 30), "unknown PCD header line");
    }
  }
  if (fields.empty()) fail(path, line_no, "FIELDS", "missing");
  if (counts.empty()) counts.assign(fields.size(), 1);
  if (sizes.size() != fields.size() || types.size() != fields.size() || counts.size() != fields.size())
    fail(path, line_no, "FIELDS", "FIELDS, SIZE, TYPE and COUNT list different numbers of entries");
  if (!width) fail(path, line_no, "WIDTH", "missing");
  if (!height) height = 1;
  if (*height != 0 && *width > kMaxCloudPoints / *height) check_point_count(kMaxCloudPoints + 1, path, line_no, "WIDTH");
  const std::size_t n = points ? *points : *width * *height;
  h.n = n;
  check_point_count(n, path, line_no, "POINTS");
  if (n != *width * *height) fail(path, line_no, "POINTS", "differs from WIDTH x HEIGHT");
  // Where x, y and z sit: field index and the byte offset in a record.
  std::array<int, 3>& field_of = h.field_of;
  std::array<std::size_t, 3>& offset_of = h.offset_of;
  std::array<std::size_t, 3>& value_of = h.value_of;
  std::size_t& record = h.record;
  std::size_t& values = h.values;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const ScalarType st{types[k], sizes[k]};
    if (!valid_scalar(st)) fail(path, line_no, "TYPE", "field '" + printable(fields[k], 30) + "' has an unsupported type/size");
    if (counts[k] == 0 || counts[k] > 10000) fail(path, line_no, "COUNT", "must be in [1, 10000]");
    if (const int a = xyz_axis(fields[k]); a >= 0) {
      if (counts[k] != 1) fail(path, line_no, "COUNT", "x, y and z must have COUNT 1");
      field_of[a] = static_cast<int>(k);
      offset_of[a] = record;
      value_of[a] = values;
    }
    record += sizes[k] * counts[k];
    values += counts[k];
  }
  if (field_of[0] < 0 || field_of[1] < 0 || field_of[2] < 0) fail(path, line_no, "FIELDS", "needs x, y and z");
  h.body = pos;
  h.line_no = line_no;
  return h;
}

}  // namespace

PointCloudFile parse_pcd(std::string_view bytes, const std::string& path) {
  const PcdHeader h = parse_pcd_header(bytes, path, false);
  const std::vector<std::size_t>& sizes = h.sizes;
  const std::string& types = h.types;
  const std::size_t n = h.n;
  const std::string& data = h.data;
  const std::array<int, 3>& field_of = h.field_of;
  const std::array<std::size_t, 3>& offset_of = h.offset_of;
  const std::array<std::size_t, 3>& value_of = h.value_of;
  const std::size_t record = h.record, values = h.values;
  const std::size_t pos = h.body;
  const int line_no = h.line_no;
  PointCloudFile f;
  const std::string_view body = bytes.substr(pos);
  if (data == "ascii") {
    f.points.reserve(std::min(n, body.size() / 6 + 1));
    std::size_t read = 0;
    int body_line = line_no;
    for_each_line(body, [&](std::string_view l, int) {
      ++body_line;
      const std::vector<std::string_view> v = split_fields(l);
      if (v.empty()) return;
      if (read >= n) fail(path, body_line, "POINTS", "more point lines than POINTS says");
      if (v.size() != values) fail(path, body_line, "DATA", std::to_string(v.size()) + " values, the header says " + std::to_string(values));
      std::array<double, 3> xyz{};
      for (int a = 0; a < 3; ++a)
        if (!parse_any_number(v[value_of[a]], xyz[a])) fail(path, body_line, std::string(1, "xyz"[a]), "'" + printable(v[value_of[a]], 20) + "' is not a number");
      keep_point(f, xyz[0], xyz[1], xyz[2]);
      ++read;
    });
    if (read != n) fail(path, 0, "POINTS", "says " + std::to_string(n) + " points, the file holds " + std::to_string(read));
    return f;
  }
  std::string decompressed;
  std::string_view raw = body;
  if (data == "binary_compressed") {
    if (body.size() < 8) fail(path, 0, "DATA", "binary_compressed data shorter than its 8-byte sizes");
    std::uint32_t compressed = 0, size = 0;
    std::memcpy(&compressed, body.data(), 4);
    std::memcpy(&size, body.data() + 4, 4);
    if (size != n * record) fail(path, 0, "DATA", "binary_compressed size " + std::to_string(size) + " is not POINTS x record");
    if (compressed > body.size() - 8) fail(path, 0, "DATA", "binary_compressed data is truncated");
    decompressed = lzf_decompress(body.substr(8, compressed), size, path);
    raw = decompressed;
  }
  if (raw.size() < n * record)
    fail(path, 0, "DATA", "binary data holds " + std::to_string(raw.size()) + " bytes, " + std::to_string(n * record) + " needed");
  f.points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::array<double, 3> xyz{};
    for (int a = 0; a < 3; ++a) {
      const auto k = static_cast<std::size_t>(field_of[a]);
      const ScalarType st{types[k], sizes[k]};
      // binary: records one after another; binary_compressed: each field's values together.
      const std::size_t at = data == "binary" ? i * record + offset_of[a] : n * offset_of[a] + i * sizes[k];
      xyz[a] = read_scalar(raw.data() + at, st, false);
    }
    keep_point(f, xyz[0], xyz[1], xyz[2]);
  }
  return f;
}

namespace {

enum class PlyEncoding { Ascii, Little, Big };

// What a PLY header says of its vertices, and where the data starts.
struct PlyHeader {
  PlyEncoding enc = PlyEncoding::Ascii;
  std::size_t n = 0;  // vertices
  std::vector<std::pair<std::string, ScalarType>> props;
  std::array<int, 3> prop_of{-1, -1, -1};  // x, y, z: property index and byte offset in a record
  std::array<std::size_t, 3> offset_of{};
  std::size_t record = 0;
  bool later_elements = false;  // elements after the vertices (faces): the file's size is not the vertices'
  std::size_t body = 0;
  int line_no = 0;              // end_header's
};

// As parse_pcd_header.
PlyHeader parse_ply_header(std::string_view bytes, const std::string& path, bool head) {
  PlyHeader h;
  std::size_t pos = 0;
  std::string_view line;
  int line_no = 0;
  if (!next_header_line(bytes, pos, line) || line != "ply") fail(path, 1, "ply", "does not start with the line 'ply'");
  line_no = 1;
  using Enc = PlyEncoding;
  Enc& enc = h.enc;
  bool have_format = false, in_vertex = false, vertex_done = false;
  std::size_t& n = h.n;
  std::vector<std::pair<std::string, ScalarType>>& props = h.props;
  for (;;) {
    if (!next_header_line(bytes, pos, line) || (head && pos == bytes.size() && bytes.back() != '\n')) {
      if (head) fail(path, line_no, "end_header", "the header does not end within the first " + std::to_string(bytes.size()) + " bytes");
      fail(path, line_no, "end_header", "missing");
    }
    ++line_no;
    const std::vector<std::string_view> t = split_fields(line);
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") break;
    if (t[0] == "format") {
      if (t.size() != 3) fail(path, line_no, "format", "needs an encoding and a version");
      if (t[1] == "ascii") enc = Enc::Ascii;
      else if (t[1] == "binary_little_endian") enc = Enc::Little;
      else if (t[1] == "binary_big_endian") enc = Enc::Big;
      else fail(path, line_no, "format", "'" + printable(t[1], 30) + "' is not ascii, binary_little_endian or binary_big_endian");
      have_format = true;
    } else if (t[0] == "element") {
      if (t.size() != 3) fail(path, line_no, "element", "needs a name and a count");
      if (in_vertex) vertex_done = true;
      if (vertex_done) h.later_elements = true;
      if (t[1] == "vertex") {
        if (in_vertex || vertex_done) fail(path, line_no, "element vertex", "appears twice");
        if (!parse_count(t[2], n)) fail(path, line_no, "element vertex", "'" + printable(t[2], 20) + "' is not a count");
        check_point_count(n, path, line_no, "element vertex");
        in_vertex = true;
      } else if (!in_vertex && !vertex_done) {
        fail(path, line_no, "element", "elements before 'vertex' are not supported");
      }
    } else if (t[0] == "property") {
      if (!in_vertex || vertex_done) continue;  // properties of later elements (faces) are not read
      if (t.size() != 3) fail(path, line_no, "property", "a vertex property needs a type and a name (no lists)");
      static const std::array<std::pair<const char*, ScalarType>, 16> kTypes{{
          {"char", {'I', 1}}, {"uchar", {'U', 1}}, {"short", {'I', 2}}, {"ushort", {'U', 2}},
          {"int", {'I', 4}}, {"uint", {'U', 4}}, {"float", {'F', 4}}, {"double", {'F', 8}},
          {"int8", {'I', 1}}, {"uint8", {'U', 1}}, {"int16", {'I', 2}}, {"uint16", {'U', 2}},
          {"int32", {'I', 4}}, {"uint32", {'U', 4}}, {"float32", {'F', 4}}, {"float64", {'F', 8}}}};
      std::optional<ScalarType> type;
      for (const auto& [name, st] : kTypes)
        if (t[1] == name) type = st;
      if (!type) fail(path, line_no, "property", "unknown type '" + printable(t[1], 20) + "'");
      props.emplace_back(std::string(t[2]), *type);
    } else {
      fail(path, line_no, printable(t[0], 30), "unknown PLY header line");
    }
  }
  if (!have_format) fail(path, line_no, "format", "missing");
  if (!in_vertex) fail(path, line_no, "element vertex", "missing");
  std::array<int, 3>& prop_of = h.prop_of;
  std::array<std::size_t, 3>& offset_of = h.offset_of;
  std::size_t& record = h.record;
  for (std::size_t k = 0; k < props.size(); ++k) {
    if (const int a = xyz_axis(props[k].first); a >= 0) {
      prop_of[a] = static_cast<int>(k);
      offset_of[a] = record;
    }
    record += props[k].second.size;
  }
  if (prop_of[0] < 0 || prop_of[1] < 0 || prop_of[2] < 0) fail(path, line_no, "property", "the vertex needs x, y and z");
  h.body = pos;
  h.line_no = line_no;
  return h;
}

}  // namespace

PointCloudFile parse_ply(std::string_view bytes, const std::string& path) {
  const PlyHeader h = parse_ply_header(bytes, path, false);
  using Enc = PlyEncoding;
  const Enc enc = h.enc;
  const std::size_t n = h.n;
  const std::vector<std::pair<std::string, ScalarType>>& props = h.props;
  const std::array<int, 3>& prop_of = h.prop_of;
  const std::array<std::size_t, 3>& offset_of = h.offset_of;
  const std::size_t record = h.record;
  const std::size_t pos = h.body;
  const int line_no = h.line_no;
  PointCloudFile f;
  const std::string_view body = bytes.substr(pos);
  if (enc == Enc::Ascii) {
    f.points.reserve(std::min(n, body.size() / 6 + 1));
    std::size_t read = 0;
    std::size_t at = 0;
    int body_line = line_no;
    std::string_view l;
    while (read < n) {
      if (!next_header_line(body, at, l)) fail(path, body_line, "element vertex", "says " + std::to_string(n) + " vertices, the file holds " + std::to_string(read));
      ++body_line;
      const std::vector<std::string_view> v = split_fields(l);
      if (v.empty()) continue;
      if (v.size() < props.size()) fail(path, body_line, "vertex", std::to_string(v.size()) + " values, " + std::to_string(props.size()) + " properties");
      std::array<double, 3> xyz{};
      for (int a = 0; a < 3; ++a)
        if (!parse_any_number(v[static_cast<std::size_t>(prop_of[a])], xyz[a]))
          fail(path, body_line, std::string(1, "xyz"[a]), "'" + printable(v[static_cast<std::size_t>(prop_of[a])], 20) + "' is not a number");
      keep_point(f, xyz[0], xyz[1], xyz[2]);
      ++read;
    }
    return f;
  }
  if (body.size() / record < n)
    fail(path, 0, "element vertex", "binary data holds " + std::to_string(body.size()) + " bytes, " + std::to_string(n * record) + " needed");
  f.points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::array<double, 3> xyz{};
    for (int a = 0; a < 3; ++a)
      xyz[a] = read_scalar(body.data() + i * record + offset_of[a], props[static_cast<std::size_t>(prop_of[a])].second, enc == Enc::Big);
    keep_point(f, xyz[0], xyz[1], xyz[2]);
  }
  return f;
}

PointCloudFile parse_kitti_bin(std::string_view bytes, const std::string& path) {
  if (bytes.size() % 16 != 0)
    fail(path, 0, "size", std::to_string(bytes.size()) + " bytes is not a whole number of 16-byte (x, y, z, reflectance) records");
  const std::size_t n = bytes.size() / 16;
  check_point_count(n, path, 0, "size");
  PointCloudFile f;
  f.points.reserve(n);
  const ScalarType float32{'F', 4};
  for (std::size_t i = 0; i < n; ++i) {
    const char* p = bytes.data() + 16 * i;
    keep_point(f, read_scalar(p, float32, false), read_scalar(p + 4, float32, false), read_scalar(p + 8, float32, false));
  }
  return f;
}

PointCloudFile read_point_cloud(const std::string& path) {
  const InputFileScope reading_path(path);
  const std::string ext = lower_extension(path);
  // The head decides before the rest is read: a PCD or PLY header, or a KITTI frame's size, and
  // the file's size against what they promise (a binary body exactly; text at most kMaxValueChars
  // a value; a PLY with elements after its vertices only from below).
  constexpr std::uint64_t kMaxValueChars = 64, kTrailingBytes = std::uint64_t{1} << 20;
  const auto check_size = [&](std::uint64_t size, std::uint64_t body, std::uint64_t least, std::optional<std::uint64_t> most,
                              const char* field) {
    if (size - body < least)
      fail(path, 0, field, "binary data holds " + std::to_string(size - body) + " bytes, " + std::to_string(least) + " needed");
    if (most && size - body > *most + kTrailingBytes)
      fail(path, 0, field, "is " + std::to_string(size) + " bytes, more than its header's points take (" +
                               std::to_string(body + *most) + " and " + std::to_string(kTrailingBytes) + " to spare)");
  };
  const auto check_head = [&](std::string_view head, std::uint64_t size) {
    if (is_gzip(head)) return;
    const bool cut = head.size() < size;
    if (head.substr(0, 4) == "ply\n" || head.substr(0, 5) == "ply\r\n" || ext == ".ply") {
      const PlyHeader h = parse_ply_header(head, path, cut);
      const std::uint64_t n = h.n;
      if (h.enc == PlyEncoding::Ascii)
        check_size(size, h.body, 0, h.later_elements ? std::nullopt : std::optional<std::uint64_t>(n * (h.props.size() * kMaxValueChars + 2)),
                   "element vertex");
      else
        check_size(size, h.body, n * h.record, h.later_elements ? std::nullopt : std::optional<std::uint64_t>(n * h.record),
                   "element vertex");
      return;
    }
    if (ext == ".pcd" || head.substr(0, 6) == "# .PCD" || head.substr(0, 7) == "VERSION") {
      const PcdHeader h = parse_pcd_header(head, path, cut);
      const std::uint64_t n = h.n, bytes = n * h.record;
      if (h.data == "ascii") check_size(size, h.body, 0, n * (h.values * kMaxValueChars + 2), "POINTS");
      else if (h.data == "binary") check_size(size, h.body, bytes, bytes, "DATA");
      else check_size(size, h.body, 8, 8 + bytes + bytes / 32 + 1, "DATA");  // LZF: a control byte per 32 literals at worst
      return;
    }
    if (ext != ".bin") throw Error("not a point cloud: expected a PCD or PLY header, or a KITTI .bin frame", path);
    // A KITTI frame's size is its point count.
    if (size % 16 != 0)
      fail(path, 0, "size", std::to_string(size) + " bytes is not a whole number of 16-byte (x, y, z, reflectance) records");
    check_point_count(static_cast<std::size_t>(size / 16), path, 0, "size");
  };
  std::string bytes = read_input_file(path, kMaxInputFileBytes, kTextHeadBytes, check_head);
  if (is_gzip(bytes)) bytes = gunzip(bytes, path);
  const std::string_view v = bytes;
  if (v.substr(0, 4) == "ply\n" || v.substr(0, 5) == "ply\r\n") return parse_ply(v, path);
  std::string stem_ext = ext;
  if (ext == ".gz") stem_ext = lower_extension(path.substr(0, path.size() - 3));
  if (stem_ext == ".pcd" || v.substr(0, 6) == "# .PCD" || v.substr(0, 7) == "VERSION") return parse_pcd(v, path);
  if (stem_ext == ".bin") return parse_kitti_bin(v, path);
  if (stem_ext == ".ply") return parse_ply(v, path);
  throw Error("not a point cloud: expected a PCD or PLY header, or a KITTI .bin frame", path);
}

std::string format_point_cloud(std::span<const Vec3> points, PointCloudFormat format, PointCloudEncoding encoding) {
  std::string out;
  const bool binary = encoding == PointCloudEncoding::Binary;
  out.reserve(256 + points.size() * (binary ? 12 : 36));
  const std::string n = std::to_string(points.size());
  if (format == PointCloudFormat::Ply) {
    out += std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
           " 1.0\ncomment starnav point cloud, metres\nelement vertex " + n +
           "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  } else {
    out += "# .PCD v0.7 - starnav point cloud, metres\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
           "COUNT 1 1 1\nWIDTH " + n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA " +
           (binary ? "binary" : "ascii") + "\n";
  }
  if (binary) {
    static_assert(std::endian::native == std::endian::little, "the binary writers assume a little-endian host");
    for (const Vec3& p : points) {
      const std::array<float, 3> v{static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
      out.append(reinterpret_cast<const char*>(v.data()), sizeof v);
    }
    return out;
  }
  char buf[96];
  for (const Vec3& p : points) {
    // Keeps every line inside the buffer and the file readable.
    if (!(p.cwiseAbs().maxCoeff() <= kMaxCoordinateM)) throw Error("a point coordinate is not finite or beyond 1e9 m", "", 0, "points");
    const int len = std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f\n", p.x(), p.y(), p.z());
    out.append(buf, static_cast<std::size_t>(len));
  }
  return out;
}

void write_point_cloud(const std::string& path, std::span<const Vec3> points, PointCloudFormat format,
                       PointCloudEncoding encoding) {
  std::string bytes;
  try {
    bytes = format_point_cloud(points, format, encoding);
  } catch (const Error& e) {
    throw e.with_file(path);
  }
  write_file_bytes(path, bytes);
}

}  // namespace starnav
