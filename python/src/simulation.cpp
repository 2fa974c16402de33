// The simulator from Python (docs/python.md, "The simulator"): a scenario read from a file or from
// YAML text (the package turns a dict into it), stepped or run with the GIL released, its sensor
// streams recorded as they are taken and handed out as arrays (copies: they stay valid after the
// simulation is gone and do not change as it runs on), the robot commanded with a body twist or by
// a Python callable; and navigation scenarios run to the end with their records, a Python object
// optionally playing the LocalController role through a C++ adapter the navigator is given.
#include <Python.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "starnav/control/local_controller.hpp"
#include "starnav/core/error.hpp"
#include "starnav/harness/lidar_frame_recorder.hpp"
#include "starnav/harness/localization_chain.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/harness/route_drive.hpp"
#include "starnav/io/yaml_document.hpp"
#include "starnav/sim/scenario.hpp"
#include "starnav/sim/simulation.hpp"

namespace starnav::python {

std::vector<ScenarioOverride> overrides_of(const py::object& sets) {
  std::vector<ScenarioOverride> out;
  if (sets.is_none()) return out;
  for (const auto& [k, v] : sets.cast<py::dict>()) {
    const std::string key = py::str(k);
    out.push_back({key, setting_text(v, key)});
  }
  check_user_overrides(out);
  return out;
}

ScenarioSpec scenario_of(const py::object& path, const py::object& text, const std::string& file, const py::object& sets) {
  const std::vector<ScenarioOverride> overrides = overrides_of(sets);
  if (!text.is_none()) return parse_scenario(text.cast<std::string>(), file, overrides);
  return load_scenario(py::str(path).cast<std::string>(), overrides);
}

namespace {

// ---- scenarios ----------------------------------------------------------------------------------------


// A YAML scalar as Python reads it: quoted -> str; plain -> bool, int, float or str as it parses.
py::object scalar_of(const YAML::Node& n) {
  const std::string& s = n.Scalar();
  if (n.Tag() == "!") return py::str(s);
  if (s == "true" || s == "True") return py::bool_(true);
  if (s == "false" || s == "False") return py::bool_(false);
  if (s.empty() || s == "~" || s == "null") return py::none();
  const py::module_ builtins = py::module_::import("builtins");
  for (const char* type : {"int", "float"}) {
    try {
      return builtins.attr(type)(s);
    } catch (const py::error_already_set&) {
    }
  }
  return py::str(s);
}

py::object node_to_python(const YAML::Node& n) {
  if (n.IsMap()) {
    py::dict d;
    for (const auto& kv : n) d[py::str(kv.first.Scalar())] = node_to_python(kv.second);
    return d;
  }
  if (n.IsSequence()) {
    py::list l;
    for (const auto& item : n) l.append(node_to_python(item));
    return l;
  }
  if (n.IsScalar()) return scalar_of(n);
  return py::none();
}

// ---- what a run records beside the simulation's own records --------------------------------------------

// Every scan of one LiDAR stream: its ranges (lines x beams per scan, +inf: no return).
struct LidarRecord {
  std::string stream;
  int lines = 0, beams = 0;
  std::vector<double> azimuths, elevations;
  std::vector<double> t;
  std::vector<double> ranges;
};

struct OdometryRow {
  double t_s;
  Pose2 pose;
  BodyTwist twist;
};

class StreamRecorder {
 public:
  // Subscribes to every LiDAR stream and the bumper of `sim` (SampleStage::Record), and to the wheel
  // odometry of `bus` when given.
  void attach(Simulation& sim, SensorBus* bus) {
    for (const std::string& stream : sim.lidar_streams()) lidars_.push_back({stream, 0, 0, {}, {}, {}, {}});
    for (std::size_t i = 0; i < lidars_.size(); ++i)
      sim.lidar_feed(lidars_[i].stream).subscribe(SampleStage::Record, [this, i](const LidarScan& scan) {
        LidarRecord& r = lidars_[i];
        if (r.t.empty()) {
          r.lines = scan.lines;
          r.beams = scan.beams;
          r.azimuths = scan.azimuths;
          r.elevations = scan.elevations;
        }
        r.t.push_back(scan.time);
        r.ranges.insert(r.ranges.end(), scan.ranges.begin(), scan.ranges.end());
      });
    sim.bumper_feed.subscribe(SampleStage::Record, [this](const BumperReading& b) { bumper_.push_back(b); });
    if (bus) {
      has_odometry_ = true;
      bus->subscribe<OdometryMessage>(kOdometryStream, [this](const OdometryMessage& o) {
        odometry_.push_back({o.header.t_s, o.pose, o.twist});
      });
    }
  }

  const LidarRecord& lidar(const std::string& stream) const {
    for (const LidarRecord& r : lidars_)
      if (r.stream == stream) return r;
    std::string known;
    for (const LidarRecord& r : lidars_) known += (known.empty() ? "" : ", ") + r.stream;
    throw Error("no LiDAR stream '" + stream + "' (" + (known.empty() ? "the scenario has no LiDAR" : "streams: " + known) + ")",
                {}, 0, "stream");
  }
  const std::vector<BumperReading>& bumper() const { return bumper_; }
  bool has_odometry() const { return has_odometry_; }
  const std::vector<OdometryRow>& odometry() const { return odometry_; }

 private:
  std::vector<LidarRecord> lidars_;
  std::vector<BumperReading> bumper_;
  bool has_odometry_ = false;
  std::vector<OdometryRow> odometry_;
};

// ---- arrays ---------------------------------------------------------------------------------------------

py::array rows_array(std::vector<double>&& v, std::size_t columns) {
  const auto n = static_cast<py::ssize_t>(v.size() / columns);
  return owning_array(std::move(v), {n, static_cast<py::ssize_t>(columns)});
}

py::array trajectory_array(const std::vector<TrajectorySample>& samples) {
  std::vector<double> v;
  v.reserve(samples.size() * 10);
  for (const TrajectorySample& s : samples)
    for (const double x : {s.t_s, s.position.x(), s.position.y(), s.position.z(), s.rpy.x(), s.rpy.y(), s.rpy.z(), s.twist.vx,
                           s.twist.vy, s.twist.wz})
      v.push_back(x);
  return rows_array(std::move(v), 10);
}

py::array state_array(const Simulation& sim) {
  const VehicleState& s = sim.vehicle().state();
  const Vec3 rpy = s.pose.rpy();
  std::vector<double> v{sim.time(), s.pose.position.x(), s.pose.position.y(), s.pose.position.z(), rpy.x(), rpy.y(), rpy.z(),
                        s.twist.vx, s.twist.vy, s.twist.wz};
  return owning_array(std::move(v), {10});
}

py::array imu_array(const std::vector<ImuModel::ImuReading>& readings) {
  std::vector<double> v;
  for (const ImuModel::ImuReading& r : readings)
    for (const double x : {r.t_s, r.yaw_rate_radps, r.yaw_rad}) v.push_back(x);
  return rows_array(std::move(v), 3);
}

py::tuple encoder_arrays(const std::vector<EncoderSample>& samples) {
  std::vector<double> t;
  std::vector<std::int64_t> ticks;
  const std::size_t wheels = samples.empty() ? 0 : samples.front().ticks.size();
  for (const EncoderSample& s : samples) {
    t.push_back(s.t_s);
    ticks.insert(ticks.end(), s.ticks.begin(), s.ticks.end());
  }
  const auto n = static_cast<py::ssize_t>(samples.size());
  return py::make_tuple(owning_array(std::move(t), {n}), owning_array(std::move(ticks), {n, static_cast<py::ssize_t>(wheels)}));
}

py::array lidar_summary_array(const std::vector<LidarScanSummary>& scans) {
  std::vector<double> v;
  for (const LidarScanSummary& s : scans)
    for (const double x : {s.t_s, s.sensor_position.x(), s.sensor_position.y(), s.sensor_position.z(), static_cast<double>(s.rays),
                           static_cast<double>(s.returns), static_cast<double>(s.dropped), static_cast<double>(s.self_filtered),
                           s.min_range_m})
      v.push_back(x);
  return rows_array(std::move(v), 9);
}

py::dict lidar_dict(const LidarRecord& r) {
  py::dict d;
  const auto n = static_cast<py::ssize_t>(r.t.size());
  d["stream"] = r.stream;
  d["t_s"] = owning_array(std::vector<double>(r.t), {n});
  d["angles_rad"] = owning_array(std::vector<double>(r.azimuths), {static_cast<py::ssize_t>(r.azimuths.size())});
  d["elevations_rad"] = owning_array(std::vector<double>(r.elevations), {static_cast<py::ssize_t>(r.elevations.size())});
  std::vector<double> ranges(r.ranges);
  if (r.lines == 1)
    d["ranges_m"] = owning_array(std::move(ranges), {n, r.beams});
  else
    d["ranges_m"] = owning_array(std::move(ranges), {n, r.lines, r.beams});
  return d;
}

// The last scan of a stream (its ranges (beams,) or (lines, beams)), or None before the first.
py::object latest_scan_dict(const LidarRecord& r) {
  if (r.t.empty()) return py::none();
  py::dict d;
  const std::size_t rays = static_cast<std::size_t>(r.lines) * static_cast<std::size_t>(r.beams);
  d["stream"] = r.stream;
  d["t_s"] = r.t.back();
  d["angles_rad"] = owning_array(std::vector<double>(r.azimuths), {static_cast<py::ssize_t>(r.azimuths.size())});
  d["elevations_rad"] = owning_array(std::vector<double>(r.elevations), {static_cast<py::ssize_t>(r.elevations.size())});
  std::vector<double> ranges(r.ranges.end() - static_cast<std::ptrdiff_t>(rays), r.ranges.end());
  if (r.lines == 1)
    d["ranges_m"] = owning_array(std::move(ranges), {r.beams});
  else
    d["ranges_m"] = owning_array(std::move(ranges), {r.lines, r.beams});
  return d;
}

py::tuple bumper_arrays(const std::vector<BumperReading>& readings) {
  std::vector<double> t;
  std::vector<std::uint8_t> contact;
  for (const BumperReading& b : readings) {
    t.push_back(b.t_s);
    contact.push_back(b.contact ? 1 : 0);
  }
  const auto n = static_cast<py::ssize_t>(readings.size());
  return py::make_tuple(owning_array(std::move(t), {n}), owning_array(std::move(contact), {n}).attr("view")("bool"));
}

py::array odometry_array(const std::vector<OdometryRow>& rows) {
  std::vector<double> v;
  for (const OdometryRow& o : rows)
    for (const double x : {o.t_s, o.pose.x, o.pose.y, o.pose.yaw, o.twist.vx, o.twist.vy, o.twist.wz}) v.push_back(x);
  return rows_array(std::move(v), 7);
}

py::list events_list(const std::vector<SimEvent>& events) {
  py::list l;
  for (const SimEvent& e : events) l.append(py::make_tuple(e.t_s, e.kind, e.detail, e.where.x(), e.where.y()));
  return l;
}

py::object json_loads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

BodyTwist twist_of(const py::handle& value, const char* who) {
  const auto fail = [&] {
    return py::type_error(std::string(who) + ": expected (vx, vy, wz) in m/s, m/s and rad/s, got " +
                          py::repr(value).cast<std::string>());
  };
  if (!PyTuple_Check(value.ptr()) && !PyList_Check(value.ptr())) throw fail();
  const py::sequence s = py::reinterpret_borrow<py::sequence>(value);
  if (s.size() != 3) throw fail();
  BodyTwist t{PyFloat_AsDouble(s[0].ptr()), PyFloat_AsDouble(s[1].ptr()), PyFloat_AsDouble(s[2].ptr())};
  if (PyErr_Occurred()) throw py::error_already_set();
  if (!std::isfinite(t.vx) || !std::isfinite(t.vy) || !std::isfinite(t.wz))
    throw py::value_error(std::string(who) + ": a command must be finite, got " + py::repr(value).cast<std::string>());
  return t;
}

// While the GIL is released: Ctrl-C (and any signal handler's exception) ends a long run.
void check_signals() {
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

// The localization chain's records (estimate.csv's rows at full precision): t, scan (bool), truth
// (N, 3), pose (N, 3), covariance (N, 3, 3), particles, updates, converged.
py::dict estimates_dict(const std::vector<EstimateRecord>& records) {
  const auto n = static_cast<py::ssize_t>(records.size());
  std::vector<double> t, truth, pose, cov;
  std::vector<std::uint8_t> scan, converged;
  std::vector<std::int64_t> particles, updates;
  for (const EstimateRecord& r : records) {
    t.push_back(r.t_s);
    scan.push_back(r.scan ? 1 : 0);
    truth.insert(truth.end(), {r.truth.x, r.truth.y, r.truth.yaw});
    pose.insert(pose.end(), {r.estimate.pose.x, r.estimate.pose.y, r.estimate.pose.yaw});
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) cov.push_back(r.estimate.covariance(i, k));
    particles.push_back(r.estimate.particles);
    updates.push_back(static_cast<std::int64_t>(r.estimate.updates));
    converged.push_back(r.estimate.converged ? 1 : 0);
  }
  py::dict d;
  d["t"] = owning_array(std::move(t), {n});
  d["scan"] = owning_array(std::move(scan), {n}).attr("astype")("bool");
  d["truth"] = owning_array(std::move(truth), {n, 3});
  d["pose"] = owning_array(std::move(pose), {n, 3});
  d["covariance"] = owning_array(std::move(cov), {n, 3, 3});
  d["particles"] = owning_array(std::move(particles), {n});
  d["updates"] = owning_array(std::move(updates), {n});
  d["converged"] = owning_array(std::move(converged), {n}).attr("astype")("bool");
  return d;
}

// ---- the simulation -------------------------------------------------------------------------------------

struct SimulationHandle {
  std::unique_ptr<Simulation> sim;
  std::unique_ptr<LocalizationChain> chain;
  std::unique_ptr<RouteDrive> route;
  std::function<BodyTwist(double)> scripted;  // the route's drive, else empty (the scenario's script)
  StreamRecorder recorder;
  std::optional<BodyTwist> command;  // given from Python: held until the next
  PyObject* controller = nullptr;    // run(controller=...): called at every step (borrowed for the run)
  PyObject* self = nullptr;
  bool broken = false;  // an exception ended a step midway: the state is no longer a run's
  std::unique_ptr<LidarFrameRecorder> lidar_frames;  // outputs.lidar_frames, into a folder given from Python

  explicit SimulationHandle(const ScenarioSpec& spec) {
    sim = std::make_unique<Simulation>(spec);
    // As `starnav sim` runs a scenario: its localization chain, its route; the chain also turns the
    // encoders into wheel odometry (robots with encoders), recorded here.
    const LocalizationConfig config = localization_config(spec);
    if (spec.localization || config.odometry != "none") chain = std::make_unique<LocalizationChain>(*sim, config);
    if (spec.route) route = make_route_drive(*sim);
    scripted = sim->command_source;
    recorder.attach(*sim, chain && config.odometry != "none" ? &chain->bus() : nullptr);
    sim->command_source = [this](double t) {
      if (controller) {
        py::gil_scoped_acquire gil;
        return twist_of(py::reinterpret_borrow<py::object>(controller)(py::handle(self)), "controller");
      }
      if (command) return *command;
      if (scripted) return scripted(t);
      return sim->spec().command_at(t);
    };
  }

  void check_usable() const {
    if (broken) throw py::value_error("the simulation was ended by an exception at t = " + format_param_real(sim->time()) + " s");
  }

  // Runs steps (GIL released) until `until` or the end; an exception marks the simulation broken.
  void advance(std::int64_t steps, const py::object& self_object, const py::object& controller_object) {
    check_usable();
    if (!controller_object.is_none() && !PyCallable_Check(controller_object.ptr()))
      throw py::type_error("controller: expected a callable f(sim) -> (vx, vy, wz)");
    controller = controller_object.is_none() ? nullptr : controller_object.ptr();
    self = self_object.ptr();
    const std::int64_t every = std::max<std::int64_t>(1, steps / 100);
    try {
      py::gil_scoped_release release;
      for (std::int64_t i = 0; i < steps && !sim->finished(); ++i) {
        sim->step();
        if ((i + 1) % every == 0) check_signals();
      }
    } catch (...) {
      controller = nullptr;
      broken = true;
      throw;
    }
    controller = nullptr;
    if (lidar_frames) lidar_frames->finish();  // frames.csv as far as the run went
  }
};

std::int64_t steps_until(const Simulation& sim, const py::object& until_s) {
  const std::int64_t left = sim.total_steps() - sim.step_count();
  if (until_s.is_none()) return left;
  const double until = until_s.cast<double>();
  if (!std::isfinite(until)) throw Error("expected a finite time in seconds", {}, 0, "until_s");
  // Steps whose end time is at most `until` (times are k dt; a hair of tolerance for k dt's rounding).
  const double k = std::floor(until / sim.spec().dt_s + 1e-9);
  return std::clamp<std::int64_t>(static_cast<std::int64_t>(k) - sim.step_count(), 0, left);
}

// ---- the Python local controller ------------------------------------------------------------------------

// What a Python controller is given at each control step (copies: valid after the step).
struct ControlInputView {
  double t_s = 0.0;
  Pose2 pose;
  BodyTwist velocity;
  Vec2 goal = Vec2::Zero();
  std::optional<double> goal_yaw;
  double goal_tolerance_m = 0.0, goal_yaw_tolerance_rad = 0.0;
  bool goal_xy_reached = false;
  VelocityLimits limits;
  py::object path;  // the path being followed, (N, 2), read-only (shared by the steps of one path)
};

ControlStatus status_of(const std::string& name) {
  for (const ControlStatus s : {ControlStatus::Idle, ControlStatus::Tracking, ControlStatus::Arrived, ControlStatus::CannotReach,
                                ControlStatus::Blocked, ControlStatus::AtCusp})
    if (name == control_status_name(s)) return s;
  throw py::value_error("controller: unknown status '" + name + "' (idle, tracking, arrived, cannot_reach, blocked, at_cusp)");
}

// The LocalController role played by a Python object: compute(input) -> (vx, vy, wz) or
// (vx, vy, wz, status); set_path(points) and clear() when it has them. The GIL is taken for each
// call (the run releases it); a Python exception leaves through the navigator and the simulation
// and is raised again, as it was, by the call that ran them.
class PythonController final : public LocalController {
 public:
  PythonController(PyObject* object, std::string name, double period_s) : object_(object), name_(std::move(name)), period_s_(period_s) {}
  ~PythonController() override {
    // Made and destroyed with the GIL held (the navigation object's lifetime), but its path array is
    // a Python object: drop it under the GIL in any case.
    py::gil_scoped_acquire gil;
    path_array_ = py::object();
  }
  std::string_view name() const override { return name_; }
  void set_path(std::span<const Vec2> points) override {
    if (points.empty()) throw Error("empty path", {}, 0, "path");
    path_.assign(points.begin(), points.end());
    py::gil_scoped_acquire gil;
    std::vector<double> xy;
    for (const Vec2& p : path_) xy.insert(xy.end(), {p.x(), p.y()});
    py::array a = owning_array(std::move(xy), {static_cast<py::ssize_t>(path_.size()), 2});
    a.attr("setflags")(py::arg("write") = false);
    path_array_ = a;
    const py::handle o(object_);
    if (py::hasattr(o, "set_path")) o.attr("set_path")(path_array_);
  }
  void clear() override {
    path_.clear();
    py::gil_scoped_acquire gil;
    path_array_ = py::none();
    const py::handle o(object_);
    if (py::hasattr(o, "clear")) o.attr("clear")();
  }
  bool has_path() const override { return !path_.empty(); }
  const std::vector<Vec2>& path() const override { return path_; }
  double control_period_s() const override { return period_s_; }

  ControlOutput compute(const ControlInput& in) override {
    py::gil_scoped_acquire gil;
    ControlInputView v;
    v.t_s = in.t_s;
    v.pose = in.pose;
    v.velocity = in.velocity;
    v.goal = in.goal;
    v.goal_yaw = in.goal_yaw;
    v.goal_tolerance_m = in.goal_tolerance_m;
    v.goal_yaw_tolerance_rad = in.goal_yaw_tolerance_rad;
    v.goal_xy_reached = in.goal_xy_reached;
    v.limits = in.limits;
    v.path = path_array_ ? path_array_ : py::none();
    const py::object out = py::handle(object_).attr("compute")(std::move(v));
    ControlOutput result;
    result.status = ControlStatus::Tracking;
    if ((PyTuple_Check(out.ptr()) || PyList_Check(out.ptr())) && py::len(out) == 4) {
      const py::sequence s = py::reinterpret_borrow<py::sequence>(out);
      result.twist = twist_of(py::make_tuple(s[0], s[1], s[2]), "controller.compute");
      result.status = status_of(py::str(s[3]));
    } else {
      result.twist = twist_of(out, "controller.compute");
    }
    return result;
  }

 private:
  PyObject* object_;  // kept alive by the navigation call that runs it
  std::string name_;
  double period_s_;
  std::vector<Vec2> path_;
  py::object path_array_;
};

// A finished navigation run and what it recorded.
struct NavigationHandle {
  py::object controller;  // the Python controller, if any (outlives the run, which points at it)
  std::unique_ptr<NavigationRun> run;
  StreamRecorder recorder;
};

std::unique_ptr<NavigationHandle> navigate(const py::object& path, const py::object& text, const std::string& file,
                                           const py::object& sets, const py::object& controller, const py::object& planner,
                                           bool record_steps) {
  const ScenarioSpec spec = scenario_of(path, text, file, sets);
  auto h = std::make_unique<NavigationHandle>();
  NavigationOptions options;
  options.record_steps = record_steps;
  if (!planner.is_none()) options.planner = planner.cast<std::string>();
  if (!controller.is_none()) {
    if (!py::hasattr(controller, "compute")) throw py::type_error("controller: expected an object with compute(input) -> (vx, vy, wz)");
    h->controller = controller;
    const std::string name = py::hasattr(controller, "name") ? py::str(controller.attr("name")).cast<std::string>()
                                                             : py::str(py::type::of(controller).attr("__name__")).cast<std::string>();
    const double period = py::hasattr(controller, "control_period_s") ? controller.attr("control_period_s").cast<double>() : 0.0;
    if (!std::isfinite(period) || period < 0.0) throw Error("must be >= 0 seconds", {}, 0, "controller.control_period_s");
    if (py::hasattr(controller, "goal_heading") && controller.attr("goal_heading").cast<bool>())
      options.controller_capabilities = Capabilities{Capability::GoalHeading};
    PyObject* object = controller.ptr();
    options.make_controller = [object, name, period](const LocalControllerContext&) -> std::unique_ptr<LocalController> {
      return std::make_unique<PythonController>(object, name, period);
    };
  }
  h->run = std::make_unique<NavigationRun>(spec, options);
  h->recorder.attach(h->run->simulation(), nullptr);
  {
    py::gil_scoped_release release;
    h->run->run([](double) { check_signals(); });
  }
  return h;
}

py::list plans_list(const Navigator& nav) {
  py::list l;
  for (const NavPlan& p : nav.plans()) {
    py::dict d;
    d["id"] = p.id;
    d["t_s"] = p.t_s;
    d["cause"] = p.cause;
    d["status"] = p.status;
    d["expanded"] = p.expanded;
    d["cost_m"] = p.cost_m;
    std::vector<double> xy;
    for (const Vec2& q : p.points) xy.insert(xy.end(), {q.x(), q.y()});
    d["points"] = owning_array(std::move(xy), {static_cast<py::ssize_t>(p.points.size()), 2});
    l.append(d);
  }
  return l;
}

py::array arrivals_array(const std::vector<NavArrival>& arrivals) {
  std::vector<double> v;
  for (const NavArrival& a : arrivals)
    for (const double x : {static_cast<double>(a.goal), static_cast<double>(a.lap), a.t_s, a.settled_t_s, a.truth.x, a.truth.y,
                           a.truth.yaw, a.estimate.x, a.estimate.y, a.estimate.yaw})
      v.push_back(x);
  return rows_array(std::move(v), 10);
}

}  // namespace

void bind_simulation(py::module_& m) {
  m.def(
      "scenario_document",
      [](const std::string& path) { return node_to_python(load_yaml_document(read_yaml_file(path), path)); },
      py::arg("path"), "A scenario file's YAML as a dict (to edit and give to Simulation or navigate).");

  py::class_<ControlInputView>(m, "ControlInput", R"doc(
What a Python local controller's compute() is given at each control step: the time, the localizer's
pose (x, y, yaw) in the map frame, the robot's body twist (vx, vy, wz), the goal (x, y) and its
heading (None without one), the goal tolerances, whether the goal position is reached (only the
heading remains), the velocity limits (max_vx, max_vy, max_yaw_rate, max_speed) and the path being
followed, (N, 2) read-only (None without one).)doc")
      .def_property_readonly("t_s", [](const ControlInputView& v) { return v.t_s; })
      .def_property_readonly("pose", [](const ControlInputView& v) { return py::make_tuple(v.pose.x, v.pose.y, v.pose.yaw); })
      .def_property_readonly("x", [](const ControlInputView& v) { return v.pose.x; })
      .def_property_readonly("y", [](const ControlInputView& v) { return v.pose.y; })
      .def_property_readonly("yaw", [](const ControlInputView& v) { return v.pose.yaw; })
      .def_property_readonly("velocity",
                             [](const ControlInputView& v) { return py::make_tuple(v.velocity.vx, v.velocity.vy, v.velocity.wz); })
      .def_property_readonly("goal", [](const ControlInputView& v) { return py::make_tuple(v.goal.x(), v.goal.y()); })
      .def_property_readonly("goal_yaw", [](const ControlInputView& v) { return v.goal_yaw ? py::object(py::float_(*v.goal_yaw)) : py::object(py::none()); })
      .def_property_readonly("goal_tolerance_m", [](const ControlInputView& v) { return v.goal_tolerance_m; })
      .def_property_readonly("goal_yaw_tolerance_rad", [](const ControlInputView& v) { return v.goal_yaw_tolerance_rad; })
      .def_property_readonly("goal_xy_reached", [](const ControlInputView& v) { return v.goal_xy_reached; })
      .def_property_readonly("limits",
                             [](const ControlInputView& v) {
                               return py::make_tuple(v.limits.max_vx_mps, v.limits.max_vy_mps, v.limits.max_yaw_rate_radps,
                                                     v.limits.max_speed_mps);
                             })
      .def_property_readonly("path", [](const ControlInputView& v) { return v.path; });

  py::class_<SimulationHandle>(m, "_Simulation")
      .def(py::init([](const py::object& path, const py::object& text, const std::string& file, const py::object& sets,
                       const py::object& lidar_frames) {
             auto h = std::make_unique<SimulationHandle>(scenario_of(path, text, file, sets));
             if (!lidar_frames.is_none()) {
               // As `starnav sim --out` records outputs.lidar_frames (every scan unless the scenario says).
               const int every = std::max(1, h->sim->spec().outputs.lidar_frames_every_n_scans);
               h->lidar_frames = std::make_unique<LidarFrameRecorder>(*h->sim, path_of(lidar_frames), every);
             }
             return h;
           }),
           py::arg("path"), py::arg("text"), py::arg("file"), py::arg("sets"), py::arg("lidar_frames"))
      .def_property_readonly("name", [](const SimulationHandle& h) { return h.sim->spec().name; })
      .def_property_readonly("time", [](const SimulationHandle& h) { return h.sim->time(); })
      .def_property_readonly("dt", [](const SimulationHandle& h) { return h.sim->spec().dt_s; })
      .def_property_readonly("duration", [](const SimulationHandle& h) { return h.sim->spec().duration_s; })
      .def_property_readonly("step_count", [](const SimulationHandle& h) { return h.sim->step_count(); })
      .def_property_readonly("total_steps", [](const SimulationHandle& h) { return h.sim->total_steps(); })
      .def_property_readonly("finished", [](const SimulationHandle& h) { return h.sim->finished(); })
      .def_property_readonly("lidar_streams", [](const SimulationHandle& h) { return h.sim->lidar_streams(); })
      .def_property_readonly("pose", [](const SimulationHandle& h) {
        const Pose2 p = h.sim->vehicle().state().pose.to_pose2();
        return owning_array(std::vector<double>{p.x, p.y, p.yaw}, {3});
      })
      .def("state", [](const SimulationHandle& h) { return state_array(*h.sim); })
      .def("command",
           [](SimulationHandle& h, const py::object& vx, double vy, double wz) {
             if (vx.is_none()) {
               h.command.reset();
               return;
             }
             h.command = twist_of(py::make_tuple(vx, vy, wz), "command");
           },
           py::arg("vx"), py::arg("vy") = 0.0, py::arg("wz") = 0.0)
      .def_property_readonly("commanded", [](const SimulationHandle& h) -> py::object {
        if (!h.command) return py::none();
        return py::make_tuple(h.command->vx, h.command->vy, h.command->wz);
      })
      .def("advance", &SimulationHandle::advance, py::arg("steps"), py::arg("self"), py::arg("controller"))
      .def("steps_until", [](const SimulationHandle& h, const py::object& until) { return steps_until(*h.sim, until); })
      .def("stop", [](SimulationHandle& h) { h.sim->stop(); })
      .def("teleport", [](SimulationHandle& h, double x, double y, double yaw) { h.sim->teleport(Pose2(x, y, yaw)); })
      .def("trajectory", [](const SimulationHandle& h) { return trajectory_array(h.sim->trajectory()); })
      .def("imu", [](const SimulationHandle& h) { return imu_array(h.sim->imu_readings()); })
      .def("encoders", [](const SimulationHandle& h) { return encoder_arrays(h.sim->encoder_samples()); })
      .def("bumper", [](const SimulationHandle& h) { return bumper_arrays(h.recorder.bumper()); })
      .def("odometry", [](const SimulationHandle& h) -> py::object {
        if (!h.recorder.has_odometry()) return py::none();
        return odometry_array(h.recorder.odometry());
      })
      .def("estimates", [](const SimulationHandle& h) -> py::object {
        if (!h.chain) return py::none();
        return estimates_dict(h.chain->records());
      })
      .def("lidar", [](const SimulationHandle& h, const std::string& stream) { return lidar_dict(h.recorder.lidar(stream)); })
      .def("latest_scan", [](const SimulationHandle& h, const std::string& stream) { return latest_scan_dict(h.recorder.lidar(stream)); })
      .def("lidar_summary", [](const SimulationHandle& h) { return lidar_summary_array(h.sim->scans()); })
      .def("events", [](const SimulationHandle& h) { return events_list(h.sim->events()); })
      .def("metrics", [](const SimulationHandle& h) { return json_loads(metrics_json(*h.sim)); })
      .def("trajectory_csv", [](const SimulationHandle& h) { return trajectory_csv(*h.sim); })
      .def("events_csv", [](const SimulationHandle& h) { return events_csv(*h.sim); })
      .def("write_records", [](const SimulationHandle& h, const std::string& dir) { write_simulation_records(*h.sim, dir); });

  py::class_<NavigationHandle>(m, "_Navigation")
      .def_property_readonly("name", [](const NavigationHandle& h) { return h.run->spec().name; })
      .def("metrics", [](const NavigationHandle& h) { return json_loads(navigation_metrics_json(*h.run)); })
      .def("trajectory", [](const NavigationHandle& h) { return trajectory_array(h.run->simulation().trajectory()); })
      .def("imu", [](const NavigationHandle& h) { return imu_array(h.run->simulation().imu_readings()); })
      .def("encoders", [](const NavigationHandle& h) { return encoder_arrays(h.run->simulation().encoder_samples()); })
      .def("bumper", [](const NavigationHandle& h) { return bumper_arrays(h.recorder.bumper()); })
      .def("lidar", [](const NavigationHandle& h, const std::string& stream) { return lidar_dict(h.recorder.lidar(stream)); })
      .def("lidar_summary", [](const NavigationHandle& h) { return lidar_summary_array(h.run->simulation().scans()); })
      .def("events", [](const NavigationHandle& h) { return events_list(h.run->simulation().events()); })
      .def("plans", [](const NavigationHandle& h) { return plans_list(h.run->navigator()); })
      .def("arrivals", [](const NavigationHandle& h) { return arrivals_array(h.run->arrivals()); })
      .def("trajectory_csv", [](const NavigationHandle& h) { return trajectory_csv(h.run->simulation()); })
      .def("paths_csv", [](const NavigationHandle& h) { return paths_csv(*h.run); })
      .def("write_records", [](const NavigationHandle& h, const std::string& dir) { write_navigation_records(*h.run, dir); });

  m.def("_navigate", &navigate, py::arg("path"), py::arg("text"), py::arg("file"), py::arg("sets"), py::arg("controller"),
        py::arg("planner"), py::arg("record_steps"));
}

}  // namespace starnav::python
