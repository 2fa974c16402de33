#include "starnav/experiment/mcap_export.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/ros_map.hpp"
#include "starnav/logs/cdr.hpp"
#include "starnav/logs/mcap.hpp"
#include "starnav/view/run_folder.hpp"
#include "starnav/viz/raster.hpp"

namespace starnav {

// A named namespace, not an anonymous one: the unity build puts this file beside others whose
// helpers have the same short names.
namespace mcap_export_detail {

#include "starnav/experiment/mcap_export_schemas.inc"

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr std::uint64_t kMaxRunFileBytes = std::uint64_t{1} << 30;

std::string embedded_schema(const std::string& name) {
  for (const EmbeddedSchema& s : kEmbeddedSchemas) {
    if (name != s.name) continue;
    std::string text;
    for (const char* p : s.pieces) text += p;
    return text;
  }
  throw Error("no embedded schema " + name);
}

// ---- What the run folder says ---------------------------------------------------------------------

struct Pose {
  double t = 0, x = 0, y = 0, z = 0, yaw = 0;
};

struct Step {
  double t = 0;
  std::optional<Pose> pose, estimate, reference;
  std::vector<Vec3> hits;
  std::vector<Pose> particles;
  std::vector<Vec2> path;
  bool has_path = false;
};

Json parse_json(const std::string& text, const std::string& file, int line = 0) {
  try {
    return Json::parse(text);
  } catch (const Json::exception& e) {
    throw Error("not JSON: " + one_line(e.what(), 120), file, line);
  }
}

double number(const Json& j, const std::string& file, int line, const std::string& field) {
  if (!j.is_number()) throw Error("expected a number", file, line, field);
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Error("not finite", file, line, field);
  return v;
}

std::vector<Pose> read_trajectory(const std::string& file) {
  std::istringstream in(read_input_file(file, kMaxRunFileBytes));
  std::string line;
  if (!std::getline(in, line)) throw Error("empty", file, 1);
  std::vector<std::string> columns;
  {
    std::istringstream h(line);
    std::string c;
    while (std::getline(h, c, ',')) columns.push_back(c);
  }
  const auto column = [&](const char* name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
  };
  const int ct = column("t_s"), cx = column("x_m"), cy = column("y_m"), cz = column("z_m"), cyaw = column("yaw_rad");
  if (ct < 0 || cx < 0 || cy < 0 || cyaw < 0) throw Error("expected the columns t_s, x_m, y_m and yaw_rad", file, 1, "header");
  std::vector<Pose> out;
  int n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    std::vector<double> v;
    std::istringstream r(line);
    std::string cell;
    while (std::getline(r, cell, ',')) {
      char* end = nullptr;
      const double d = std::strtod(cell.c_str(), &end);
      if (end == cell.c_str() || *end != '\0' || !std::isfinite(d)) throw Error("expected a finite number, got '" + printable(cell, 40) + "'", file, n);
      v.push_back(d);
    }
    if (v.size() != columns.size()) throw Error("expected " + std::to_string(columns.size()) + " values", file, n);
    out.push_back({v[ct], v[cx], v[cy], cz >= 0 ? v[cz] : 0.0, v[cyaw]});
  }
  return out;
}

std::optional<Pose> pose_of(const Json& j, double t, const std::string& file, int line, const char* field, bool six) {
  if (j.is_null()) return std::nullopt;
  if (!j.is_array() || j.size() != (six ? 6u : 3u)) throw Error(six ? "expected [x, y, z, roll, pitch, yaw]" : "expected [x, y, yaw]", file, line, field);
  Pose p;
  p.t = t;
  p.x = number(j[0], file, line, field);
  p.y = number(j[1], file, line, field);
  if (six) {
    p.z = number(j[2], file, line, field);
    p.yaw = number(j[5], file, line, field);
  } else {
    p.yaw = number(j[2], file, line, field);
  }
  return p;
}

std::vector<Step> read_steps(const std::string& file) {
  std::istringstream in(read_input_file(file, kMaxRunFileBytes));
  std::vector<Step> steps;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    const Json j = parse_json(line, file, n);
    if (!j.is_object() || !j.contains("t_s")) throw Error("expected an object with t_s", file, n);
    Step s;
    s.t = number(j["t_s"], file, n, "t_s");
    if (j.contains("pose")) s.pose = pose_of(j["pose"], s.t, file, n, "pose", true);
    if (j.contains("estimate")) s.estimate = pose_of(j["estimate"], s.t, file, n, "estimate", false);
    if (j.contains("reference")) s.reference = pose_of(j["reference"], s.t, file, n, "reference", false);
    if (j.contains("hits")) {
      if (!j["hits"].is_array()) throw Error("expected a list", file, n, "hits");
      for (const Json& h : j["hits"]) {
        if (!h.is_array() || h.size() != 3) throw Error("expected [x, y, z]", file, n, "hits");
        s.hits.emplace_back(number(h[0], file, n, "hits"), number(h[1], file, n, "hits"), number(h[2], file, n, "hits"));
      }
    }
    if (j.contains("particles")) {
      if (!j["particles"].is_array()) throw Error("expected a list", file, n, "particles");
      for (const Json& p : j["particles"]) s.particles.push_back(*pose_of(p, s.t, file, n, "particles", false));
    }
    if (j.contains("path")) {
      if (!j["path"].is_array()) throw Error("expected a list", file, n, "path");
      s.has_path = true;
      for (const Json& p : j["path"]) {
        if (!p.is_array() || p.size() < 2) throw Error("expected [x, y]", file, n, "path");
        s.path.emplace_back(number(p[0], file, n, "path"), number(p[1], file, n, "path"));
      }
    }
    steps.push_back(std::move(s));
  }
  return steps;
}

// ---- Message bodies -----------------------------------------------------------------------------

std::int64_t to_ns(double t) {
  if (!(t > 0)) return 0;
  const double ns = std::round(t * 1e9);
  return ns >= 9.2e18 ? std::numeric_limits<std::int64_t>::max() : static_cast<std::int64_t>(ns);
}

Json stamp(std::int64_t ns) { return {{"sec", ns / 1'000'000'000}, {"nsec", ns % 1'000'000'000}}; }

Json quaternion_yaw(double yaw) { return {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(yaw / 2)}, {"w", std::cos(yaw / 2)}}; }

Json pose_json(double x, double y, double z, double yaw) {
  return {{"position", {{"x", x}, {"y", y}, {"z", z}}}, {"orientation", quaternion_yaw(yaw)}};
}

Json color(double r, double g, double b, double a) { return {{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }

Json empty_entity(std::int64_t ns, const std::string& frame, const std::string& id) {
  return {{"timestamp", stamp(ns)}, {"frame_id", frame}, {"id", id}, {"lifetime", stamp(0)}, {"frame_locked", frame != "map"},
          {"metadata", Json::array()}, {"arrows", Json::array()}, {"cubes", Json::array()}, {"spheres", Json::array()},
          {"cylinders", Json::array()}, {"lines", Json::array()}, {"triangles", Json::array()}, {"texts", Json::array()},
          {"models", Json::array()}};
}

// An obstacle's parts (docs/run-records.md) moved by `shift`, into the entity.
void add_parts(Json& e, const Json& parts, const Vec3& shift, const std::string& file) {
  const Json grey = color(0.55, 0.55, 0.6, 1.0);
  for (const Json& p : parts) {
    if (!p.is_array() || p.empty() || !p[0].is_string()) throw Error("expected [kind, ...]", file, 0, "obstacles.parts");
    const std::string kind = p[0].get<std::string>();
    const auto v = [&](std::size_t i) { return i < p.size() ? number(p[i], file, 0, "obstacles.parts") : 0.0; };
    if (kind == "box") {
      if (p.size() != 10) throw Error("a box has 9 numbers", file, 0, "obstacles.parts");
      const Eigen::Quaterniond q = Eigen::AngleAxisd(v(9), Vec3::UnitZ()) * Eigen::AngleAxisd(v(8), Vec3::UnitY()) *
                                   Eigen::AngleAxisd(v(7), Vec3::UnitX());
      e["cubes"].push_back({{"pose", {{"position", {{"x", v(1) + shift.x()}, {"y", v(2) + shift.y()}, {"z", v(3) + shift.z()}}},
                                      {"orientation", {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}}}},
                            {"size", {{"x", v(4)}, {"y", v(5)}, {"z", v(6)}}},
                            {"color", grey}});
    } else if (kind == "cylinder") {
      if (p.size() != 6) throw Error("a cylinder has 5 numbers", file, 0, "obstacles.parts");
      // Foxglove's cylinder is centred: its bottom disc is at the record's centre.
      e["cylinders"].push_back({{"pose", pose_json(v(1) + shift.x(), v(2) + shift.y(), v(3) + v(5) / 2 + shift.z(), 0.0)},
                                {"size", {{"x", 2 * v(4)}, {"y", 2 * v(4)}, {"z", v(5)}}},
                                {"bottom_scale", 1.0},
                                {"top_scale", 1.0},
                                {"color", grey}});
    } else if (kind == "sphere") {
      if (p.size() != 5) throw Error("a sphere has 4 numbers", file, 0, "obstacles.parts");
      e["spheres"].push_back({{"pose", pose_json(v(1) + shift.x(), v(2) + shift.y(), v(3) + shift.z(), 0.0)},
                              {"size", {{"x", 2 * v(4)}, {"y", 2 * v(4)}, {"z", 2 * v(4)}}},
                              {"color", grey}});
    } else if (kind == "prism") {
      if (p.size() != 9) throw Error("a prism has 8 numbers", file, 0, "obstacles.parts");
      // The triangle (base width, height, apex offset) in the prism's x-z plane, extruded along y.
      const double w = v(5), h = v(6), apex = v(7), len = v(8);
      const Vec3 tri[3] = {{-w / 2, 0, 0}, {w / 2, 0, 0}, {apex, 0, h}};
      Json points = Json::array();
      const auto add = [&](const Vec3& a) { points.push_back({{"x", a.x()}, {"y", a.y()}, {"z", a.z()}}); };
      const Vec3 off(0, len / 2, 0);
      for (int k = 0; k < 3; ++k) add(tri[k] - off);  // the two ends
      for (int k = 0; k < 3; ++k) add(tri[k] + off);
      for (int k = 0; k < 3; ++k) {  // the three sides, two triangles each
        const Vec3 a = tri[k], b = tri[(k + 1) % 3];
        add(a - off), add(b - off), add(b + off), add(a - off), add(b + off), add(a + off);
      }
      e["triangles"].push_back({{"pose", pose_json(v(1) + shift.x(), v(2) + shift.y(), v(3) + shift.z(), v(4))},
                                {"points", points},
                                {"color", grey},
                                {"colors", Json::array()},
                                {"indices", Json::array()}});
    } else {
      throw Error("unknown part kind '" + printable(kind, 20) + "'", file, 0, "obstacles.parts");
    }
  }
}

// Where an obstacle's anchor is at t (docs/run-records.md), and whether it exists then.
std::optional<Vec3> anchor_at(const Json& o, double t, const std::string& file) {
  const double appear = o.contains("appear_s") ? number(o["appear_s"], file, 0, "appear_s") : 0.0;
  const bool forever = !o.contains("disappear_s") || o["disappear_s"].is_null();
  if (t < appear || (!forever && t >= number(o["disappear_s"], file, 0, "disappear_s"))) return std::nullopt;
  const Json& a = o["anchor"];
  Vec3 anchor(number(a[0], file, 0, "anchor"), number(a[1], file, 0, "anchor"), number(a[2], file, 0, "anchor"));
  if (o.contains("velocity")) {
    const Json& v = o["velocity"];
    return anchor + (t - appear) * Vec3(number(v[0], file, 0, "velocity"), number(v[1], file, 0, "velocity"), number(v[2], file, 0, "velocity"));
  }
  if (o.contains("waypoints") && o["waypoints"].is_array() && !o["waypoints"].empty()) {
    const Json& w = o["waypoints"];
    const auto point = [&](const Json& p) {
      return std::pair<double, Vec3>(number(p[0], file, 0, "waypoints"),
                                     Vec3(number(p[1], file, 0, "waypoints"), number(p[2], file, 0, "waypoints"), number(p[3], file, 0, "waypoints")));
    };
    auto prev = point(w[0]);
    if (t <= prev.first) return prev.second;
    for (std::size_t i = 1; i < w.size(); ++i) {
      const auto next = point(w[i]);
      if (t <= next.first) {
        const double u = next.first > prev.first ? (t - prev.first) / (next.first - prev.first) : 1.0;
        return prev.second + u * (next.second - prev.second);
      }
      prev = next;
    }
    return prev.second;
  }
  return anchor;
}

std::vector<std::int8_t> run_lengths(const Json& rle, std::size_t cells, const std::string& file) {
  std::vector<std::int8_t> out;
  out.reserve(cells);
  if (!rle.is_array() || rle.size() % 2 != 0) throw Error("expected [value, count, ...]", file, 0, "nav_map.initial");
  for (std::size_t i = 0; i < rle.size(); i += 2) {
    const double v = number(rle[i], file, 0, "nav_map.initial"), n = number(rle[i + 1], file, 0, "nav_map.initial");
    if (v < -1 || v > 100 || n < 0 || n > static_cast<double>(cells - out.size())) throw Error("run outside the grid", file, 0, "nav_map.initial");
    out.insert(out.end(), static_cast<std::size_t>(n), static_cast<std::int8_t>(v));
  }
  if (out.size() != cells) throw Error("the runs cover " + std::to_string(out.size()) + " of " + std::to_string(cells) + " cells", file, 0, "nav_map.initial");
  return out;
}

struct Grid {
  int width = 0, height = 0;
  double resolution = 0, ox = 0, oy = 0, oyaw = 0;
  std::vector<std::int8_t> cells;  // row-major from the origin corner
};

// The hits of a step as ranges in base_link, one per degree from -180 degrees (NaN: none).
std::vector<float> binned_ranges(const Step& s) {
  std::vector<float> r(360, std::numeric_limits<float>::quiet_NaN());
  if (!s.pose) return r;
  for (const Vec3& h : s.hits) {
    const double dx = h.x() - s.pose->x, dy = h.y() - s.pose->y;
    const double a = wrap_angle(std::atan2(dy, dx) - s.pose->yaw);
    const int bin = std::clamp(static_cast<int>(std::floor((a + kPi) / deg_to_rad(1.0))), 0, 359);
    const float d = static_cast<float>(std::hypot(dx, dy));
    if (std::isnan(r[bin]) || d < r[bin]) r[bin] = d;
  }
  return r;
}

// ---- The writer ---------------------------------------------------------------------------------

struct Out {
  struct Message {
    std::int64_t ns;
    std::uint16_t channel;
    std::string data;
  };
  McapWriter writer{"", McapWriter::Compression::Zstd};
  std::map<std::string, std::uint16_t> channels;
  std::map<std::uint16_t, std::string> topic_of;
  std::vector<Message> messages;
  bool ros2 = false;

  std::uint16_t channel(const std::string& topic, const std::string& schema) {
    const auto it = channels.find(topic);
    if (it != channels.end()) return it->second;
    const std::string encoding = ros2 ? "ros2msg" : "jsonschema";
    const std::uint16_t s = writer.add_schema(schema, encoding, embedded_schema(schema));
    const std::uint16_t c = writer.add_channel(s, topic, ros2 ? "cdr" : "json");
    channels[topic] = c;
    topic_of[c] = topic;
    return c;
  }
  void add(const std::string& topic, const std::string& schema, std::int64_t ns, std::string data) {
    messages.push_back({ns, channel(topic, schema), std::move(data)});
  }
  void add_json(const std::string& topic, const std::string& schema, std::int64_t ns, const Json& j) {
    add(topic, schema, ns, j.dump(-1, ' ', false, Json::error_handler_t::replace));
  }
};

// ROS 2 CDR bodies.
void ros2_header(CdrWriter& w, std::int64_t ns, const std::string& frame) {
  w.i32(static_cast<std::int32_t>(std::min<std::int64_t>(ns / 1'000'000'000, std::numeric_limits<std::int32_t>::max())));
  w.u32(static_cast<std::uint32_t>(ns % 1'000'000'000));
  w.string(frame);
}

void ros2_pose(CdrWriter& w, double x, double y, double z, double yaw) {
  w.f64(x).f64(y).f64(z).f64(0.0).f64(0.0).f64(std::sin(yaw / 2)).f64(std::cos(yaw / 2));
}

std::string ros2_grid(const Grid& g, std::int64_t ns) {
  CdrWriter w;
  ros2_header(w, ns, "map");
  w.i32(static_cast<std::int32_t>(ns / 1'000'000'000)).u32(static_cast<std::uint32_t>(ns % 1'000'000'000));  // map_load_time
  w.f32(static_cast<float>(g.resolution)).u32(static_cast<std::uint32_t>(g.width)).u32(static_cast<std::uint32_t>(g.height));
  ros2_pose(w, g.ox, g.oy, 0.0, g.oyaw);
  w.u32(static_cast<std::uint32_t>(g.cells.size()));
  w.raw(std::string_view(reinterpret_cast<const char*>(g.cells.data()), g.cells.size()));
  return w.take();
}

std::string ros2_path(const std::vector<Pose>& poses, std::int64_t ns) {
  CdrWriter w;
  ros2_header(w, ns, "map");
  w.u32(static_cast<std::uint32_t>(poses.size()));
  for (const Pose& p : poses) {
    ros2_header(w, to_ns(p.t), "map");
    ros2_pose(w, p.x, p.y, p.z, p.yaw);
  }
  return w.take();
}

Json foxglove_grid(const Grid& g, std::int64_t ns) {
  return {{"timestamp", stamp(ns)},
          {"frame_id", "map"},
          {"pose", pose_json(g.ox, g.oy, 0.0, g.oyaw)},
          {"column_count", g.width},
          {"cell_size", {{"x", g.resolution}, {"y", g.resolution}}},
          {"row_stride", g.width},
          {"cell_stride", 1},
          {"fields", Json::array({{{"name", "occupancy"}, {"offset", 0}, {"type", 2}}})},  // INT8
          {"data", viz::base64_encode(std::string_view(reinterpret_cast<const char*>(g.cells.data()), g.cells.size()))}};
}

Json foxglove_poses(const std::vector<Pose>& poses, std::int64_t ns) {
  Json list = Json::array();
  for (const Pose& p : poses) list.push_back(pose_json(p.x, p.y, p.z, p.yaw));
  return {{"timestamp", stamp(ns)}, {"frame_id", "map"}, {"poses", list}};
}

McapExportSummary export_run(const std::string& run_dir, const std::string& out_path, const McapExportOptions& options) {
  const RunFolder run = read_run_folder(run_dir);
  const auto has = [&](const std::string& f) { return std::find(run.files.begin(), run.files.end(), f) != run.files.end(); };
  const auto file = [&](const std::string& f) { return (fs::path(run_dir) / f).string(); };
  const Json manifest = parse_json(read_input_file(file("run.json"), kMaxRunFileBytes), file("run.json"));
  const double start_s = manifest.contains("start_s") && manifest["start_s"].is_number() ? manifest["start_s"].get<double>() : 0.0;
  const std::int64_t t0 = to_ns(start_s);

  Out out;
  out.ros2 = options.ros2;
  const std::vector<Pose> trajectory = has("trajectory.csv") ? read_trajectory(file("trajectory.csv")) : std::vector<Pose>{};
  const std::vector<Step> steps = has("steps.jsonl") ? read_steps(file("steps.jsonl")) : std::vector<Step>{};
  Json world;
  if (has("world.json")) world = parse_json(read_input_file(file("world.json"), kMaxRunFileBytes), file("world.json"));
  const std::string wfile = file("world.json");

  // Maps: the navigation grid at the start, the written map at the end.
  std::vector<std::pair<std::int64_t, Grid>> grids;
  if (world.is_object() && world.contains("nav_map") && world["nav_map"].is_object()) {
    const Json& m = world["nav_map"];
    Grid g;
    const double w = number(m["width"], wfile, 0, "nav_map.width"), h = number(m["height"], wfile, 0, "nav_map.height");
    if (w < 1 || h < 1 || w * h > 4e8) throw Error("expected a grid of 1 to 4e8 cells", wfile, 0, "nav_map");
    g.width = static_cast<int>(w);
    g.height = static_cast<int>(h);
    g.resolution = number(m["resolution_m"], wfile, 0, "nav_map.resolution_m");
    g.ox = number(m["origin"][0], wfile, 0, "nav_map.origin");
    g.oy = number(m["origin"][1], wfile, 0, "nav_map.origin");
    g.oyaw = number(m["origin"][2], wfile, 0, "nav_map.origin");
    g.cells = run_lengths(m["initial"], static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height), wfile);
    grids.emplace_back(t0, std::move(g));
  }
  double last_s = start_s;
  for (const Pose& p : trajectory) last_s = std::max(last_s, p.t);
  for (const Step& s : steps) last_s = std::max(last_s, s.t);
  if (has("map.yaml")) {
    const OccupancyGrid m = read_ros_map(file("map.yaml"));
    Grid g;
    g.width = m.width();
    g.height = m.height();
    g.resolution = m.resolution();
    g.ox = m.origin().x;
    g.oy = m.origin().y;
    g.oyaw = m.origin().yaw;
    g.cells.assign(m.data().begin(), m.data().end());
    grids.emplace_back(to_ns(last_s), std::move(g));
  }
  for (const auto& [ns, g] : grids) {
    if (options.ros2) out.add("/map", "nav_msgs/msg/OccupancyGrid", ns, ros2_grid(g, ns));
    else out.add_json("/map", "foxglove.Grid", ns, foxglove_grid(g, ns));
  }

  // The robot's pose: map -> base_link, at most 50 a second.
  double last_tf = -1e300;
  for (const Pose& p : trajectory) {
    if (p.t - last_tf < 0.02) continue;
    last_tf = p.t;
    const std::int64_t ns = to_ns(p.t);
    if (options.ros2) {
      CdrWriter w;
      w.u32(1);
      ros2_header(w, ns, "map");
      w.string("base_link");
      ros2_pose(w, p.x, p.y, p.z, p.yaw);
      out.add("/tf", "tf2_msgs/msg/TFMessage", ns, w.take());
    } else {
      out.add_json("/tf", "foxglove.FrameTransform", ns,
                   {{"timestamp", stamp(ns)}, {"parent_frame_id", "map"}, {"child_frame_id", "base_link"},
                    {"translation", {{"x", p.x}, {"y", p.y}, {"z", p.z}}}, {"rotation", quaternion_yaw(p.yaw)}});
    }
  }
  if (!trajectory.empty()) {
    if (options.ros2) out.add("/trajectory", "nav_msgs/msg/Path", t0, ros2_path(trajectory, t0));
    else out.add_json("/trajectory", "foxglove.PosesInFrame", t0, foxglove_poses(trajectory, t0));
  }

  // The world's solids (Foxglove only) and the robot's body.
  if (!options.ros2 && world.is_object()) {
    const Json obstacles = world.contains("obstacles") ? world["obstacles"] : Json::array();
    bool moving = false;
    for (const Json& o : obstacles)
      moving = moving || o.contains("velocity") || o.contains("waypoints") || (o.contains("disappear_s") && !o["disappear_s"].is_null()) ||
               (o.contains("appear_s") && number(o["appear_s"], wfile, 0, "appear_s") > start_s);
    std::vector<double> times{start_s};
    if (moving)
      for (const Step& s : steps) times.push_back(s.t);
    for (const double t : times) {
      const std::int64_t ns = to_ns(t);
      Json update = {{"deletions", Json::array()}, {"entities", Json::array()}};
      if (t == start_s) update["deletions"].push_back({{"timestamp", stamp(ns)}, {"type", 1}, {"id", ""}});  // ALL
      for (const Json& o : obstacles) {
        if (!o.is_object() || !o.contains("anchor") || !o.contains("parts")) throw Error("an obstacle needs anchor and parts", wfile, 0, "obstacles");
        const std::string id = o.contains("name") && o["name"].is_string() ? o["name"].get<std::string>() : "obstacle";
        const std::optional<Vec3> at = anchor_at(o, t, wfile);
        if (!at) {
          update["deletions"].push_back({{"timestamp", stamp(ns)}, {"type", 0}, {"id", id}});
          continue;
        }
        const Vec3 anchor(number(o["anchor"][0], wfile, 0, "anchor"), number(o["anchor"][1], wfile, 0, "anchor"), number(o["anchor"][2], wfile, 0, "anchor"));
        Json e = empty_entity(ns, "map", id);
        add_parts(e, o["parts"], *at - anchor, wfile);
        update["entities"].push_back(std::move(e));
      }
      if (t == start_s && world.contains("robot") && world["robot"].is_object()) {
        const Json& r = world["robot"];
        Json e = empty_entity(ns, "base_link", "robot");
        const double l = number(r.value("body_length_m", Json(0.5)), wfile, 0, "robot"), w = number(r.value("body_width_m", Json(0.4)), wfile, 0, "robot");
        const double h = number(r.value("body_height_m", Json(0.2)), wfile, 0, "robot"), c = number(r.value("ground_clearance_m", Json(0.0)), wfile, 0, "robot");
        const double cx = number(r.value("body_center_x_m", Json(0.0)), wfile, 0, "robot");
        e["cubes"].push_back({{"pose", pose_json(cx, 0.0, c + h / 2, 0.0)}, {"size", {{"x", l}, {"y", w}, {"z", h}}}, {"color", color(0.1, 0.45, 0.9, 0.8)}});
        update["entities"].push_back(std::move(e));
      }
      out.add_json("/world", "foxglove.SceneUpdate", ns, update);
    }
    if (world.contains("terrain") && world["terrain"].is_object()) {
      const Json& t = world["terrain"];
      const double sx = number(t["samples_x"], wfile, 0, "terrain.samples_x"), sy = number(t["samples_y"], wfile, 0, "terrain.samples_y");
      if (sx < 1 || sy < 1 || sx * sy > 1e7 || !t["heights"].is_array() || t["heights"].size() != static_cast<std::size_t>(sx * sy))
        throw Error("expected samples_x x samples_y heights", wfile, 0, "terrain.heights");
      std::string data;
      for (const Json& h : t["heights"]) {
        const float v = h.is_null() ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(number(h, wfile, 0, "terrain.heights"));
        data.append(reinterpret_cast<const char*>(&v), 4);
      }
      const double cell = number(t["resolution_m"], wfile, 0, "terrain.resolution_m") * number(t["stride"], wfile, 0, "terrain.stride");
      out.add_json("/terrain", "foxglove.Grid", t0,
                   {{"timestamp", stamp(t0)},
                    {"frame_id", "map"},
                    {"pose", pose_json(number(t["origin"][0], wfile, 0, "terrain.origin"), number(t["origin"][1], wfile, 0, "terrain.origin"), 0.0,
                                       number(t["origin"][2], wfile, 0, "terrain.origin"))},
                    {"column_count", static_cast<int>(sx)},
                    {"cell_size", {{"x", cell}, {"y", cell}}},
                    {"row_stride", static_cast<int>(sx) * 4},
                    {"cell_stride", 4},
                    {"fields", Json::array({{{"name", "height"}, {"offset", 0}, {"type", 7}}})},  // FLOAT32
                    {"data", viz::base64_encode(data)}});
    }
  }

  // Each step: hits, the scan, the plan, particles, estimate, reference.
  for (const Step& s : steps) {
    const std::int64_t ns = to_ns(s.t);
    if (!s.hits.empty() || s.pose) {
      const std::vector<float> ranges = binned_ranges(s);
      if (options.ros2) {
        CdrWriter w;
        ros2_header(w, ns, "base_link");
        float range_max = 0.0f;
        for (float r : ranges)
          if (!std::isnan(r)) range_max = std::max(range_max, r);
        w.f32(static_cast<float>(-kPi)).f32(static_cast<float>(kPi - deg_to_rad(1.0))).f32(static_cast<float>(deg_to_rad(1.0)));
        w.f32(0.0f).f32(0.0f).f32(0.0f).f32(range_max + 1.0f);
        w.u32(360);
        for (float r : ranges) w.f32(std::isnan(r) ? std::numeric_limits<float>::infinity() : r);
        w.u32(0);
        out.add("/scan", "sensor_msgs/msg/LaserScan", ns, w.take());
      } else {
        std::string points;
        for (const Vec3& h : s.hits)
          for (int k = 0; k < 3; ++k) {
            const float v = static_cast<float>(h[k]);
            points.append(reinterpret_cast<const char*>(&v), 4);
          }
        out.add_json("/hits", "foxglove.PointCloud", ns,
                     {{"timestamp", stamp(ns)},
                      {"frame_id", "map"},
                      {"pose", pose_json(0, 0, 0, 0)},
                      {"point_stride", 12},
                      {"fields", Json::array({{{"name", "x"}, {"offset", 0}, {"type", 7}},
                                              {{"name", "y"}, {"offset", 4}, {"type", 7}},
                                              {{"name", "z"}, {"offset", 8}, {"type", 7}}})},
                      {"data", viz::base64_encode(points)}});
        Json r = Json::array();
        for (float v : ranges) r.push_back(std::isnan(v) ? 0.0 : static_cast<double>(v));
        out.add_json("/scan", "foxglove.LaserScan", ns,
                     {{"timestamp", stamp(ns)},
                      {"frame_id", "base_link"},
                      {"pose", pose_json(0, 0, 0, 0)},
                      {"start_angle", -kPi},
                      {"end_angle", kPi - deg_to_rad(1.0)},
                      {"ranges", r},
                      {"intensities", Json::array()}});
      }
    }
    if (s.has_path) {
      std::vector<Pose> plan;
      for (const Vec2& p : s.path) plan.push_back({s.t, p.x(), p.y(), 0.0, 0.0});
      if (options.ros2) out.add("/plan", "nav_msgs/msg/Path", ns, ros2_path(plan, ns));
      else out.add_json("/plan", "foxglove.PosesInFrame", ns, foxglove_poses(plan, ns));
    }
    if (!options.ros2) {
      if (!s.particles.empty()) out.add_json("/particles", "foxglove.PosesInFrame", ns, foxglove_poses(s.particles, ns));
      if (s.estimate) out.add_json("/estimate", "foxglove.PosesInFrame", ns, foxglove_poses({*s.estimate}, ns));
      if (s.reference) out.add_json("/reference", "foxglove.PosesInFrame", ns, foxglove_poses({*s.reference}, ns));
    }
  }

  if (out.messages.empty()) throw Error("holds nothing to export (no trajectory.csv, steps.jsonl, world.json or map)", run_dir);
  std::stable_sort(out.messages.begin(), out.messages.end(), [](const Out::Message& a, const Out::Message& b) { return a.ns < b.ns; });
  McapExportSummary summary;
  summary.first_s = static_cast<double>(out.messages.front().ns) * 1e-9;
  summary.last_s = static_cast<double>(out.messages.back().ns) * 1e-9;
  for (const Out::Message& m : out.messages) {
    out.writer.add_message(m.channel, static_cast<std::uint64_t>(m.ns), static_cast<std::uint64_t>(m.ns), m.data);
    ++summary.per_topic[out.topic_of[m.channel]];
    ++summary.messages;
  }
  write_file_bytes(out_path, out.writer.finish());
  return summary;
}

}  // namespace mcap_export_detail

McapExportSummary export_run_mcap(const std::string& run_dir, const std::string& out_path, const McapExportOptions& options) {
  return mcap_export_detail::export_run(run_dir, out_path, options);
}

}  // namespace starnav
