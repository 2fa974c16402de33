// Estimation from Python (docs/python.md, "SLAM and localization"): a robot log read as arrays (the
// messages the log's robot received, by the one rule of logs/robot_log_source.hpp), `starnav slam
// run` and `starnav localize` as one call each (the same library drivers, run with the GIL
// released), and a localizer of the registry (ekf, amcl, ground_truth, odometry) fed message by
// message through the Localizer role.
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "bindings.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/file_error.hpp"
#include "starnav/estimate/localizer.hpp"
#include "starnav/experiment/localize_report.hpp"
#include "starnav/harness/localization_chain.hpp"
#include "starnav/harness/slam_report.hpp"
#include "starnav/logs/log_file.hpp"
#include "starnav/logs/robot_log_source.hpp"
#include "starnav/registry/components.hpp"

namespace starnav::python {

namespace {


// The reader's options as the CLI's log flags give them (--scan-topic ... --range-max, --flaser-angles);
// the reader's warnings are kept to be raised as Python warnings once the GIL is held again.
struct LogRead {
  LogReadOptions options;
  std::shared_ptr<std::vector<std::string>> warnings = std::make_shared<std::vector<std::string>>();
};

LogRead log_read(const py::dict& read) {
  LogRead out;
  for (const auto& [k, v] : read) {
    const std::string key = py::str(k);
    if (v.is_none()) continue;
    if (key == "scan_topic") out.options.scan_topic = v.cast<std::string>();
    else if (key == "odom_topic") out.options.odom_topic = v.cast<std::string>();
    else if (key == "imu_topic") out.options.imu_topic = v.cast<std::string>();
    else if (key == "truth_topic") out.options.truth_topic = v.cast<std::string>();
    else if (key == "flaser_angles") out.options.flaser_beam_angles = v.cast<bool>();
    else if (key == "range_max") {
      const double r = v.cast<double>();
      if (!(r > 0) || !std::isfinite(r)) throw Error("expected metres > 0", {}, 0, "range_max");
      out.options.range_max_m = r;
    } else {
      throw Error("unknown reader option (scan_topic, odom_topic, imu_topic, truth_topic, range_max, flaser_angles)", {}, 0, key);
    }
  }
  auto warnings = out.warnings;
  out.options.warn = [warnings](const std::string& w) { warnings->push_back(w); };
  return out;
}

void raise_warnings(const LogRead& read) {
  if (read.warnings->empty()) return;
  const py::object warn = py::module_::import("warnings").attr("warn");
  for (const std::string& w : *read.warnings) warn(w, py::arg("stacklevel") = 3);
}

py::array pose_array(const Pose2& p) { return owning_array(std::vector<double>{p.x, p.y, p.yaw}, {3}); }

py::array trajectory_array(const std::vector<TrajectoryPose>& poses) {
  std::vector<double> v;
  v.reserve(4 * poses.size());
  for (const TrajectoryPose& p : poses) {
    v.push_back(static_cast<double>(p.stamp_us) * 1e-6);
    v.push_back(p.pose.x);
    v.push_back(p.pose.y);
    v.push_back(p.pose.yaw);
  }
  return owning_array(std::move(v), {static_cast<py::ssize_t>(poses.size()), 4});
}

py::object json_value(const nlohmann::ordered_json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// ---- logs ---------------------------------------------------------------------------------------------

// Every scan of a log as its robot received it: the odometry at the scan (NaN without one) and
// the scan's beams, by the same rule the SLAM and localization drivers play the log.
py::dict read_log_arrays(const py::object& path_object, const py::dict& read_kwargs) {
  const std::string path = path_of(path_object);
  const LogRead read = log_read(read_kwargs);
  RobotLog log;
  {
    py::gil_scoped_release release;
    log = with_missing_files({path}, [&] { return read_robot_log(path, read.options); });
  }
  raise_warnings(read);
  const std::size_t n = log.scans.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> t(n), odometry(3 * n, nan), twist(3 * n, 0.0), range_min(n), range_max(n);
  py::list ranges, angles;
  std::vector<ScanMessage> scans;
  scans.reserve(n);
  std::vector<std::optional<OdometryMessage>> odom(n);
  std::size_t reading = 0;
  RobotLogSource source(log);
  source.play(
      [&](const SensorMessage& m) {
        if (const auto* o = std::get_if<OdometryMessage>(&m)) odom[reading] = *o;
        if (const auto* s = std::get_if<ScanMessage>(&m)) scans.push_back(*s);
      },
      [&](std::size_t read_count) { reading = read_count; });
  if (scans.size() != n) throw Error("the log played " + std::to_string(scans.size()) + " scans of " + std::to_string(n), path);
  for (std::size_t i = 0; i < n; ++i) {
    const ScanMessage& s = scans[i];
    t[i] = s.header.t_s;
    if (odom[i]) {
      odometry[3 * i] = odom[i]->pose.x, odometry[3 * i + 1] = odom[i]->pose.y, odometry[3 * i + 2] = odom[i]->pose.yaw;
      twist[3 * i] = odom[i]->twist.vx, twist[3 * i + 1] = odom[i]->twist.vy, twist[3 * i + 2] = odom[i]->twist.wz;
    }
    range_min[i] = s.range_min_m;
    range_max[i] = s.range_max_m;
    std::vector<double> a(s.ranges_m.size());
    for (std::size_t b = 0; b < a.size(); ++b) a[b] = s.angle(b);
    const auto beams = static_cast<py::ssize_t>(a.size());
    ranges.append(owning_array(std::vector<double>(s.ranges_m), {beams}));
    angles.append(owning_array(std::move(a), {beams}));
  }
  const auto rows = static_cast<py::ssize_t>(n);
  py::dict d;
  d["path"] = path;
  d["format"] = log.format;
  d["laser_in_base"] = pose_array(log.laser_in_base.value_or(Pose2()));
  d["t"] = owning_array(std::move(t), {rows});
  d["odometry"] = owning_array(std::move(odometry), {rows, 3});
  d["twist"] = owning_array(std::move(twist), {rows, 3});
  d["range_min"] = owning_array(std::move(range_min), {rows});
  d["range_max"] = owning_array(std::move(range_max), {rows});
  d["ranges"] = ranges;
  d["angles"] = angles;
  return d;
}

// ---- SLAM -----------------------------------------------------------------------------------------------

struct SlamRunHandle {
  std::shared_ptr<SlamRunResult> result;
  std::shared_ptr<const LoadedMap> map;  // the result's map, copied once: every `map` shares it
};

SlamRunHandle slam_run(const py::object& log, const std::string& method, const py::object& relations, bool record_steps,
                       const py::dict& read_kwargs, const py::dict& params) {
  SlamRunRequest q;
  q.log = path_of(log);
  const LogRead read = log_read(read_kwargs);
  q.read = read.options;
  q.method = method;
  q.settings = settings_of(params);
  if (!relations.is_none()) q.relations = path_of(relations);
  q.record_steps = record_steps;
  auto r = std::make_shared<SlamRunResult>();
  {
    py::gil_scoped_release release;
    *r = with_missing_files({q.log, q.relations}, [&] { return run_slam_on_file(q); });
  }
  raise_warnings(read);
  LoadedMap loaded;
  loaded.format = MapFormat::RosMap;
  loaded.map = r->map;
  return {std::move(r), std::make_shared<const LoadedMap>(std::move(loaded))};
}

py::dict graph_dict(const SlamGraph& g) {
  std::vector<std::int64_t> edges(2 * g.edges.size());
  std::vector<double> measurements(3 * g.edges.size()), scores(g.edges.size());
  py::list kinds;
  for (std::size_t i = 0; i < g.edges.size(); ++i) {
    const SlamGraphEdge& e = g.edges[i];
    edges[2 * i] = static_cast<std::int64_t>(e.from), edges[2 * i + 1] = static_cast<std::int64_t>(e.to);
    measurements[3 * i] = e.measurement.x, measurements[3 * i + 1] = e.measurement.y, measurements[3 * i + 2] = e.measurement.yaw;
    scores[i] = e.score;
    kinds.append(slam_edge_kind_name(e.kind));
  }
  const auto n = static_cast<py::ssize_t>(g.edges.size());
  std::vector<std::int64_t> anchors(g.submap_anchors.begin(), g.submap_anchors.end());
  const auto na = static_cast<py::ssize_t>(anchors.size());
  py::dict d;
  d["nodes"] = trajectory_array(g.nodes);
  d["edges"] = owning_array(std::move(edges), {n, 2});
  d["edge_kinds"] = kinds;
  d["measurements"] = owning_array(std::move(measurements), {n, 3});
  d["scores"] = owning_array(std::move(scores), {n});
  d["submap_anchors"] = owning_array(std::move(anchors), {na});
  d["closures"] = g.closures();
  return d;
}

// ---- localization --------------------------------------------------------------------------------------

struct LocalizeRunHandle {
  std::shared_ptr<LocalizeRunResult> result;
};

LocalizeInitial initial_of(const py::object& initial) {
  LocalizeInitial init;
  if (py::isinstance<py::str>(initial)) {
    const std::string s = initial.cast<std::string>();
    if (s == "first") return init;
    if (s == "global") {
      init.kind = LocalizeStart::Global;
      return init;
    }
    throw Error("expected (x, y, yaw) in m and rad, 'global' or 'first', got '" + s + "'", {}, 0, "initial");
  }
  std::vector<double> v;
  try {
    v = initial.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw Error("expected (x, y, yaw) in m and rad, 'global' or 'first'", {}, 0, "initial");
  }
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw Error("expected (x, y, yaw), three finite numbers (m, m, rad)", {}, 0, "initial");
  init.kind = LocalizeStart::Pose;
  init.pose = Pose2(v[0], v[1], wrap_angle(v[2]));
  return init;
}

LocalizeRunHandle localize_run(const py::object& log, const py::object& map, const py::object& initial,
                               const py::object& reference, std::uint64_t seed, bool record_steps, const py::dict& read_kwargs,
                               const py::dict& params) {
  LocalizeRunRequest q;
  q.log = path_of(log);
  const LogRead read = log_read(read_kwargs);
  q.read = read.options;
  if (!reference.is_none()) q.reference = path_of(reference);
  q.initial = initial_of(initial);
  q.seed = seed;
  q.record_steps = record_steps;
  q.settings = settings_of(params);
  auto r = std::make_shared<LocalizeRunResult>();
  if (py::isinstance<OccupancyMapHandle>(map)) {
    // A map in memory (e.g. a SLAM run's): the same run on it, the log and the reference read here.
    const auto& h = map.cast<const OccupancyMapHandle&>();
    std::shared_ptr<const LoadedMap> loaded = h.loaded;
    q.map = h.from_file ? h.source : std::string();
    py::gil_scoped_release release;
    const RobotLog robot_log = with_missing_files({q.log}, [&] { return read_robot_log(q.log, q.read); });
    std::optional<RobotLog> ref;
    if (!q.reference.empty()) ref = with_missing_files({q.reference}, [&] { return read_robot_log(q.reference); });
    *r = run_localize(robot_log, loaded->occupancy(), loaded->thresholds(), ref ? &*ref : nullptr, q);
  } else if (py::isinstance<ElevationMapHandle>(map)) {
    throw Error("is an elevation map; localization needs an occupancy grid", {}, 0, "map");
  } else {
    q.map = path_of(map);
    py::gil_scoped_release release;
    *r = with_missing_files({q.log, q.map, q.reference}, [&] { return run_localize_on_file(q); });
  }
  raise_warnings(read);
  return {std::move(r)};
}

// ---- a localizer fed step by step ---------------------------------------------------------------------

struct LocalizerHandle {
  std::string name;
  std::shared_ptr<const LoadedMap> map;         // kept alive: the localizer points into it
  std::shared_ptr<const ScenarioSpec> scenario;  // likewise (its robot)
  std::unique_ptr<Localizer> localizer;
  Pose2 laser_in_base;
};

Pose2 pose_of(const py::object& p, const char* field) {
  std::vector<double> v;
  try {
    v = p.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw Error("expected (x, y, yaw), three numbers (m, m, rad)", {}, 0, field);
  }
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw Error("expected (x, y, yaw), three finite numbers (m, m, rad)", {}, 0, field);
  return Pose2(v[0], v[1], v[2]);
}

double stamp_of(double t, const char* field) {
  if (!std::isfinite(t)) throw Error("expected a finite time (s)", {}, 0, field);
  return t;
}

// The scenario's settings for localizer `name` (its localization section, when it runs that
// localizer or filters its odometry with it), the keywords replacing those of the same key.
std::vector<ParamSetting> scenario_settings(const LocalizationConfig& config, const std::string& name,
                                            const std::vector<ParamSetting>& keywords) {
  std::vector<ParamSetting> out;
  const ComponentChoice* choice = config.localizer.name == name ? &config.localizer
                                  : config.odometry_filter && config.odometry_filter->name == name ? &*config.odometry_filter
                                                                                                   : nullptr;
  if (choice)
    for (const ParamSetting& v : choice->settings) {
      bool replaced = false;
      for (const ParamSetting& k : keywords) replaced = replaced || k.key == v.key;
      if (!replaced) out.push_back(v);
    }
  out.insert(out.end(), keywords.begin(), keywords.end());
  return out;
}

LocalizerHandle make_localizer_handle(const std::string& name, const py::object& map, const py::object& initial, const py::object& seed,
                                      const py::object& laser_in_base, const py::object& laser_range, const py::object& scenario_path,
                                      const py::object& scenario_text, const std::string& scenario_file, const py::dict& params) {
  std::string warning;
  const LocalizerDef& def = find_localizer(name, "name", &warning);
  warn_deprecated(warning);
  LocalizerHandle h;
  h.name = def.info.name;
  std::vector<ParamSetting> settings = settings_of(params);
  LocalizerContext ctx;
  std::string map_file;
  if (!scenario_path.is_none() || !scenario_text.is_none()) {
    // As the scenario's localization chain builds it: its start, seed, robot and LiDAR.
    auto spec = std::make_shared<const ScenarioSpec>(scenario_of(scenario_path, scenario_text, scenario_file, py::none()));
    ctx = localizer_context(*spec);
    const LocalizationConfig config = localization_config(*spec);
    settings = scenario_settings(config, h.name, settings);
    map_file = config.map_file;
    h.scenario = std::move(spec);
  }
  if (!initial.is_none()) ctx.start = pose_of(initial, "initial");
  if (!seed.is_none()) ctx.seed = seed.cast<std::uint64_t>();
  if (!map.is_none()) {
    if (!py::isinstance<OccupancyMapHandle>(map)) throw Error("expected a starnav.OccupancyMap", {}, 0, "map");
    h.map = map.cast<const OccupancyMapHandle&>().loaded;
  } else if (def.info.has(Capability::NeedsMap) && !map_file.empty()) {
    h.map = std::make_shared<const LoadedMap>(load_map(map_file));
    if (h.map->is_elevation()) throw Error("an elevation map; " + h.name + " needs an occupancy map", map_file, 0, "localization.map");
  }
  if (h.map) {
    ctx.map = &h.map->occupancy();
    ctx.thresholds = h.map->thresholds();
  }
  if (!laser_in_base.is_none()) ctx.laser_in_base = pose_of(laser_in_base, "laser_in_base");
  h.laser_in_base = ctx.laser_in_base;
  if (!laser_range.is_none()) {
    const auto r = laser_range.cast<std::pair<double, double>>();
    ctx.laser_range_min_m = r.first;
    ctx.laser_range_max_m = r.second;
  }
  h.localizer = def.make(ctx, settings);
  return h;
}

py::dict estimate_dict(const PoseEstimate& e) {
  py::dict d;
  d["t"] = e.t_s;
  d["pose"] = pose_array(e.pose);
  std::vector<double> c(9);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(3 * r + k)] = e.covariance(r, k);
  d["covariance"] = owning_array(std::move(c), {3, 3});
  d["valid"] = e.valid;
  d["particles"] = e.particles;
  d["updates"] = e.updates;
  d["converged"] = e.converged;
  return d;
}

}  // namespace

void bind_estimation(py::module_& m) {
  m.def("read_log", &read_log_arrays, py::arg("path"), py::arg("read"),
        "A robot log's scans as its robot received them (dict of arrays).");

  py::class_<SlamRunHandle>(m, "SlamRun", "A 2D SLAM run over a log (starnav.slam.run): `starnav slam run`'s results as arrays.")
      .def_property_readonly("log", [](const SlamRunHandle& h) { return h.result->log; }, "the log's path")
      .def_property_readonly("method", [](const SlamRunHandle& h) { return h.result->method; }, "the SLAM method run")
      .def_property_readonly("scans", [](const SlamRunHandle& h) { return h.result->scans; }, "scans in the log")
      .def_property_readonly("trajectory", [](const SlamRunHandle& h) { return trajectory_array(h.result->trajectory); },
                             "(N, 4) float64: t (s), x, y (m), yaw (rad), the base pose at every scan with odometry")
      .def_property_readonly(
          "map",
          [](const SlamRunHandle& h) {
            OccupancyMapHandle m;
            m.loaded = h.map;
            m.source = "slam";
            return m;
          },
          "the map rendered from every scan at its SLAM pose (a starnav.OccupancyMap; its data is shared by every access)")
      .def_property_readonly(
          "statistics",
          [](const SlamRunHandle& h) {
            py::dict d;
            for (const auto& [k, v] : h.result->statistics) d[py::str(k)] = v;
            return d;
          },
          "the method's statistics (as summary.json's)")
      .def_property_readonly("graph", [](const SlamRunHandle& h) { return graph_dict(h.result->graph); },
                             "the pose graph: nodes (M, 4), edges (E, 2), edge_kinds, measurements (E, 3), scores, "
                             "submap_anchors, closures")
      .def_property_readonly("laser_in_base", [](const SlamRunHandle& h) { return pose_array(h.result->laser_in_base); },
                             "the laser's mount (x, y, yaw)")
      .def_property_readonly("cpu_s", [](const SlamRunHandle& h) { return h.result->cpu_s; }, "thread CPU of the run (s)")
      .def_property_readonly("wall_s", [](const SlamRunHandle& h) { return h.result->wall_s; }, "wall time of the run (s)")
      .def("summary", [](const SlamRunHandle& h) { return json_value(slam_summary_json(*h.result)); },
           "summary.json as a dict (with the relative-pose error when relations were given)")
      .def("trajectory_csv", [](const SlamRunHandle& h) { return trajectory_csv(h.result->trajectory); },
           "trajectory.csv's text, byte for byte")
      .def(
          "write",
          [](const SlamRunHandle& h, const py::object& dir) {
            const std::string d = path_of(dir);
            py::gil_scoped_release release;
            write_slam_outputs(*h.result, d);
          },
          py::arg("folder"), "Writes the outputs of `starnav slam run --out FOLDER` (overwriting).");
  m.def("slam_run", &slam_run, py::arg("log"), py::arg("method"), py::arg("relations"), py::arg("record_steps"), py::arg("read"),
        py::arg("params"), "2D SLAM on a log, as `starnav slam run` (GIL released).");

  py::class_<LocalizeRunHandle>(m, "LocalizeRun", "AMCL over a log on a known map (starnav.localize): `starnav localize`'s results.")
      .def_property_readonly(
          "trajectory",
          [](const LocalizeRunHandle& h) {
            const auto& t = h.result->trajectory;
            std::vector<double> v;
            v.reserve(4 * t.size());
            for (const LocalizePose& p : t)
              v.insert(v.end(), {static_cast<double>(p.stamp_us) * 1e-6, p.pose.x, p.pose.y, p.pose.yaw});
            return owning_array(std::move(v), {static_cast<py::ssize_t>(t.size()), 4});
          },
          "(N, 4) float64: t (s), x, y (m), yaw (rad), the base pose in the map frame at every scan run")
      .def_property_readonly(
          "converged",
          [](const LocalizeRunHandle& h) {
            std::vector<std::uint8_t> v;
            for (const LocalizePose& p : h.result->trajectory) v.push_back(p.converged ? 1 : 0);
            const auto n = static_cast<py::ssize_t>(v.size());
            return owning_array(std::move(v), {n}).attr("astype")("bool");
          },
          "(N,) bool: the filter's converged flag at each scan")
      .def_property_readonly(
          "particles",
          [](const LocalizeRunHandle& h) {
            std::vector<std::int32_t> v;
            for (const LocalizePose& p : h.result->trajectory) v.push_back(p.particles);
            const auto n = static_cast<py::ssize_t>(v.size());
            return owning_array(std::move(v), {n});
          },
          "(N,) int32: the particles at each scan")
      .def_property_readonly(
          "errors",
          [](const LocalizeRunHandle& h) {
            const auto& e = h.result->errors;
            std::vector<double> v;
            for (const LocalizeError& x : e) v.insert(v.end(), {static_cast<double>(x.stamp_us) * 1e-6, x.err_m, x.err_deg});
            return owning_array(std::move(v), {static_cast<py::ssize_t>(e.size()), 3});
          },
          "(M, 3) float64: t (s), error (m), error (deg) of the laser pose at each scan with a corrected twin")
      .def_property_readonly("initial_pose", [](const LocalizeRunHandle& h) { return pose_array(h.result->initial_pose); },
                             "the base pose the cloud started around")
      .def_property_readonly("updates", [](const LocalizeRunHandle& h) { return h.result->updates; }, "filter updates")
      .def("summary", [](const LocalizeRunHandle& h) { return json_value(localize_summary_json(*h.result)); },
           "summary.json as a dict")
      .def("trajectory_csv", [](const LocalizeRunHandle& h) { return localize_trajectory_csv(*h.result); },
           "trajectory.csv's text, byte for byte")
      .def("errors_csv", [](const LocalizeRunHandle& h) { return localize_errors_csv(*h.result); }, "errors.csv's text")
      .def(
          "write",
          [](const LocalizeRunHandle& h, const py::object& dir) {
            const std::string d = path_of(dir);
            py::gil_scoped_release release;
            write_localize_outputs(*h.result, d);
          },
          py::arg("folder"), "Writes the outputs of `starnav localize --out FOLDER` (overwriting).");
  m.def("localize_run", &localize_run, py::arg("log"), py::arg("map"), py::arg("initial"), py::arg("reference"), py::arg("seed"),
        py::arg("record_steps"), py::arg("read"), py::arg("params"), "AMCL on a log, as `starnav localize` (GIL released).");

  py::class_<LocalizerHandle>(m, "Localizer", "A localizer of the registry fed message by message (the Localizer role).")
      .def(py::init(&make_localizer_handle), py::arg("name"), py::arg("map"), py::arg("initial"), py::arg("seed"),
           py::arg("laser_in_base"), py::arg("laser_range"), py::arg("scenario_path"), py::arg("scenario_text"),
           py::arg("scenario_file"), py::arg("params"))
      .def_property_readonly("name", [](const LocalizerHandle& h) { return h.name; }, "the registry's name")
      .def(
          "on_odometry",
          [](LocalizerHandle& h, double t, const py::object& pose, const py::object& twist) {
            OdometryMessage o;
            o.header.t_s = stamp_of(t, "t");
            o.header.stream = "odom";
            o.pose = pose_of(pose, "pose");
            const Pose2 v = pose_of(twist, "twist");
            o.twist.vx = v.x, o.twist.vy = v.y, o.twist.wz = v.yaw;
            h.localizer->on_odometry(o);
          },
          py::arg("t"), py::arg("pose"), py::arg("twist"))
      .def(
          "on_imu",
          [](LocalizerHandle& h, double t, const py::object& yaw, const py::object& angular_velocity) {
            ImuMessage m;
            m.header.t_s = stamp_of(t, "t");
            m.header.stream = "imu";
            if (!yaw.is_none()) {
              const double y = yaw.cast<double>();
              if (!std::isfinite(y)) throw Error("expected a finite yaw (rad)", {}, 0, "yaw");
              m.yaw_rad = y;
            }
            const auto w = angular_velocity.cast<std::vector<double>>();
            if (w.size() != 3 || !std::isfinite(w[0]) || !std::isfinite(w[1]) || !std::isfinite(w[2]))
              throw Error("expected (wx, wy, wz), three finite numbers (rad/s)", {}, 0, "angular_velocity");
            m.angular_velocity_radps = Vec3(w[0], w[1], w[2]);
            h.localizer->on_imu(m);
          },
          py::arg("t"), py::arg("yaw"), py::arg("angular_velocity"))
      .def(
          "on_scan",
          [](LocalizerHandle& h, const py::object& ranges, const py::object& angles, double t, double range_min, double range_max,
             const std::string& stream, const py::object& mount) {
            const auto numpy = py::module_::import("numpy");
            const auto r = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
                numpy.attr("asarray")(ranges, py::arg("dtype") = "float64"));
            const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
                numpy.attr("asarray")(angles, py::arg("dtype") = "float64"));
            if (!r || r.ndim() != 1) throw Error("expected a 1D array of ranges (m)", {}, 0, "ranges");
            if (!a || a.ndim() != 1 || a.shape(0) != r.shape(0)) throw Error("expected a 1D array of angles (rad), one per range", {}, 0, "angles");
            if (!(range_min >= 0) || !(range_max > range_min)) throw Error("expected 0 <= range_min < range_max", {}, 0, "range_max");
            ScanMessage s;
            s.header.t_s = stamp_of(t, "stamp");
            s.header.stream = stream;
            const Pose2 mp = mount.is_none() ? h.laser_in_base : pose_of(mount, "mount");
            s.mount = Pose3::from_rpy(Vec3(mp.x, mp.y, 0.0), 0.0, 0.0, mp.yaw);
            s.range_min_m = range_min;
            s.range_max_m = range_max;
            s.ranges_m.assign(r.data(), r.data() + r.shape(0));
            s.angles_rad.assign(a.data(), a.data() + a.shape(0));
            for (double x : s.angles_rad)
              if (!std::isfinite(x)) throw Error("expected finite angles (rad)", {}, 0, "angles");
            // The GIL stays held: a localizer is one mutable object, and another thread could
            // otherwise feed it at the same time (one scan's update takes milliseconds).
            h.localizer->on_scan(s);
          },
          py::arg("ranges"), py::arg("angles"), py::arg("stamp"), py::arg("range_min"), py::arg("range_max"), py::arg("stream"),
          py::arg("mount"))
      .def(
          "on_ground_truth",
          [](LocalizerHandle& h, double t, const py::object& pose) { h.localizer->on_ground_truth(stamp_of(t, "t"), pose_of(pose, "pose")); },
          py::arg("t"), py::arg("pose"))
      .def("estimate", [](const LocalizerHandle& h) { return estimate_dict(h.localizer->estimate()); },
           "the estimate: t, pose (3,), covariance (3, 3), valid, particles, updates, converged")
      .def(
          "belief_samples",
          [](const LocalizerHandle& h, std::size_t max) {
            const std::vector<Pose2> s = h.localizer->belief_samples(max);
            std::vector<double> v;
            v.reserve(3 * s.size());
            for (const Pose2& p : s) v.insert(v.end(), {p.x, p.y, p.yaw});
            return owning_array(std::move(v), {static_cast<py::ssize_t>(s.size()), 3});
          },
          py::arg("max"), "at most `max` poses drawn evenly from the belief, (K, 3)");
}

}  // namespace starnav::python
