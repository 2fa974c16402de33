#include "cli_util.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cctype>
#include <filesystem>

#include "starnav/core/error.hpp"

namespace starnav::cli {

namespace {
bool parse_double(const std::string& s, double& out) {
  if (s.empty()) return false;
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  out = std::strtod(begin, &end);
  return errno == 0 && end == begin + s.size() && std::isfinite(out);
}
}  // namespace

Vec2 parse_xy(const std::string& text, const std::string& flag) {
  const auto comma = text.find(',');
  double x = 0, y = 0;
  if (comma == std::string::npos || !parse_double(text.substr(0, comma), x) ||
      !parse_double(text.substr(comma + 1), y))
    throw Error("expected X,Y (two numbers), got '" + text + "'", {}, 0, flag);
  return {x, y};
}

void check_output_path(const std::string& path, bool force, const std::string& flag) {
  namespace fs = std::filesystem;
  if (path.empty()) throw Error("empty output path", {}, 0, flag);
  if (fs::exists(path) && !force) throw Error("exists already (use --force to overwrite)", path, 0, flag);
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent)) throw Error("folder does not exist", path, 0, flag);
}

MapFormat output_map_format(const std::string& path, bool elevation) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".yaml" || ext == ".yml") return elevation ? MapFormat::ElevationYaml : MapFormat::RosMap;
  if (ext == ".map") return MapFormat::MovingAi;
  if (ext == ".asc") return MapFormat::Asc;
  if (ext == ".csv") return MapFormat::Csv;
  if (ext == ".raw" || ext == ".r16") return MapFormat::UnityRaw;
  if (ext == ".tif" || ext == ".tiff") return MapFormat::GeoTiff;
  throw Error("unknown output format (expected .map, .yaml, .asc, .csv, .raw)", path);
}

bool picture_is_png(const std::string& path, const std::string& flag) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png") return true;
  if (ext == ".svg") return false;
  throw Error("picture must end in .svg or .png", path, 0, flag);
}

}  // namespace starnav::cli
