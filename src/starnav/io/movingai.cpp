#include "starnav/io/movingai.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/text_lines.hpp"
#include "starnav/io/file_bytes.hpp"

namespace starnav {

namespace {


// Splits text into lines on LF, dropping one trailing CR per line (CRLF files). A final line
// without a newline is kept; the empty piece after a final newline is not a line.
class MovingAiLines {
 public:
  explicit MovingAiLines(std::string_view text) : text_(without_utf8_bom(text)) {}

  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end == std::string_view::npos ? text_.size() : end + 1;
    ++line_number_;
    return true;
  }
  int line_number() const { return line_number_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_number_ = 0;
};

bool is_blank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

bool blank_line(std::string_view line) { return trim_blanks(line).empty(); }

// A plain non-negative decimal integer (digits only) that fits an int.
bool parse_non_negative_int(std::string_view text, int& value) {
  if (text.empty()) return false;
  for (const char c : text)
    if (c < '0' || c > '9') return false;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && ptr == text.data() + text.size();
}

// "keyword value" with one or more blanks between; false when the keyword differs.
bool split_header(std::string_view line, std::string_view keyword, std::string_view& value) {
  line = trim_blanks(line);
  if (line.substr(0, keyword.size()) != keyword) return false;
  const std::string_view rest = line.substr(keyword.size());
  if (rest.empty() || !is_blank(rest.front())) return false;
  value = trim_blanks(rest);
  return true;
}

int header_dimension(MovingAiLines& lines, std::string_view keyword, const std::string& source) {
  const std::string field(keyword);
  std::string_view line;
  if (!lines.next(line))
    throw Error("file ends before the '" + field + "' line", source, lines.line_number() + 1, field);
  std::string_view value;
  if (!split_header(line, keyword, value))
    throw Error("expected '" + field + " N', found '" + printable(line, 40) + "'", source, lines.line_number(), field);
  int n = 0;
  if (!parse_non_negative_int(value, n))
    throw Error("expected a positive integer, found '" + printable(value, 40) + "'", source, lines.line_number(), field);
  if (n <= 0) throw Error("must be positive, got " + std::to_string(n), source, lines.line_number(), field);
  return n;
}

std::vector<std::string_view> split_scen_fields(std::string_view line, bool on_tabs) {
  std::vector<std::string_view> fields;
  if (on_tabs) {
    std::size_t start = 0;
    while (true) {
      const std::size_t tab = line.find('\t', start);
      if (tab == std::string_view::npos) {
        fields.push_back(line.substr(start));
        break;
      }
      fields.push_back(line.substr(start, tab - start));
      start = tab + 1;
    }
  } else {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_blank(line[i])) ++i;
      if (i >= line.size()) break;
      const std::size_t start = i;
      while (i < line.size() && !is_blank(line[i])) ++i;
      fields.push_back(line.substr(start, i - start));
    }
  }
  return fields;
}

// A length with no text of its own: 8 decimals, as the newer MovingAI files write them.
std::string format_length(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.8f", v);
  return buf;
}

bool parse_length(std::string_view text, double& value) {
  if (text.empty()) return false;
  // Only plain decimals: digits, at most one point, optional exponent (no sign, inf or nan).
  for (const char c : text)
    if (!((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-')) return false;
  if (text.front() < '0' || text.front() > '9') {
    if (text.front() != '.') return false;
  }
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && ptr == text.data() + text.size() && std::isfinite(value) && value >= 0.0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// .map

OccupancyGrid MovingAiMap::to_occupancy() const {
  if (width <= 0 || height <= 0 || cells.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw Error("MovingAI map is inconsistent: " + std::to_string(width) + " x " + std::to_string(height) + " with " +
                std::to_string(cells.size()) + " cells");
  GridGeometry g;
  g.width = width;
  g.height = height;
  g.resolution = 1.0;
  g.y_down = true;
  OccupancyGrid grid(g, kFreeOccupancy);
  auto data = grid.data();
  for (std::size_t i = 0; i < cells.size(); ++i) data[i] = passable(cells[i]) ? kFreeOccupancy : kOccupiedOccupancy;
  return grid;
}

MovingAiMap MovingAiMap::from_occupancy(const OccupancyGrid& grid, const OccupancyThresholds& t) {
  MovingAiMap map;
  map.width = grid.width();
  map.height = grid.height();
  map.cells.resize(grid.cell_count());
  const bool y_down = grid.geometry().y_down;
  for (int y = 0; y < map.height; ++y) {
    // MovingAI rows run top first; a metric grid's row iy = 0 is the bottom one.
    const int iy = y_down ? y : map.height - 1 - y;
    for (int x = 0; x < map.width; ++x)
      map.cells[static_cast<std::size_t>(y) * map.width + x] = grid.state(x, iy, t) == CellState::Free ? '.' : '@';
  }
  return map;
}

namespace {

// The four header lines (type, height, width, map) into `map`.
void parse_movingai_header(MovingAiLines& lines, MovingAiMap& map, const std::string& source) {
  std::string_view line;
  if (!lines.next(line)) throw Error("empty file: expected 'type octile'", source, 1, "type");
  std::string_view type;
  // One visible-ASCII word ("octile" in every known file), so that it is written back unchanged.
  if (!split_header(line, "type", type) || type.empty() ||
      !std::all_of(type.begin(), type.end(), [](char c) { return c > 0x20 && c < 0x7f; }))
    throw Error("expected 'type octile', found '" + printable(line, 40) + "'", source, lines.line_number(), "type");
  map.type = std::string(type);

  map.height = header_dimension(lines, "height", source);
  const int height_line = lines.line_number();
  map.width = header_dimension(lines, "width", source);
  if (static_cast<std::uint64_t>(map.width) * static_cast<std::uint64_t>(map.height) > kMaxGridCells)
    throw Error("map too large: " + std::to_string(map.width) + " x " + std::to_string(map.height) +
                    " cells (at most 2^31 - 1)",
                source, height_line, "height");

  if (!lines.next(line)) throw Error("file ends before the 'map' line", source, lines.line_number() + 1, "map");
  if (trim_blanks(line) != "map")
    throw Error("expected 'map', found '" + printable(line, 40) + "'", source, lines.line_number(), "map");

}

}  // namespace

MovingAiMap parse_movingai_map(std::string_view text, const std::string& source) {
  MovingAiLines lines(text);
  std::string_view line;
  MovingAiMap map;
  parse_movingai_header(lines, map, source);

  // Grows with the rows actually present, so a tiny file claiming a huge map allocates little.
  const std::size_t cell_count = static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height);
  map.cells.reserve(std::min(cell_count, text.size()));
  for (int row = 0; row < map.height; ++row) {
    if (!lines.next(line))
      throw Error("file ends after " + std::to_string(row) + " of " + std::to_string(map.height) + " map rows", source,
                  lines.line_number() + 1, "map");
    if (line.size() != static_cast<std::size_t>(map.width))
      throw Error("map row " + std::to_string(row) + " has " + std::to_string(line.size()) + " characters, width is " +
                      std::to_string(map.width),
                  source, lines.line_number(), "map");
    for (std::size_t x = 0; x < line.size(); ++x) {
      if (!MovingAiMap::valid_char(line[x]))
        throw Error("invalid terrain character '" + printable(line.substr(x, 1)) + "' at column " +
                        std::to_string(x + 1) + " (allowed: . G S @ O T W)",
                    source, lines.line_number(), "map");
    }
    map.cells.insert(map.cells.end(), line.begin(), line.end());
  }
  while (lines.next(line)) {
    if (!blank_line(line))
      throw Error("unexpected text after the " + std::to_string(map.height) + " map rows: '" + printable(line, 40) + "'",
                  source, lines.line_number(), "map");
  }
  return map;
}

MovingAiMap read_movingai_map(const std::string& path) {
  const InputFileScope reading_path(path);
  // The header decides before the body is read: a file that is not a map, or holds more bytes
  // than its rows (width + 2 with CRLF each) and a header and trailing blank lines could take.
  const std::size_t head_bytes = 64 * 1024;
  const auto check_head = [&](std::string_view head, std::uint64_t size) {
    MovingAiLines lines(head);
    MovingAiMap map;
    parse_movingai_header(lines, map, path);
    const std::uint64_t most = head_bytes + std::uint64_t{1} * 1024 * 1024 +
                               static_cast<std::uint64_t>(map.height) * (static_cast<std::uint64_t>(map.width) + 2);
    if (size > most)
      throw Error("is " + std::to_string(size) + " bytes, more than a " + std::to_string(map.width) + " x " +
                      std::to_string(map.height) + " map takes (" + std::to_string(most) + ")",
                  path, 0, "map");
  };
  return parse_movingai_map(read_input_file(path, kMaxInputFileBytes, head_bytes, check_head), path);
}

std::string format_movingai_map(const MovingAiMap& map) {
  const std::size_t cell_count =
      static_cast<std::size_t>(std::max(map.width, 0)) * static_cast<std::size_t>(std::max(map.height, 0));
  if (map.width <= 0 || map.height <= 0 || map.cells.size() != cell_count)
    throw Error("MovingAI map is inconsistent: " + std::to_string(map.width) + " x " + std::to_string(map.height) +
                " with " + std::to_string(map.cells.size()) + " cells");
  std::string out = "type " + map.type + "\nheight " + std::to_string(map.height) + "\nwidth " +
                    std::to_string(map.width) + "\nmap\n";
  out.reserve(out.size() + cell_count + static_cast<std::size_t>(map.height));
  for (int y = 0; y < map.height; ++y) {
    out.append(map.cells.data() + static_cast<std::size_t>(y) * map.width, static_cast<std::size_t>(map.width));
    out.push_back('\n');
  }
  return out;
}

void write_movingai_map(const MovingAiMap& map, const std::string& path) {
  std::string text;
  try {
    text = format_movingai_map(map);
  } catch (const Error& e) {
    throw e.with_file(path);
  }
  write_file_bytes(path, text);
}

// ---------------------------------------------------------------------------------------------
// .scen

MovingAiScenario parse_movingai_scenario(std::string_view text, const std::string& source) {
  MovingAiLines lines(text);
  std::string_view line;
  MovingAiScenario scen;

  if (!lines.next(line)) throw Error("empty file: expected 'version 1'", source, 1, "version");
  std::string_view version;
  if (!split_header(line, "version", version) || (version != "1" && version != "1.0"))
    throw Error("expected 'version 1' or 'version 1.0', found '" + printable(line, 40) + "'", source, 1, "version");
  scen.version = std::string(version);

  bool separator_known = false;
  int first_blank_line = 0;  // blank lines are allowed only at the end of the file
  while (lines.next(line)) {
    if (blank_line(line)) {
      if (first_blank_line == 0) first_blank_line = lines.line_number();
      ++scen.trailing_blank_lines;
      continue;
    }
    const int n = lines.line_number();
    if (first_blank_line != 0)
      throw Error("blank line " + std::to_string(first_blank_line) + " inside the problem list", source, n);
    if (!separator_known) {
      // hog2 and newer files separate fields by TABs; bg512 "version 1.0" files by spaces.
      scen.space_separated = line.find('\t') == std::string_view::npos;
      separator_known = true;
    }
    const std::vector<std::string_view> fields = split_scen_fields(line, !scen.space_separated);
    if (fields.size() != 9)
      throw Error("expected 9 " + std::string(scen.space_separated ? "space" : "tab") +
                      "-separated fields (bucket map width height start_x start_y goal_x goal_y length), found " +
                      std::to_string(fields.size()),
                  source, n);
    ScenarioEntry e;
    auto int_field = [&](std::size_t i, const char* name, int& out) {
      if (!parse_non_negative_int(fields[i], out))
        throw Error("expected a non-negative integer, found '" + printable(fields[i], 40) + "'", source, n, name);
    };
    int_field(0, "bucket", e.bucket);
    e.map = std::string(fields[1]);
    if (e.map.empty()) throw Error("empty map name", source, n, "map");
    int_field(2, "width", e.map_width);
    int_field(3, "height", e.map_height);
    int_field(4, "start_x", e.start_x);
    int_field(5, "start_y", e.start_y);
    int_field(6, "goal_x", e.goal_x);
    int_field(7, "goal_y", e.goal_y);
    if (!parse_length(fields[8], e.optimal_length))
      throw Error("expected a non-negative decimal length, found '" + printable(fields[8], 40) + "'", source, n,
                  "optimal_length");
    e.optimal_length_text = std::string(fields[8]);
    if (e.map_width <= 0) throw Error("map width must be positive", source, n, "width");
    if (e.map_height <= 0) throw Error("map height must be positive", source, n, "height");
    if (e.start_x >= e.map_width)
      throw Error("start x " + std::to_string(e.start_x) + " outside the map width " + std::to_string(e.map_width),
                  source, n, "start_x");
    if (e.start_y >= e.map_height)
      throw Error("start y " + std::to_string(e.start_y) + " outside the map height " + std::to_string(e.map_height),
                  source, n, "start_y");
    if (e.goal_x >= e.map_width)
      throw Error("goal x " + std::to_string(e.goal_x) + " outside the map width " + std::to_string(e.map_width),
                  source, n, "goal_x");
    if (e.goal_y >= e.map_height)
      throw Error("goal y " + std::to_string(e.goal_y) + " outside the map height " + std::to_string(e.map_height),
                  source, n, "goal_y");
    scen.entries.push_back(std::move(e));
  }
  return scen;
}

void check_scenario_map_size(const MovingAiScenario& scen, const std::string& scen_path, int map_width, int map_height,
                             const std::string& map_name) {
  for (std::size_t k = 0; k < scen.entries.size(); ++k) {
    const ScenarioEntry& e = scen.entries[k];
    if (e.map_width != map_width || e.map_height != map_height)
      throw Error("problem " + std::to_string(k + 1) + " is for a " + std::to_string(e.map_width) + " x " +
                      std::to_string(e.map_height) + " map, but " + map_name + " is " + std::to_string(map_width) + " x " +
                      std::to_string(map_height),
                  scen_path, 0, "width/height");
  }
}

MovingAiScenario read_movingai_scenario(const std::string& path) {
  const InputFileScope reading_path(path);
  // Its first line decides before the rest is read.
  const auto check_head = [&](std::string_view head, std::uint64_t) {
    MovingAiLines lines(head);
    std::string_view line, version;
    if (!lines.next(line) || !split_header(line, "version", version) || (version != "1" && version != "1.0"))
      parse_movingai_scenario(head.substr(0, std::min(head.find('\n'), head.size())), path);  // its error line
  };
  return parse_movingai_scenario(read_input_file(path, kMaxInputFileBytes, 4096, check_head), path);
}

std::string format_movingai_scenario(const MovingAiScenario& scen) {
  const char sep = scen.space_separated ? ' ' : '\t';
  std::string out = "version " + scen.version + "\n";
  for (const ScenarioEntry& e : scen.entries) {
    // The length as read, unless the number was changed since.
    double as_read = 0.0;
    const bool text_matches = parse_length(e.optimal_length_text, as_read) && as_read == e.optimal_length;
    const std::string length = text_matches ? e.optimal_length_text : format_length(e.optimal_length);
    out += std::to_string(e.bucket);
    out += sep;
    out += e.map;
    for (const int v : {e.map_width, e.map_height, e.start_x, e.start_y, e.goal_x, e.goal_y}) {
      out += sep;
      out += std::to_string(v);
    }
    out += sep;
    out += length;
    out += '\n';
  }
  out.append(static_cast<std::size_t>(std::max(scen.trailing_blank_lines, 0)), '\n');
  return out;
}

void write_movingai_scenario(const MovingAiScenario& scen, const std::string& path) {
  write_file_bytes(path, format_movingai_scenario(scen));
}

}  // namespace starnav
