#include "starnav/io/ros_map.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>

#include "starnav/core/error.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/image.hpp"
#include "starnav/io/yaml_document.hpp"

namespace starnav {

namespace {

namespace fs = std::filesystem;

// GraphicsMagick as ROS 2 uses it (Q16): every sample becomes a 16-bit "quantum"; 8-bit v -> 257 v.
constexpr double kMaxQuantum = 65535.0;

const char* mode_name(RosMapMode mode) {
  switch (mode) {
    case RosMapMode::Trinary:
      return "trinary";
    case RosMapMode::Scale:
      return "scale";
    case RosMapMode::Raw:
      return "raw";
  }
  return "trinary";
}

// The 1-based line of `key` in a mapping (0 when absent). Errors point at the key, since a null
// value's own mark is where the next token starts.
int key_line(const YAML::Node& doc, const char* key) {
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) {
      const YAML::Mark mark = it->first.Mark();
      return mark.is_null() ? 0 : mark.line + 1;
    }
  }
  return 0;
}

bool is_yaml_infinity_or_nan(std::string_view text) {
  std::string lower;
  for (const char c : text) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return lower == ".inf" || lower == "+.inf" || lower == "-.inf" || lower == ".nan";
}

// Reads the YAML keys one by one so that every fault names its key (yaml-cpp's own conversions
// throw "bad conversion" without saying which).
class YamlFields {
 public:
  YamlFields(const YAML::Node& doc, const std::string& source) : doc_(doc), source_(source) {}

  YAML::Node scalar(const char* key) const {
    const YAML::Node node = doc_[key];
    if (!node.IsDefined()) throw Error("required key is missing", source_, 0, key);
    if (node.IsNull()) throw Error("has no value", source_, line(key), key);
    if (!node.IsScalar()) throw Error("must be a single value, not a list or map", source_, line(key), key);
    return node;
  }

  double number(const char* key) const { return parse_number(scalar(key), key); }

  double parse_number(const YAML::Node& node, const char* key) const {
    std::string_view text = node.Scalar();
    if (is_yaml_infinity_or_nan(text)) throw Error("must be finite, got " + node.Scalar(), source_, line(key), key);
    const std::optional<double> value = parse_real_text(text);
    if (!value) throw Error("expected a number, found '" + one_line(node.Scalar()) + "'", source_, line(key), key);
    return *value;
  }

  int line(const char* key) const { return key_line(doc_, key); }

  const std::string& source() const { return source_; }
  const YAML::Node& doc() const { return doc_; }

 private:
  const YAML::Node& doc_;
  const std::string& source_;
};

// Shortest decimal text that reads back as exactly `v`.
std::string shortest(double v) {
  char buf[64];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, ptr) : std::to_string(v);
}

// A YAML scalar for a file name: plain when that is unambiguous, else double-quoted.
std::string yaml_string(const std::string& s) {
  bool plain = !s.empty() && s.front() != '-';
  for (const char c : s) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                      c == '_' || c == '-' || c == '/';
    if (!safe) plain = false;
  }
  if (plain) return s;
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out.push_back('\\');
    out.push_back(c);
  }
  return out + "\"";
}

void check_thresholds(double free_thresh, double occupied_thresh, const std::string& source, int free_line = 0,
                      int occupied_line = 0) {
  if (!(free_thresh >= 0.0 && free_thresh <= 1.0))
    throw Error("must be in 0..1, got " + shortest(free_thresh), source, free_line, "free_thresh");
  if (!(occupied_thresh >= 0.0 && occupied_thresh <= 1.0))
    throw Error("must be in 0..1, got " + shortest(occupied_thresh), source, occupied_line, "occupied_thresh");
  if (!(free_thresh < occupied_thresh))
    throw Error(
        "free_thresh (" + shortest(free_thresh) + ") must be below occupied_thresh (" + shortest(occupied_thresh) + ")",
        source, free_line, "free_thresh");
}

// The 16-bit quantum GraphicsMagick gives a sample of an image with this maxval (PNM readers
// scale any maxval to the quantum range with rounding; 8 and 16 bit are exact).
std::uint32_t to_quantum(std::uint16_t v, int max_value) {
  if (max_value == 65535) return v;
  return static_cast<std::uint32_t>(std::floor(static_cast<double>(v) * kMaxQuantum / max_value + 0.5));
}

// GraphicsMagick's quantum -> 8-bit sample when writing an 8-bit file.
std::uint16_t quantum_to_byte(std::uint32_t q) { return static_cast<std::uint16_t>((q + 128u) / 257u); }

// GraphicsMagick's ColorGray(shade): quantum = trunc(shade * MaxRGB).
std::uint32_t shade_to_quantum(double shade) { return static_cast<std::uint32_t>(shade * kMaxQuantum); }

}  // namespace

RosMapMetadata parse_ros_map_yaml(std::string_view yaml_text, const std::string& source) {
  const YAML::Node doc = load_yaml_document(yaml_text, source);
  if (!doc.IsDefined() || doc.IsNull()) throw Error("empty YAML file: expected map_server metadata", source);
  if (!doc.IsMap()) throw Error("YAML top level must be a mapping of keys (image, resolution, ...)", source, 1);

  RosMapMetadata md;
  try {
    const YAML::Node& cdoc = doc;  // const access never inserts keys
    const YamlFields fields(cdoc, source);

    const YAML::Node image = fields.scalar("image");
    md.image = image.Scalar();
    if (md.image.empty()) throw Error("is empty", source, fields.line("image"), "image");

    md.resolution = fields.number("resolution");
    if (!(md.resolution > 0.0))
      throw Error("must be positive, got " + shortest(md.resolution), source, fields.line("resolution"), "resolution");

    const YAML::Node origin = cdoc["origin"];
    if (!origin.IsDefined()) throw Error("required key is missing", source, 0, "origin");
    if (!origin.IsSequence() || origin.size() != 3)
      throw Error("must be a list of 3 numbers [x, y, yaw]", source, fields.line("origin"), "origin");
    double xyz[3];
    for (std::size_t i = 0; i < 3; ++i) {
      if (!origin[i].IsScalar())
        throw Error("must be a list of 3 numbers [x, y, yaw]", source, fields.line("origin"), "origin");
      xyz[i] = fields.parse_number(origin[i], "origin");
    }
    md.origin = Pose2(xyz[0], xyz[1], xyz[2]);

    // ROS writes `negate: 0`; hand-written files say true/false. Both mean the same.
    const YAML::Node negate = fields.scalar("negate");
    const std::string& negate_text = negate.Scalar();
    if (negate_text == "0") {
      md.negate = false;
    } else if (negate_text == "1") {
      md.negate = true;
    } else {
      bool b = false;
      if (!YAML::convert<bool>::decode(negate, b))
        throw Error("must be 0, 1, true or false, found '" + one_line(negate_text) + "'", source, fields.line("negate"),
                    "negate");
      md.negate = b;
    }

    md.occupied_thresh = fields.number("occupied_thresh");
    md.free_thresh = fields.number("free_thresh");
    check_thresholds(md.free_thresh, md.occupied_thresh, source, fields.line("free_thresh"),
                     fields.line("occupied_thresh"));

    const YAML::Node mode = cdoc["mode"];
    if (!mode.IsDefined()) {
      md.mode = RosMapMode::Trinary;  // map_server's default
    } else {
      const std::string& m = fields.scalar("mode").Scalar();
      if (m == "trinary")
        md.mode = RosMapMode::Trinary;
      else if (m == "scale")
        md.mode = RosMapMode::Scale;
      else if (m == "raw")
        md.mode = RosMapMode::Raw;
      else
        throw Error("must be trinary, scale or raw, found '" + one_line(m) + "'", source, fields.line("mode"), "mode");
    }
  } catch (const YAML::Exception& e) {
    throw Error("invalid YAML: " + one_line(e.msg), source, e.mark.is_null() ? 0 : e.mark.line + 1);
  }
  return md;
}

OccupancyGrid ros_map_from_image(const RasterImage& image, const RosMapMetadata& md, const std::string& source) {
  check_thresholds(md.free_thresh, md.occupied_thresh, source);
  GridGeometry g;
  g.width = image.width;
  g.height = image.height;
  g.resolution = md.resolution;
  g.origin = md.origin;
  OccupancyGrid grid;
  try {
    grid = OccupancyGrid(g, kUnknownOccupancy);
  } catch (const Error& e) {
    throw e.with_file(source);
  }
  const int c = image.channels;
  if (c < 1 || c > 4 || image.samples.size() != grid.cell_count() * static_cast<std::size_t>(c))
    throw Error("image has an inconsistent number of samples", source);
  const bool has_alpha = c == 2 || c == 4;  // GraphicsMagick's matte()

  for (int row = 0; row < image.height; ++row) {
    const int iy = image.height - 1 - row;  // image top row is the map's last row
    for (int x = 0; x < image.width; ++x) {
      const std::uint16_t* px = &image.samples[(static_cast<std::size_t>(row) * image.width + x) * c];
      std::uint32_t red, green, blue, alpha = static_cast<std::uint32_t>(kMaxQuantum);
      if (c <= 2) {
        red = green = blue = to_quantum(px[0], image.max_value);
      } else {
        red = to_quantum(px[0], image.max_value);
        green = to_quantum(px[1], image.max_value);
        blue = to_quantum(px[2], image.max_value);
      }
      if (has_alpha) alpha = to_quantum(px[c - 1], image.max_value);

      // map_server: average the colour channels (and, in trinary mode only, the alpha).
      double sum = static_cast<double>(red) + static_cast<double>(green) + static_cast<double>(blue);
      double count = 3.0;
      if (md.mode == RosMapMode::Trinary && has_alpha) {
        sum += static_cast<double>(alpha);
        count = 4.0;
      }
      const double shade = (sum / count) / kMaxQuantum;
      const double occ = md.negate ? shade : 1.0 - shade;

      std::int8_t cell = kUnknownOccupancy;
      switch (md.mode) {
        case RosMapMode::Trinary:
          if (md.occupied_thresh < occ)
            cell = kOccupiedOccupancy;
          else if (occ < md.free_thresh)
            cell = kFreeOccupancy;
          else
            cell = kUnknownOccupancy;
          break;
        case RosMapMode::Scale:
          if (has_alpha && alpha != static_cast<std::uint32_t>(kMaxQuantum))
            cell = kUnknownOccupancy;  // not opaque
          else if (md.occupied_thresh < occ)
            cell = kOccupiedOccupancy;
          else if (occ < md.free_thresh)
            cell = kFreeOccupancy;
          else
            cell = static_cast<std::int8_t>(
                std::rint((occ - md.free_thresh) / (md.occupied_thresh - md.free_thresh) * 100.0));
          break;
        case RosMapMode::Raw: {
          // Raw ignores negate and alpha: the grey level is the value.
          const double value = std::round(shade * 255.0);
          cell = (value >= 0.0 && value <= 100.0) ? static_cast<std::int8_t>(value) : kUnknownOccupancy;
          break;
        }
      }
      grid(x, iy) = cell;
    }
  }
  return grid;
}

std::string ros_map_image_path(const std::string& yaml_path, const std::string& image) {
  if (!image.empty() && image.front() == '/') return image;
  const fs::path folder = fs::path(yaml_path).parent_path();
  return folder.empty() ? image : (folder / image).string();
}

OccupancyGrid read_ros_map(const std::string& yaml_path, RosMapMetadata* metadata_out) {
  const RosMapMetadata md = parse_ros_map_yaml(read_yaml_file(yaml_path), yaml_path);
  const std::string image_path = ros_map_image_path(yaml_path, md.image);
  std::error_code ec;
  if (!fs::exists(image_path, ec)) throw Error("image file '" + image_path + "' not found", yaml_path, 0, "image");
  const RasterImage image = read_raster_image(image_path);
  OccupancyGrid grid = ros_map_from_image(image, md, image_path);
  if (metadata_out) *metadata_out = md;
  return grid;
}

RasterImage ros_map_to_image(const OccupancyGrid& grid, const RosMapMetadata& md) {
  RasterImage image;
  image.width = grid.width();
  image.height = grid.height();
  image.max_value = 255;
  image.channels = md.mode == RosMapMode::Scale ? 4 : 1;  // scale needs alpha for unknown cells
  image.samples.assign(grid.cell_count() * static_cast<std::size_t>(image.channels), 0);
  // map_saver compares cell values with the thresholds in percent, rounded.
  const int free_percent = static_cast<int>(std::rint(md.free_thresh * 100.0));
  const int occupied_percent = static_cast<int>(std::rint(md.occupied_thresh * 100.0));
  const bool invert = md.negate && md.mode != RosMapMode::Raw;  // raw mode never negates

  for (int row = 0; row < image.height; ++row) {
    // Index grids (MovingAI) keep their top row first already; metric grids are bottom-up.
    const int iy = grid.geometry().y_down ? row : image.height - 1 - row;
    for (int x = 0; x < image.width; ++x) {
      const int v = grid(x, iy);
      const bool unknown = v < 0 || v > 100;
      std::uint16_t grey = 0;
      std::uint16_t alpha = 255;
      switch (md.mode) {
        case RosMapMode::Trinary:
          if (unknown)
            grey = 205;
          else if (v <= free_percent)
            grey = 254;
          else if (v >= occupied_percent)
            grey = 0;
          else
            grey = 205;
          break;
        case RosMapMode::Scale:
          if (unknown) {
            grey = quantum_to_byte(shade_to_quantum(0.5));
            alpha = 0;
          } else {
            grey = quantum_to_byte(shade_to_quantum((100.0 - v) / 100.0));
          }
          break;
        case RosMapMode::Raw:
          grey = unknown ? 255 : quantum_to_byte(shade_to_quantum(v / 255.0));
          break;
      }
      if (invert) grey = static_cast<std::uint16_t>(255 - grey);
      std::uint16_t* px = &image.samples[(static_cast<std::size_t>(row) * image.width + x) * image.channels];
      if (image.channels == 1) {
        px[0] = grey;
      } else {
        px[0] = px[1] = px[2] = grey;
        px[3] = alpha;
      }
    }
  }
  return image;
}

void write_ros_map(const OccupancyGrid& grid, const std::string& yaml_path, RosMapMetadata metadata) {
  if (grid.width() <= 0 || grid.height() <= 0) throw Error("cannot write an empty map", yaml_path);
  check_thresholds(metadata.free_thresh, metadata.occupied_thresh, yaml_path);
  const bool scale = metadata.mode == RosMapMode::Scale;
  if (metadata.image.empty()) metadata.image = fs::path(yaml_path).stem().string() + (scale ? ".png" : ".pgm");
  for (const char ch : metadata.image)
    if (static_cast<unsigned char>(ch) < 0x20)
      throw Error("image name contains a control character", yaml_path, 0, "image");
  const std::string extension = lower_extension(metadata.image);
  if (extension != ".pgm" && extension != ".png")
    throw Error("image must be a .pgm or .png file, got '" + metadata.image + "'", yaml_path, 0, "image");
  if (scale && extension == ".pgm")
    throw Error("scale mode marks unknown cells by transparency: use a .png image", yaml_path, 0, "image");

  const RasterImage image = ros_map_to_image(grid, metadata);
  const std::string image_path = ros_map_image_path(yaml_path, metadata.image);
  if (extension == ".png") {
    write_png_raster(image, image_path);
  } else {
    GrayImage gray;
    gray.width = image.width;
    gray.height = image.height;
    gray.max_value = 255;
    gray.pixels = image.samples;
    write_pgm(gray, image_path);
  }

  // Key order and values as map_saver writes them; numbers in full (shortest exact) precision.
  const Pose2& origin = grid.origin();
  std::string yaml;
  yaml += "image: " + yaml_string(metadata.image) + "\n";
  yaml += std::string("mode: ") + mode_name(metadata.mode) + "\n";
  yaml += "resolution: " + shortest(grid.resolution()) + "\n";
  yaml += "origin: [" + shortest(origin.x) + ", " + shortest(origin.y) + ", " + shortest(origin.yaw) + "]\n";
  yaml += std::string("negate: ") + (metadata.negate ? "1" : "0") + "\n";
  yaml += "occupied_thresh: " + shortest(metadata.occupied_thresh) + "\n";
  yaml += "free_thresh: " + shortest(metadata.free_thresh) + "\n";
  write_file_bytes(yaml_path, yaml);
}

}  // namespace starnav
