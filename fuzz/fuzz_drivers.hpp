#pragma once
// What each fuzz target does with one input, shared by the libFuzzer targets (fuzz/fuzz_*.cpp)
// and the regression test that replays fuzz/crashers/ and fuzz/corpus/ under g++
// (tests/io/test_fuzz_regressions.cpp).
//
// starnav::Error is the expected outcome for bad input and is swallowed here. Any other exception
// escapes, and so does InvariantViolation when a parser accepts an input but returns something
// inconsistent (cell count != width * height, a documented round trip that does not hold, ...).
//
// Targets that read files (fuzz_elevation_yaml, fuzz_unity_raw; fuzz_ros_yaml with an image and
// fuzz_asc with a .prj)
// take two files in one input: the YAML text, then the line kFileSeparator, then the bytes of the
// second file, which is written to a per-process scratch folder under the name the seeds use.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/io/elevation_io.hpp"
#include "starnav/io/image.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"

namespace starnav::fuzz {

// A parser accepted an input but broke a promise its header makes.
class InvariantViolation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

inline void require(bool ok, const std::string& what) {
  if (!ok) throw InvariantViolation("fuzz invariant violated: " + what);
}

// Splits "FIRST\n#@@\nSECOND" into its two files; without the separator all of it is the first.
inline constexpr std::string_view kFileSeparator = "\n#@@\n";
inline std::pair<std::string_view, std::string_view> split_files(std::string_view data) {
  const std::size_t at = data.find(kFileSeparator);
  if (at == std::string_view::npos) return {data, {}};
  return {data.substr(0, at), data.substr(at + kFileSeparator.size())};
}

// A scratch folder for this process, removed at exit: under $STARNAV_FUZZ_TMPDIR, else /dev/shm
// (memory: thousands of small writes a second), else $TMPDIR or /tmp.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::string base = "/tmp";
    std::error_code ec;
    if (const char* env = std::getenv("STARNAV_FUZZ_TMPDIR"); env && *env) base = env;
    else if (::access("/dev/shm", W_OK) == 0 && std::filesystem::is_directory("/dev/shm", ec)) base = "/dev/shm";
    else if (const char* tmp = std::getenv("TMPDIR"); tmp && *tmp) base = tmp;
    std::string templ = base + "/starnav_fuzz_XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (::mkdtemp(buf.data()) == nullptr) throw std::runtime_error("starnav fuzz: mkdtemp failed for " + templ);
    path_ = buf.data();
  }
  ~ScratchFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  std::string write(const std::string& name, std::string_view bytes) const {
    const std::string p = (path_ / name).string();
    // A new file rather than a truncated one: ext4 flushes files that are truncated and rewritten.
    std::error_code ec;
    std::filesystem::remove(p, ec);
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("starnav fuzz: cannot write " + p);
    return p;
  }

 private:
  std::filesystem::path path_;
};

inline const ScratchFolder& scratch() {
  static const ScratchFolder folder;
  return folder;
}

// --- invariants shared by several targets -------------------------------------------------

inline bool same_double(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b));
}

inline void check_geometry(const GridGeometry& g, const char* what) {
  const std::string w = what;
  require(g.width > 0 && g.height > 0, w + ": non-positive size accepted");
  require(std::isfinite(g.resolution) && g.resolution > 0, w + ": bad resolution accepted");
  require(std::isfinite(g.origin.x) && std::isfinite(g.origin.y) && std::isfinite(g.origin.yaw),
          w + ": non-finite origin accepted");
}

inline void check_occupancy(const OccupancyGrid& grid) {
  check_geometry(grid.geometry(), "occupancy grid");
  require(grid.cell_count() == grid.geometry().cell_count(), "occupancy grid: cell count != width * height");
  for (const std::int8_t v : grid.data()) require(v >= -1 && v <= 100, "occupancy grid: value outside -1..100");
}

inline void check_elevation(const ElevationMap& map) {
  check_geometry(map.geometry(), "elevation map");
  const std::size_t n = map.geometry().cell_count();
  require(map.cell_count() == n && map.min_heights().size() == n && map.max_heights().size() == n &&
              map.observed().size() == n,
          "elevation map: cell count != width * height");
  for (std::size_t i = 0; i < n; ++i) {
    if (!map.observed_at_index(i)) continue;
    const double h = map.heights()[i], lo = map.min_heights()[i], hi = map.max_heights()[i];
    require(std::isfinite(h) && std::isfinite(lo) && std::isfinite(hi), "elevation map: non-finite height stored");
    require(lo <= h && h <= hi, "elevation map: height outside its min..max");
  }
  (void)map.height_range();
}

inline void check_image(const GrayImage& img) {
  require(img.width > 0 && img.height > 0, "image: non-positive size accepted");
  require(img.max_value >= 1 && img.max_value <= 65535, "image: max_value outside 1..65535");
  require(img.channels >= 1 && img.channels <= 4, "image: channels outside 1..4");
  const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  require(img.pixels.size() == n, "image: pixel count != width * height");
  require(img.alpha.empty() || img.alpha.size() == n, "image: alpha count != width * height");
  (void)img.at(img.width - 1, img.height - 1);
}

// --- one function per target ----------------------------------------------------------------

inline void fuzz_movingai_map(std::string_view data) {
  MovingAiMap map;
  try {
    map = parse_movingai_map(data, "fuzz.map");
  } catch (const Error&) {
    return;
  }
  require(map.width > 0 && map.height > 0, "movingai map: non-positive size accepted");
  require(map.cells.size() == static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height),
          "movingai map: cell count != width * height");
  // movingai.hpp: every terrain character is kept "so a map round-trips exactly".
  const std::string text = format_movingai_map(map);
  MovingAiMap again;
  try {
    again = parse_movingai_map(text, "fuzz-roundtrip.map");
  } catch (const Error& e) {
    throw InvariantViolation(std::string("movingai map: format_movingai_map output does not parse: ") + e.what());
  }
  require(again == map, "movingai map: parse(format(map)) != map");
  try {
    check_occupancy(map.to_occupancy());
  } catch (const Error&) {
    // A map the parser accepted may still be refused as a grid; that is an error, not a crash.
  }
}

inline bool same_entry(const ScenarioEntry& a, const ScenarioEntry& b) {
  return a.bucket == b.bucket && a.map == b.map && a.map_width == b.map_width && a.map_height == b.map_height &&
         a.start_x == b.start_x && a.start_y == b.start_y && a.goal_x == b.goal_x && a.goal_y == b.goal_y &&
         same_double(a.optimal_length, b.optimal_length) && a.optimal_length_text == b.optimal_length_text;
}

inline void fuzz_movingai_scen(std::string_view data) {
  MovingAiScenario scen;
  try {
    scen = parse_movingai_scenario(data, "fuzz.scen");
  } catch (const Error&) {
    return;
  }
  for (const auto& e : scen.entries) (void)e.unsolvable();
  // movingai.hpp keeps the length "exactly as written, so files round-trip".
  const std::string text = format_movingai_scenario(scen);
  MovingAiScenario again;
  try {
    again = parse_movingai_scenario(text, "fuzz-roundtrip.scen");
  } catch (const Error& e) {
    throw InvariantViolation(std::string("movingai scen: format_movingai_scenario output does not parse: ") +
                             e.what());
  }
  require(again.version == scen.version && again.space_separated == scen.space_separated &&
              again.entries.size() == scen.entries.size(),
          "movingai scen: parse(format(scen)) differs in version, flavour or entry count");
  for (std::size_t i = 0; i < scen.entries.size(); ++i)
    require(same_entry(again.entries[i], scen.entries[i]), "movingai scen: parse(format(scen)) differs in entry " +
                                                               std::to_string(i));
}

inline void fuzz_pgm(std::string_view data) {
  try {
    check_image(parse_pgm(data, "fuzz.pgm"));
  } catch (const Error&) {
  }
}

inline void fuzz_png(std::string_view data) {
  try {
    check_image(parse_png(data, "fuzz.png"));
  } catch (const Error&) {
  }
}

// The YAML alone through parse_ros_map_yaml; with a second file (the image, saved as m.pgm, which
// the seeds name) also the whole map through read_ros_map.
inline void fuzz_ros_yaml(std::string_view data) {
  const auto [yaml, image] = split_files(data);
  try {
    (void)parse_ros_map_yaml(yaml, "fuzz.yaml");
  } catch (const Error&) {
    return;
  }
  if (image.empty()) return;
  const ScratchFolder& dir = scratch();
  dir.write("m.pgm", image);
  const std::string yaml_path = dir.write("map.yaml", yaml);
  try {
    check_occupancy(read_ros_map(yaml_path));
  } catch (const Error&) {
  }
}

// The grid alone through parse_asc; with a second file (a .prj: WKT or the old ESRI keywords)
// both are written as g.asc and g.prj and read with read_asc, which converts the geometry.
inline void fuzz_asc(std::string_view data) {
  const auto [asc, prj] = split_files(data);
  if (prj.empty()) {
    try {
      check_elevation(parse_asc(asc, "fuzz.asc"));
    } catch (const Error&) {
    }
    return;
  }
  const ScratchFolder& dir = scratch();
  dir.write("g.prj", prj);
  const std::string asc_path = dir.write("g.asc", asc);
  try {
    ElevationGeoref georef;
    check_elevation(read_asc(asc_path, &georef));
  } catch (const Error&) {
  }
}

inline void fuzz_elevation_csv(std::string_view data) {
  try {
    check_elevation(parse_elevation_csv(data, "fuzz.csv"));
  } catch (const Error&) {
  }
}

// YAML sidecar, then the PNG saved as e.png (the name the seeds' `image:` uses).
inline void fuzz_elevation_yaml(std::string_view data) {
  const auto [yaml, image] = split_files(data);
  const ScratchFolder& dir = scratch();
  dir.write("e.png", image);
  const std::string yaml_path = dir.write("elevation.yaml", yaml);
  try {
    check_elevation(read_elevation_yaml(yaml_path));
  } catch (const Error&) {
  }
}

// The `<path>.yaml` sidecar, then the RAW bytes.
inline void fuzz_unity_raw(std::string_view data) {
  const auto [yaml, raw] = split_files(data);
  const ScratchFolder& dir = scratch();
  dir.write("terrain.raw.yaml", yaml);
  const std::string raw_path = dir.write("terrain.raw", raw);
  try {
    check_elevation(read_unity_raw(raw_path));
  } catch (const Error&) {
  }
}

struct Target {
  const char* name;
  void (*run)(std::string_view);
};

inline constexpr Target kTargets[] = {
    {"fuzz_movingai_map", fuzz_movingai_map},
    {"fuzz_movingai_scen", fuzz_movingai_scen},
    {"fuzz_pgm", fuzz_pgm},
    {"fuzz_png", fuzz_png},
    {"fuzz_ros_yaml", fuzz_ros_yaml},
    {"fuzz_asc", fuzz_asc},
    {"fuzz_elevation_csv", fuzz_elevation_csv},
    {"fuzz_elevation_yaml", fuzz_elevation_yaml},
    {"fuzz_unity_raw", fuzz_unity_raw},
};

inline const Target* find_target(std::string_view name) {
  for (const Target& t : kTargets)
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace starnav::fuzz
