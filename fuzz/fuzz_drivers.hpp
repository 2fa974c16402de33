#pragma once
// What each fuzz target does with one input, shared by the libFuzzer executable (fuzz/fuzz_main.cpp)
// and the regression test that replays fuzz/crashers/ and fuzz/corpus/ under g++
// (tests/io/test_fuzz_regressions.cpp).
//
// starnav::Error is the expected outcome for bad input and is swallowed here. Any other exception
// escapes, and so does InvariantViolation when a parser accepts an input but returns something
// inconsistent (cell count != width * height, a documented round trip that does not hold, ...).
//
// fuzz_scenario stops at parse_scenario: build_world (which loads terrain files and generates
// terrains and gravel) is never called, so an input cannot ask for gigabytes of terrain.
//
// Targets that read files (fuzz_elevation_yaml, fuzz_unity_raw; fuzz_ros_yaml with an image and
// fuzz_asc with a .prj)
// take two files in one input: the YAML text, then the line kFileSeparator, then the bytes of the
// second file, which is written to a per-process scratch folder under the name the seeds use.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/number_text.hpp"
#include "starnav/io/elevation_io.hpp"
#include "starnav/io/image.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/map/occupancy_grid.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/logs/carmen_log.hpp"
#include "starnav/logs/mcap.hpp"
#include "starnav/logs/ros2_bag.hpp"
#include "starnav/logs/ros_bag.hpp"
#include "starnav/logs/rosbag2_sqlite.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sweep/manifest.hpp"

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

// --- fuzz_scenario: what scenario.hpp promises about an accepted ScenarioSpec -----------------

inline bool finite2(const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }
inline bool finite3(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// Runs a library validation that must pass on what the parser accepted (it already ran them).
template <class F>
void must_validate(F&& f, const std::string& what) {
  try {
    f();
  } catch (const Error& e) {
    throw InvariantViolation("fuzz invariant violated: " + what + " accepted but fails its validation: " + e.what());
  }
}

inline void check_scenario_terrain(const ScenarioTerrain& t) {
  using K = ScenarioTerrain::Kind;
  require((t.kind == K::File) == !t.file.empty() && (t.kind == K::File) == !t.resolved_file.empty(),
          "scenario: terrain file given exactly for a file terrain");
  for (const TerrainFeature& f : t.features)
    require(finite2(f.centre) && std::isfinite(f.radius_m) && f.radius_m > 0 && std::isfinite(f.depth_m) &&
                f.depth_m > 0,
            "scenario: terrain feature with a bad centre, radius or depth");
  if (t.kind == K::Flat || t.kind == K::Hills || t.kind == K::Road) {
    // Geometry only (no cells allocated): at most 2^31 - 1 cells.
    must_validate([&] { (void)terrain_geometry(t.hills.width_m, t.hills.height_m, t.hills.resolution, t.hills.origin); },
                  "scenario: generated terrain size");
    require(std::isfinite(t.flat_z_m), "scenario: non-finite flat terrain height");
  }
  if (t.kind == K::Hills) must_validate([&] { t.hills.validate(); }, "scenario: hills options");
  if (t.kind == K::Road) must_validate([&] { t.road.validate(); }, "scenario: road options");
}

inline void check_scenario_obstacles(const std::vector<ScenarioObstacle>& obstacles) {
  static constexpr const char* kKinds[] = {"box",       "cylinder",          "prism",        "sphere",
                                           "slope_step", "undulating_ground", "round_convex", "gravel"};
  std::vector<std::string> names;
  for (const ScenarioObstacle& o : obstacles) {
    require(!o.name.empty(), "scenario: obstacle without a name");
    require(std::find(names.begin(), names.end(), o.name) == names.end(), "scenario: duplicate obstacle name");
    names.push_back(o.name);
    // The variant holds the shape of the kind as written (kKinds is in ScenarioObstacle::Shape's order).
    require(o.shape.index() < std::size(kKinds) && o.kind == kKinds[o.shape.index()],
            "scenario: obstacle kind '" + o.kind + "' does not match its shape");
    require(finite2(o.position) && (!o.z || std::isfinite(*o.z)), "scenario: non-finite obstacle position");
    require(std::isfinite(o.appear_s) && !std::isnan(o.disappear_s) && o.disappear_s > o.appear_s,
            "scenario: obstacle disappears before it appears");
    require(finite3(o.velocity), "scenario: non-finite obstacle velocity");
    require(o.waypoints.empty() || o.velocity == Vec3::Zero(), "scenario: obstacle with a velocity and waypoints");
    for (std::size_t i = 0; i < o.waypoints.size(); ++i) {
      const auto& w = o.waypoints[i];
      require(std::isfinite(w.t_s) && finite2(w.xy) && (!w.z || std::isfinite(*w.z)), "scenario: non-finite waypoint");
      require(i == 0 || w.t_s > o.waypoints[i - 1].t_s, "scenario: waypoint times do not increase strictly");
    }
  }
}

inline void check_scenario_settings(const std::vector<ParamSetting>& settings) {
  for (const ParamSetting& v : settings)
    require(!v.key.empty() && v.file == "fuzz.yaml" && v.line > 0 && !v.field.empty(),
            "scenario: a setting lost its key, file, line or field");
}

inline void check_scenario_navigation(const ScenarioSpec& s) {
  const ScenarioNavigation& n = *s.navigation;
  require(finite2(n.goal), "scenario: non-finite navigation goal");
  check_scenario_settings(n.settings);
  if (s.localization) check_scenario_settings(s.localization->settings);
  // The components' declared parameters judge the settings (the harness, without a world):
  // a refusal is a starnav::Error (fine); anything else escaping is a finding.
  try {
    check_navigation_scenario(s);
  } catch (const Error& e) {
    require(std::string(e.what()).find('\n') == std::string::npos, "scenario: a multi-line navigation error");
  }
}

inline void check_scenario(const ScenarioSpec& s) {
  require(s.file == "fuzz.yaml" && !s.name.empty(), "scenario: file or name lost");
  require(std::isfinite(s.dt_s) && s.dt_s > 0 && s.dt_s <= 1.0, "scenario: dt_s outside (0, 1]");
  require(std::isfinite(s.duration_s) && s.duration_s > 0, "scenario: duration_s not a finite number > 0");
  // Commands: consecutive from 0, each ending after it starts, found again by segment_at.
  double t = 0.0;
  for (std::size_t i = 0; i < s.commands.size(); ++i) {
    const CommandSegment& c = s.commands[i];
    require(c.start_s == t, "scenario: command " + std::to_string(i) + " does not start where the previous ends");
    require(std::isfinite(c.end_s) && c.end_s > c.start_s, "scenario: command " + std::to_string(i) +
                                                               " does not end (finitely) after it starts");
    require(std::isfinite(c.twist.vx) && std::isfinite(c.twist.vy) && std::isfinite(c.twist.wz),
            "scenario: non-finite command twist");
    require(s.segment_at(c.start_s) == static_cast<int>(i), "scenario: segment_at(start_s) is not the segment");
    t = c.end_s;
  }
  if (!s.commands.empty()) require(s.segment_at(t) == -1, "scenario: segment_at(end of script) is not -1");
  require(s.motion_mode.empty() || s.motion_mode == "auto" || s.motion_mode == "turn_then_drive" ||
              s.motion_mode == "holonomic" || s.motion_mode == "pure_pursuit",
          "scenario: unknown motion_mode '" + s.motion_mode + "'");
  if (s.navigation) {
    require(s.commands.empty(), "scenario: navigation scenario with a command script");
    check_scenario_navigation(s);
  }
  check_scenario_terrain(s.terrain);
  check_scenario_obstacles(s.obstacles);
  must_validate([&] { s.vehicle.validate(); }, "scenario: robot/vehicle");
  require(std::isfinite(s.start.x) && std::isfinite(s.start.y) && std::isfinite(s.start.yaw) &&
              std::abs(s.start.yaw) <= kPi + 1e-12,
          "scenario: robot.start not finite or yaw not wrapped");
  if (s.lidar) {
    must_validate([&] { s.lidar->config.validate(); }, "scenario: lidar");
    // sensors.lidar.beams allows 1..1000000; a preset's horizontal resolution must not give more.
    require(s.lidar->config.beams >= 1 && s.lidar->config.beams <= 1000000, "scenario: lidar beams outside 1..1000000");
  }
  if (s.imu) must_validate([&] { s.imu->config.validate(); }, "scenario: imu");
  if (s.encoders) {
    must_validate([&] { s.encoders->config.validate(); }, "scenario: encoders");
    require(std::isfinite(s.encoders->rate_hz) && s.encoders->rate_hz > 0, "scenario: encoder rate");
  }
  require(s.reference_line.empty() || s.reference_line.size() >= 2, "scenario: reference line of one point");
  for (const Vec2& p : s.reference_line) require(finite2(p), "scenario: non-finite reference line point");
  require(s.outputs.trajectory_every_n_steps >= 1 && s.outputs.clouds_every_n_scans >= 1,
          "scenario: outputs every_n below 1");
  require(s.outputs.point_clouds == ScenarioOutputs::CloudFormat::None || s.lidar.has_value(),
          "scenario: point clouds without a lidar");
  (void)s.command_at(0.5 * s.duration_s);
}

// parse_scenario on the YAML text; never build_world (see the top of this file).
inline void fuzz_scenario(std::string_view data) {
  ScenarioSpec spec;
  try {
    spec = parse_scenario(data, "fuzz.yaml");
  } catch (const Error&) {
    return;
  }
  check_scenario(spec);
}

// A log a reader accepted: the promises of logs/robot_log.hpp, and its reports must not throw.
inline void check_log(const RobotLog& log) {
  for (const LogScan& scan : log.scans) {
    require(scan.ranges_m.size() <= 100000, "log: more than 100000 beams");
    require(std::isfinite(scan.angle_min_rad) && std::isfinite(scan.angle_increment_rad), "log: beam angles not finite");
    require(!std::isnan(scan.range_max_m), "log: range_max is NaN");
    std::int64_t back = 0;
    require(parse_stamp_us(format_stamp_us(scan.stamp_us), back) && back == scan.stamp_us, "log: stamp round trip");
  }
  for (const LogOdometry& o : log.odometry)
    require(std::isfinite(o.pose.x) && std::isfinite(o.pose.y) && std::abs(o.pose.yaw) <= kPi + 1e-12,
            "log: odometry not finite or yaw not wrapped");
  const std::vector<LogOdometry> sorted = sort_by_time(log.odometry);
  for (const LogScan& scan : log.scans) (void)odometry_at(sorted, scan.stamp_us);
  (void)log_info_text(log);
  (void)log_info_json(log);
}

// The CARMEN reader and the text-extract reader on the same bytes.
inline void fuzz_carmen_log(std::string_view data) {
  try {
    check_log(read_carmen_log(data, "fuzz.clf"));
  } catch (const Error&) {
  }
  try {
    check_log(read_odomscan_text(data, "fuzz.txt"));
  } catch (const Error&) {
  }
}

inline void fuzz_ros_bag(std::string_view data) {
  try {
    check_log(read_ros1_bag(data, "fuzz.bag"));
  } catch (const Error&) {
  }
  // The same bytes as a 3D LiDAR recording: PointCloud2 clouds, odometry, truth and mount.
  try {
    const PointCloudBagIndex ix = index_point_cloud_bag(data, "fuzz.bag");
    std::size_t clouds = 0;
    for_each_bag_point_cloud(data, "fuzz.bag", ix, [&](BagPointCloud&& c) {
      ++clouds;
      for (const Vec3& p : c.points) require(p.allFinite(), "a non-finite cloud point was kept");
    });
    require(clouds == ix.cloud_stamps_us.size(), "a cloud indexed but not streamed");
  } catch (const Error&) {
  }
}

// ROS 2 recordings in one file, as read_robot_log reads them (with and without scans required),
// then the MCAP reader's record-by-record path on the same bytes (it must agree with the indexed one).
inline void fuzz_ros2_file(std::string_view data, const char* name) {
  LogReadOptions o;
  o.allow_no_scans = true;
  try {
    check_log(read_ros2_bag_bytes(data, name, o));
  } catch (const Error&) {
  }
  try {
    check_log(read_ros2_bag_bytes(data, name));
  } catch (const Error&) {
  }
}

inline void fuzz_mcap(std::string_view data) {
  fuzz_ros2_file(data, "fuzz.mcap");
  try {
    McapReader indexed(data, "fuzz.mcap");
    std::size_t from_index = 0, from_scan = 0;
    indexed.for_each_message([](const McapChannel&) { return true; }, [&](const McapMessageView&) { ++from_index; });
    McapReader scanned(data, "fuzz.mcap");
    scanned.ignore_summary();
    scanned.for_each_message([](const McapChannel&) { return true; }, [&](const McapMessageView& m) {
      require(m.channel != nullptr, "an MCAP message without its channel");
      ++from_scan;
    });
    if (indexed.indexed()) require(from_index <= from_scan, "the indexed path read more messages than the file holds");
  } catch (const Error&) {
  }
}

inline void fuzz_rosbag2_sqlite(std::string_view data) { fuzz_ros2_file(data, "fuzz.db3"); }

// The first byte picks a message type, the rest is its CDR serialisation.
inline void fuzz_cdr(std::string_view data) {
  static constexpr const char* kTypes[] = {"sensor_msgs/msg/LaserScan", "nav_msgs/msg/Odometry", "sensor_msgs/msg/Imu",
                                           "tf2_msgs/msg/TFMessage", "geometry_msgs/msg/PoseStamped",
                                           "geometry_msgs/msg/PoseWithCovarianceStamped", "sensor_msgs/msg/PointCloud2"};
  if (data.empty()) return;
  const char* type = kTypes[static_cast<unsigned char>(data[0]) % std::size(kTypes)];
  try {
    require(decode_ros2_message(type, data.substr(1), "fuzz.cdr", "fuzz message,"), "a decoded type was not decoded");
  } catch (const Error&) {
  }
}

inline void check_cloud(const PointCloudFile& f) {
  require(f.points.size() + f.dropped_non_finite <= kMaxCloudPoints, "a cloud larger than its limit");
  for (const Vec3& p : f.points) require(p.allFinite(), "a non-finite point was kept");
}

// PCD (ascii, binary, binary_compressed), PLY and KITTI .bin on the same bytes; LZF on its own with
// the size the first four bytes claim (bounded).
inline void fuzz_point_cloud(std::string_view data) {
  try {
    check_cloud(parse_pcd(data, "fuzz.pcd"));
  } catch (const Error&) {
  }
  try {
    check_cloud(parse_ply(data, "fuzz.ply"));
  } catch (const Error&) {
  }
  try {
    check_cloud(parse_kitti_bin(data, "fuzz.bin"));
  } catch (const Error&) {
  }
  if (data.size() >= 4) {
    std::uint32_t size = 0;
    std::memcpy(&size, data.data(), 4);
    try {
      const std::string out = lzf_decompress(data.substr(4), size % (1U << 20), "fuzz.lzf");
      require(out.size() == size % (1U << 20), "LZF returned another size than asked");
    } catch (const Error&) {
    }
  }
}

// parse_sweep_file on the YAML text (globs are never resolved: no file system is read), then the
// first tasks of its expansion: ids, columns, and the manifest's brace escaping undone exactly.
inline void fuzz_sweep_file(std::string_view data) {
  sweep::SweepSpec spec;
  try {
    spec = sweep::parse_sweep_file(data, "fuzz_sweep.yaml");
  } catch (const Error&) {
    return;
  }
  const std::uint64_t n = spec.task_count();
  require(n <= sweep::kMaxSweepTasks, "sweep: more tasks than the limit");
  const std::size_t columns = spec.axis_columns().size();
  for (std::uint64_t i = 0; i < std::min<std::uint64_t>(n, 64); ++i) {
    const sweep::SweepTask t = sweep::make_task(spec, i);
    require(t.id.size() == 16 && t.id.find_first_not_of("0123456789abcdef") == std::string::npos, "sweep: a task id not 16 hex digits");
    require(t.values.size() == columns, "sweep: task values do not match the columns");
    const std::vector<std::string> argv = sweep::command_for_run(t.argv, "/o");
    require(argv.size() == t.argv.size() && argv[0] == "starnav" && argv.size() >= spec.command.size() + 1, "sweep: argv size");
    for (std::size_t k = 0; k < spec.command.size(); ++k) {
      std::string expected;
      for (const sweep::TemplatePart& p : spec.command[k].parts)
        expected += p.kind == sweep::TemplatePart::Kind::Text ? p.text
                    : p.kind == sweep::TemplatePart::Kind::Out ? std::string("/o")
                                                               : t.values.at([&] {
                                                                   std::size_t col = 0;
                                                                   for (std::size_t a = 0; a < p.axis; ++a) col += spec.axes[a].width();
                                                                   return col + p.field;
                                                                 }());
      require(argv[k + 1] == expected, "sweep: the manifest's braces do not come back as written");
    }
  }
  for (const sweep::SweepAxis& a : spec.axes)
    if (a.kind == sweep::SweepAxis::Kind::Range && a.size() > 0)
      require(parse_real_text(a.value(0)).has_value() && parse_real_text(a.value(a.size() - 1)).has_value(), "sweep: a range value is not a number");
  try {
    sweep::check_axis_values(spec);
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
    {"fuzz_scenario", fuzz_scenario},
    {"fuzz_carmen_log", fuzz_carmen_log},
    {"fuzz_ros_bag", fuzz_ros_bag},
    {"fuzz_point_cloud", fuzz_point_cloud},
    {"fuzz_sweep_file", fuzz_sweep_file},
    {"fuzz_mcap", fuzz_mcap},
    {"fuzz_rosbag2_sqlite", fuzz_rosbag2_sqlite},
    {"fuzz_cdr", fuzz_cdr},
};

inline const Target* find_target(std::string_view name) {
  for (const Target& t : kTargets)
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace starnav::fuzz
