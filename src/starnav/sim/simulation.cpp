#include "starnav/sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/output_file.hpp"

namespace starnav {

namespace {


// Sample index n of a sensor at `rate_hz` is due at n / rate_hz; a step at time t takes every
// sample due by t (to a nanosecond, so exact multiples of dt are not lost to rounding).
bool due(std::int64_t n, double rate_hz, double t) { return static_cast<double>(n) / rate_hz <= t + 1e-9; }

std::string fixed(double v) { return format_fixed6(v); }

void write_file(const std::string& path, const std::string& text) { write_file_atomically(path, text); }

std::string twist_text(const BodyTwist& t) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "vx=%g vy=%g wz=%g", t.vx, t.vy, t.wz);
  return buf;
}

std::string pose_text(const Pose2& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "x=%g y=%g yaw_deg=%g", p.x, p.y, p.yaw * 180.0 / kPi);
  return buf;
}

}  // namespace

Simulation::Simulation(const ScenarioSpec& spec) : Simulation(spec, build_world(spec)) {}

Simulation::Simulation(const ScenarioSpec& spec, const WorldDescription& world) : spec_(spec) {
  try {
    world_ = World(world);
    terrain_map_ = world.terrain;
  } catch (const Error& e) {
    throw Error(e.message(), spec_.file, 0, "world" + (e.field().empty() ? "" : "." + e.field()));
  }
  init();
}

Simulation::~Simulation() = default;

void Simulation::init() {
  if (!(spec_.dt_s > 0.0)) throw Error("must be > 0", spec_.file, 0, "sim.dt_s");
  if (!(spec_.duration_s > 0.0)) throw Error("must be > 0", spec_.file, 0, "sim.duration_s");
  // A bound on the work (and the memory of the records) that a typo in duration or dt can ask for.
  constexpr double kMaxSteps = 1e9;
  if (!(spec_.duration_s / spec_.dt_s <= kMaxSteps))
    throw Error("asks for more than 1e9 steps of sim.dt_s", spec_.file, 0, "sim.duration_s");
  total_steps_ = static_cast<std::int64_t>(std::ceil(spec_.duration_s / spec_.dt_s - 1e-9));
  const Rng root(spec_.seed);
  try {
    vehicle_ = std::make_unique<Vehicle>(world_, spec_.vehicle, spec_.start, root.fork(1), 0.0);
  } catch (const Error& e) {
    // The vehicle names its own fields ("start", "robot.x"); place them in the scenario's sections.
    std::string field = e.field().empty() ? "robot.start" : e.field();
    if (field.rfind("robot.", 0) != 0 && field.rfind("vehicle.", 0) != 0) field = "robot." + field;
    throw Error(e.message(), spec_.file, field == "robot.start" ? spec_.start_source.line : spec_.robot_source.line, field);
  }
  if (spec_.lidar) {
    lidars_.push_back({"lidar", Lidar(spec_.lidar->config, root.fork(2)), {}, 0, {}});
    first_lidar_ = true;
  }
  // Streams 20, 21, ... for more LiDARs: the first LiDAR's draws stay as they were.
  for (std::size_t i = 0; i < spec_.other_lidars.size(); ++i)
    lidars_.push_back({spec_.other_lidars[i].stream, Lidar(spec_.other_lidars[i].config, root.fork(20 + i)), {}, 0, {}});
  if (spec_.imu) imu_model_.emplace(spec_.imu->config, root.fork(3), spec_.start.yaw);
  if (spec_.encoders) {
    try {
      encoders_.emplace(vehicle_->model().actuator_count(), spec_.encoders->config, root.fork(4));
    } catch (const Error& e) {
      throw Error(e.message(), spec_.file, spec_.encoders->source.line, "sensors." + e.field());
    }
  }

  last_ = sample_now();
  z_min_ = z_max_ = last_.position.z();
  roll_max_ = std::abs(last_.rpy.x());
  pitch_max_ = std::abs(last_.rpy.y());
  if (spec_.reference_line.size() >= 2) {
    const double d = distance_to_polyline(last_.position.head<2>(), spec_.reference_line);
    deviation_sum_ = d;
    deviation_max_ = d;
    deviation_n_ = 1;
  }
  trajectory_.push_back(last_);
  // The sensors' samples at t = 0 are taken by the first step(), once the feeds have subscribers.
}

TrajectorySample Simulation::sample_now() const {
  const VehicleState& s = vehicle_->state();
  TrajectorySample out;
  out.t_s = time();
  out.position = s.pose.position;
  out.rpy = s.pose.rpy();
  out.twist = s.twist;
  return out;
}

void Simulation::add_event(double t, std::string kind, std::string detail, const Vec2& where) {
  events_.push_back({t, std::move(kind), std::move(detail), where});
}

SampleFeed<LidarScan>& Simulation::lidar_feed(const std::string& stream) {
  for (LidarSlot& slot : lidars_)
    if (slot.stream == stream) return slot.feed;
  throw Error("the scenario has no LiDAR on stream '" + stream + "'", spec_.file, 0, "sensors");
}

std::vector<std::string> Simulation::lidar_streams() const {
  std::vector<std::string> streams;
  for (const LidarSlot& slot : lidars_) streams.push_back(slot.stream);
  return streams;
}

void Simulation::scan_lidars(double t) {
  for (std::size_t i = 0; i < lidars_.size(); ++i) {
    LidarSlot& slot = lidars_[i];
    if (!due(slot.next, slot.lidar.config().rate_hz, t)) continue;
    slot.lidar.scan(world_, vehicle_->state().pose, t, slot.scan);
    if (i == 0 && first_lidar_) {
      const LidarScan& scan = slot.scan;
      LidarScanSummary s;
      s.t_s = t;
      s.sensor_position = scan.sensor_pose.position;
      s.rays = scan.ranges.size();
      s.returns = scan.points_world.size();
      s.dropped = scan.dropped;
      s.self_filtered = scan.self_filtered;
      s.min_range_m = kInfinity;
      for (const double r : scan.ranges)
        if (r < s.min_range_m) s.min_range_m = r;
      rays_ += static_cast<std::int64_t>(s.rays);
      returns_ += static_cast<std::int64_t>(s.returns);
      scans_.push_back(s);
    }
    slot.feed.publish(slot.scan);
    // One scan per step at most: a rate above 1/dt is capped to the step rate.
    while (due(slot.next, slot.lidar.config().rate_hz, t)) ++slot.next;
  }
}

void Simulation::sample_sensors(bool initial) {
  const double t = time();
  if (imu_model_ && !initial && due(next_imu_, imu_model_->config().rate_hz, t)) {
    imu_.push_back(imu_model_->sample(t, vehicle_->state().twist.wz, t - last_imu_t_));
    last_imu_t_ = t;
    imu_feed.publish(imu_.back());
    while (due(next_imu_, imu_model_->config().rate_hz, t)) ++next_imu_;
  }
  if (encoders_ && due(next_encoder_, spec_.encoders->rate_hz, t)) {
    encoder_samples_.push_back({t, encoders_->sample(vehicle_->state().wheel_angle_rad)});
    encoder_feed.publish(encoder_samples_.back());
    while (due(next_encoder_, spec_.encoders->rate_hz, t)) ++next_encoder_;
  }
  // The scans last: a localizer matching one then has the odometry of the same instant.
  scan_lidars(t);
}

void Simulation::step() {
  if (!started_) {
    started_ = true;
    sample_sensors(true);
  }
  if (finished()) return;
  const double t0 = time();
  const int seg = spec_.segment_at(t0);
  if (seg != segment_) {
    segment_ = seg;
    const Vec2 at = vehicle_->state().pose.position.head<2>();
    if (seg >= 0)
      add_event(t0, "command", "segment " + std::to_string(seg) + ": " + twist_text(spec_.commands[static_cast<std::size_t>(seg)].twist), at);
    else if (!spec_.commands.empty())
      add_event(t0, "command", "end of script: stop", at);
  }
  const BodyTwist command = command_source ? command_source(t0)
                            : seg >= 0     ? spec_.commands[static_cast<std::size_t>(seg)].twist
                                           : BodyTwist{};
  if (stopped_) return;  // command_source stopped the run
  while (next_teleport_ < spec_.teleports.size() && spec_.teleports[next_teleport_].t_s <= t0) {
    const ScenarioTeleport& tp = spec_.teleports[next_teleport_++];
    try {
      teleport(tp.to);
    } catch (const Error& e) {
      throw Error(e.message(), spec_.file, tp.source.line, tp.source.field + ".teleport");
    }
  }
  vehicle_events_.clear();
  vehicle_->step(command, spec_.dt_s, vehicle_events_);
  ++step_;
  const double t1 = time();

  // The vehicle reports each episode once, when it starts (Vehicle::step).
  for (const VehicleEvent& e : vehicle_events_) add_event(t1, e.kind, e.detail, e.where);

  for (const Obstacle& o : world_.obstacles()) {
    if (o.appear > t0 && o.appear <= t1) add_event(t1, "appear", o.name, o.anchor_at(o.appear).head<2>());
    if (o.disappear > t0 && o.disappear <= t1) add_event(t1, "disappear", o.name, o.anchor_at(o.disappear).head<2>());
  }
  if (spec_.bumper && vehicle_->bumper_contact() != bumper_) {
    bumper_ = vehicle_->bumper_contact();
    add_event(t1, "bumper", bumper_ ? "contact" : "released", vehicle_->state().pose.position.head<2>());
  }
  if (spec_.bumper) bumper_feed.publish(BumperReading{t1, bumper_});

  sample_sensors(false);
  track_step();
  if (on_step) on_step();
}

void Simulation::teleport(const Pose2& to) {
  vehicle_->teleport(to, time());
  add_event(time(), "teleport", "to " + pose_text(to), to.translation());
  last_ = sample_now();  // the jump is not driven distance
}

void Simulation::track_step() {
  const TrajectorySample s = sample_now();
  distance_ += (s.position.head<2>() - last_.position.head<2>()).norm();
  distance_3d_ += (s.position - last_.position).norm();
  z_min_ = std::min(z_min_, s.position.z());
  z_max_ = std::max(z_max_, s.position.z());
  roll_max_ = std::max(roll_max_, std::abs(s.rpy.x()));
  pitch_max_ = std::max(pitch_max_, std::abs(s.rpy.y()));
  if (spec_.reference_line.size() >= 2) {
    const double d = distance_to_polyline(s.position.head<2>(), spec_.reference_line);
    deviation_sum_ += d;
    deviation_max_ = std::max(deviation_max_, d);
    ++deviation_n_;
  }
  last_ = s;
  if (step_ % spec_.outputs.trajectory_every_n_steps == 0 || finished()) trajectory_.push_back(s);
}

void Simulation::stop() {
  if (stopped_) return;
  stopped_ = true;
  if (trajectory_.empty() || trajectory_.back().t_s != time()) trajectory_.push_back(sample_now());
}

void Simulation::run(const std::function<void(double)>& progress) {
  const std::int64_t every = std::max<std::int64_t>(1, total_steps_ / 100);
  while (!finished()) {
    step();
    if (progress && (step_ % every == 0 || finished())) progress(static_cast<double>(step_) / static_cast<double>(total_steps_));
  }
}

SimulationMetrics Simulation::metrics() const {
  SimulationMetrics m;
  m.duration_s = time();
  m.steps = step_;
  m.distance_m = distance_;
  m.distance_3d_m = distance_3d_;
  m.final_state = last_;
  m.z_min_m = z_min_;
  m.z_max_m = z_max_;
  m.roll_max_abs_rad = roll_max_;
  m.pitch_max_abs_rad = pitch_max_;
  for (const SimEvent& e : events_) ++m.events_by_kind[e.kind];
  m.collisions = m.events_by_kind.count("collision") ? m.events_by_kind.at("collision") : 0;
  m.has_reference = deviation_n_ > 0;
  if (m.has_reference) {
    m.deviation_mean_m = deviation_sum_ / static_cast<double>(deviation_n_);
    m.deviation_max_m = deviation_max_;
  }
  m.lidar_scans = static_cast<std::int64_t>(scans_.size());
  m.lidar_rays = rays_;
  m.lidar_returns = returns_;
  m.imu_samples = static_cast<std::int64_t>(imu_.size());
  m.encoder_samples = static_cast<std::int64_t>(encoder_samples_.size());
  return m;
}

std::string trajectory_csv(const Simulation& sim) {
  std::string out = "t_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,vx_mps,vy_mps,wz_radps\n";
  for (const TrajectorySample& s : sim.trajectory()) {
    out += fixed(s.t_s) + ',' + fixed(s.position.x()) + ',' + fixed(s.position.y()) + ',' + fixed(s.position.z()) + ',' +
           fixed(s.rpy.x()) + ',' + fixed(s.rpy.y()) + ',' + fixed(s.rpy.z()) + ',' + fixed(s.twist.vx) + ',' +
           fixed(s.twist.vy) + ',' + fixed(s.twist.wz) + '\n';
  }
  return out;
}

std::string events_csv(const Simulation& sim) {
  std::string out = "t_s,kind,detail,x_m,y_m\n";
  for (const SimEvent& e : sim.events())
    out += fixed(e.t_s) + ',' + csv_field(e.kind) + ',' + csv_field(e.detail) + ',' + fixed(e.where.x()) + ',' +
           fixed(e.where.y()) + '\n';
  return out;
}

std::string metrics_json(const Simulation& sim) {
  const SimulationMetrics m = sim.metrics();
  const ScenarioSpec& s = sim.spec();
  nlohmann::ordered_json j;
  j["scenario"] = s.name;
  j["seed"] = s.seed;
  j["dt_s"] = s.dt_s;
  j["duration_s"] = m.duration_s;
  j["steps"] = m.steps;
  j["distance_m"] = m.distance_m;
  j["distance_3d_m"] = m.distance_3d_m;
  const TrajectorySample& f = m.final_state;
  j["final_pose"] = {{"x_m", unsigned_zero(f.position.x())},   {"y_m", unsigned_zero(f.position.y())},
                     {"z_m", unsigned_zero(f.position.z())},   {"roll_rad", unsigned_zero(f.rpy.x())},
                     {"pitch_rad", unsigned_zero(f.rpy.y())}, {"yaw_rad", unsigned_zero(f.rpy.z())}};
  j["z_min_m"] = m.z_min_m;
  j["z_max_m"] = m.z_max_m;
  j["roll_max_abs_rad"] = m.roll_max_abs_rad;
  j["pitch_max_abs_rad"] = m.pitch_max_abs_rad;
  j["collisions"] = m.collisions;
  nlohmann::ordered_json kinds = nlohmann::ordered_json::object();
  for (const auto& [k, n] : m.events_by_kind) kinds[k] = n;
  j["events_by_kind"] = kinds;
  if (m.has_reference) {
    j["reference_deviation_mean_m"] = m.deviation_mean_m;
    j["reference_deviation_max_m"] = m.deviation_max_m;
  }
  j["lidar_scans"] = m.lidar_scans;
  j["lidar_rays"] = m.lidar_rays;
  j["lidar_returns"] = m.lidar_returns;
  j["imu_samples"] = m.imu_samples;
  j["encoder_samples"] = m.encoder_samples;
  return j.dump(2) + "\n";
}

void write_simulation_records(const Simulation& sim, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path d(dir);
  write_file((d / "trajectory.csv").string(), trajectory_csv(sim));
  write_file((d / "events.csv").string(), events_csv(sim));
  write_file((d / "metrics.json").string(), metrics_json(sim));
  if (sim.spec().lidar) {
    std::string out = "t_s,x_m,y_m,z_m,rays,returns,dropped,self_filtered,min_range_m\n";
    for (const LidarScanSummary& s : sim.scans())
      out += fixed(s.t_s) + ',' + fixed(s.sensor_position.x()) + ',' + fixed(s.sensor_position.y()) + ',' +
             fixed(s.sensor_position.z()) + ',' + std::to_string(s.rays) + ',' + std::to_string(s.returns) + ',' +
             std::to_string(s.dropped) + ',' + std::to_string(s.self_filtered) + ',' +
             (std::isfinite(s.min_range_m) ? fixed(s.min_range_m) : std::string("inf")) + '\n';
    write_file((d / "lidar.csv").string(), out);
  }
  if (sim.spec().imu) {
    std::string out = "t_s,yaw_rate_radps,yaw_rad\n";
    for (const auto& r : sim.imu_readings()) out += fixed(r.t_s) + ',' + fixed(r.yaw_rate_radps) + ',' + fixed(r.yaw_rad) + '\n';
    write_file((d / "imu.csv").string(), out);
  }
  if (sim.spec().encoders) {
    std::string out = "t_s";
    const int wheels = sim.vehicle().model().actuator_count();
    for (int i = 0; i < wheels; ++i) out += ",ticks_" + std::to_string(i);
    out += '\n';
    for (const EncoderSample& e : sim.encoder_samples()) {
      out += fixed(e.t_s);
      for (const std::int64_t t : e.ticks) out += ',' + std::to_string(t);
      out += '\n';
    }
    write_file((d / "encoders.csv").string(), out);
  }
}

void write_timing_json(const SimulationTiming& t, const std::string& path) {
  nlohmann::ordered_json j;
  j["wall_s"] = t.wall_s;
  j["setup_s"] = t.setup_s;
  j["sim_s"] = t.sim_s;
  j["real_time_factor"] = t.wall_s > 0.0 ? t.sim_s / t.wall_s : 0.0;
  j["steps"] = t.steps;
  j["steps_per_s"] = t.wall_s > 0.0 ? static_cast<double>(t.steps) / t.wall_s : 0.0;
  j["lidar_rays"] = t.lidar_rays;
  j["rays_per_s"] = t.wall_s > 0.0 ? static_cast<double>(t.lidar_rays) / t.wall_s : 0.0;
  write_file(path, j.dump(2) + "\n");
}

}  // namespace starnav
