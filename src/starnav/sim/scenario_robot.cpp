// The scenario's robot, vehicle and sensors sections.
#include <limits>

#include "starnav/core/angle.hpp"
#include "starnav/sim/scenario_document.hpp"

namespace starnav::scenario_detail {

namespace {

const SectionDecl<RobotConfig>& robot_decl() {
  static const SectionDecl<RobotConfig> d = [] {
    SectionDecl<RobotConfig> s;
    s.id = "robot";
    s.title = "robot";
    s.table
        .choice(
            "drive", {"mecanum", "differential", "ackermann"},
            [](RobotConfig& c, const std::string& k) { c.drive = parse_drive_kind(k, "drive"); },
            [](const RobotConfig& c) { return std::string(drive_kind_name(c.drive)); }, "kinematic model")
        .real("half_track_m", &RobotConfig::half_track_m, positive(), "m", "L1: wheel contacts at y = +-L1")
        .real("half_wheelbase_m", &RobotConfig::half_wheelbase_m, positive(), "m",
              "L2: wheel contacts at x = +-L2 (Ackermann wheelbase 2 L2)")
        .real("wheel_radius_m", &RobotConfig::wheel_radius_m, positive(), "m", "wheel radius")
        .real("roller_angle_deg", &RobotConfig::roller_angle_rad, open(0.0, 90.0), "deg", "Mecanum roller angle", kDeg)
        .real("body_length_m", &RobotConfig::body_length_m, positive(), "m", "body box along x")
        .real("body_width_m", &RobotConfig::body_width_m, positive(), "m", "body box along y")
        .real("body_height_m", &RobotConfig::body_height_m, positive(), "m", "body box along z")
        .real("ground_clearance_m", &RobotConfig::ground_clearance_m, non_negative(), "m",
              "the body spans z in [clearance, clearance + height] in base_link")
        .real("max_wheel_speed_radps", &RobotConfig::max_wheel_speed_radps, positive(), "rad/s",
              "wheel speed limit (all wheels scaled together)")
        .real("max_wheel_accel_radps2", &RobotConfig::max_wheel_accel_radps2, positive(), "rad/s^2", "per-wheel acceleration limit")
        .real("actuator_lag_s", &RobotConfig::actuator_lag_s, non_negative(), "s", "first-order lag (0: none)")
        .real("max_steer_deg", &RobotConfig::max_steer_rad, open(0.0, 90.0), "deg", "Ackermann: steering limit", kDeg)
        .real("max_steer_rate_degps", &RobotConfig::max_steer_rate_radps, positive(), "deg/s", "Ackermann: steering rate limit",
              kDeg)
        .real("max_step_m", &RobotConfig::max_step_m, non_negative(), "m", "tallest step the wheels climb");
    s.structural = {{"start", "mapping", "all 0", "", "", "start pose of base_link (robot.start)"}};
    return s;
  }();
  return d;
}

struct PlanarPose {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
};

const SectionDecl<PlanarPose>& start_decl() {
  static const SectionDecl<PlanarPose> d = [] {
    SectionDecl<PlanarPose> s;
    s.id = "robot.start";
    s.title = "robot.start";
    s.table.real("x_m", &PlanarPose::x_m, any_value(), "m", "x in the world frame")
        .real("y_m", &PlanarPose::y_m, any_value(), "m", "y in the world frame")
        .real("yaw_deg", &PlanarPose::yaw_rad, any_value(), "deg", "heading, counter-clockwise from +x", kDeg);
    return s;
  }();
  return d;
}

const SectionDecl<VehicleConfig>& vehicle_decl() {
  static const SectionDecl<VehicleConfig> d = [] {
    SectionDecl<VehicleConfig> s;
    s.id = "vehicle";
    s.title = "vehicle";
    s.table.real("friction", &VehicleConfig::friction, positive(), "", "the robot slides down slopes steeper than atan(friction)")
        .real("rough_slip_sigma", &VehicleConfig::rough_slip_sigma, non_negative(), "",
              "random slip on rough ground (fraction of speed), 0: off");
    return s;
  }();
  return d;
}

struct SensorsKeys {
  bool bumper = true;
};

const SectionDecl<SensorsKeys>& sensors_decl() {
  static const SectionDecl<SensorsKeys> d = [] {
    SectionDecl<SensorsKeys> s;
    s.id = "sensors";
    s.title = "sensors";
    s.structural = {
        {"lidar", "mapping", "none", "", "", "the first LiDAR (sensors.lidar), on the stream lidar", true},
        {"lidars", "mapping of mappings", "none", "at most 8", "",
         "more LiDARs by name, each with the keys of lidar, on the streams lidar/NAME; only with lidar", true},
        {"imu", "mapping", "none", "", "", "the IMU (sensors.imu)", true},
        {"encoders", "mapping", "none", "", "", "the wheel encoders (sensors.encoders)", true},
    };
    s.table.boolean("bumper", &SensorsKeys::bumper, "record bumper contact changes as events");
    return s;
  }();
  return d;
}

// A LiDAR's keys: its configuration and the scenario's keys around it.
struct LidarKeys {
  LidarConfig config;
  std::string preset;
  double resolution_deg = 0.2;
  bool self_filter = true;
  double self_filter_margin_m = 0.05;
};

const SectionDecl<LidarKeys>& lidar_decl() {
  static const SectionDecl<LidarKeys> d = [] {
    SectionDecl<LidarKeys> s;
    s.id = "sensors.lidar";
    s.title = "sensors.lidar (and each of sensors.lidars)";
    const auto c = [](auto member) {
      return [member](LidarKeys& k) -> std::remove_reference_t<decltype(k.config.*member)>& { return k.config.*member; };
    };
    s.table
        .choice(
            "preset", lidar_preset_names(), [](LidarKeys& k, const std::string& p) { k.preset = p; },
            [](const LidarKeys& k) { return k.preset; }, "a sensor model (docs/simulator.md); the keys below override it", false)
        .real("horizontal_resolution_deg", &LidarKeys::resolution_deg, ParamRange{0.00036, std::numeric_limits<double>::infinity(), false, false}, "deg",
              "3D presets only: sets their beams (at most 1,000,000 per line)")
        .integer("beams", c(&LidarConfig::beams), closed(1, 1000000), "",
                 "horizontal beams per line; beams x lines at most 4,194,304 rays per scan")
        .real("scan_angle_deg", c(&LidarConfig::scan_angle), ParamRange{0.0, 360.0, true, false}, "deg", "horizontal field of view",
              kDeg)
        .real("range_min_m", c(&LidarConfig::range_min), non_negative(), "m", "shortest range (below range_max_m)")
        .real("range_max_m", c(&LidarConfig::range_max), positive(), "m", "longest range")
        .real("rate_hz", c(&LidarConfig::rate_hz), positive(), "Hz", "scans per second (at most one per simulation step)")
        .real("noise_sigma_m", c(&LidarConfig::noise_sigma), non_negative(), "m", "Gaussian range noise")
        .real("dropout", c(&LidarConfig::dropout), closed(0.0, 1.0), "", "probability of a lost return")
        .boolean("self_filter", &LidarKeys::self_filter, "drop returns inside the robot's body box ...")
        .real("self_filter_margin_m", &LidarKeys::self_filter_margin_m, non_negative(), "m", "... grown by this margin");
    s.table.default_rule("preset", "none: one 360 deg line of 360 beams, 0.15-12 m, 10 Hz");
    for (const char* k : {"beams", "scan_angle_deg", "range_min_m", "range_max_m", "rate_hz"})
      s.table.default_rule(k, "the preset's");
    s.structural = {
        {"elevations_deg", "list of numbers", "the preset's", "each in [-90, 90]", "deg", "one per line, top first"},
        {"mount", "mapping", "centred, 0.1 m above the body's top", "", "", "the sensor's pose in base_link (sensors.lidar.mount)"},
    };
    return s;
  }();
  return d;
}

struct MountKeys {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0, roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;
};

const SectionDecl<MountKeys>& mount_decl() {
  static const SectionDecl<MountKeys> d = [] {
    SectionDecl<MountKeys> s;
    s.id = "sensors.lidar.mount";
    s.title = "sensors.lidar.mount";
    s.table.real("x_m", &MountKeys::x_m, any_value(), "m", "forward of base_link")
        .real("y_m", &MountKeys::y_m, any_value(), "m", "left of base_link")
        .real("z_m", &MountKeys::z_m, any_value(), "m", "above base_link")
        .real("roll_deg", &MountKeys::roll_rad, any_value(), "deg", "roll about x", kDeg)
        .real("pitch_deg", &MountKeys::pitch_rad, any_value(), "deg", "pitch about y", kDeg)
        .real("yaw_deg", &MountKeys::yaw_rad, any_value(), "deg", "yaw about z", kDeg);
    s.table.default_rule("z_m", "0.1 above the body's top");
    return s;
  }();
  return d;
}

const SectionDecl<ImuConfig>& imu_decl() {
  static const SectionDecl<ImuConfig> d = [] {
    SectionDecl<ImuConfig> s;
    s.id = "sensors.imu";
    s.title = "sensors.imu";
    s.table.real("rate_hz", &ImuConfig::rate_hz, positive(), "Hz", "samples per second (at most one per simulation step)")
        .real("yaw_rate_noise_sigma_radps", &ImuConfig::yaw_rate_noise_sigma_radps, non_negative(), "rad/s",
              "Gaussian noise on the yaw rate")
        .real("yaw_rate_bias_radps", &ImuConfig::yaw_rate_bias_radps, any_value(), "rad/s", "constant yaw rate bias")
        .real("yaw_noise_sigma_rad", &ImuConfig::yaw_noise_sigma_rad, non_negative(), "rad", "Gaussian noise on the yaw");
    return s;
  }();
  return d;
}

const SectionDecl<ScenarioEncoders>& encoders_decl() {
  static const SectionDecl<ScenarioEncoders> d = [] {
    SectionDecl<ScenarioEncoders> s;
    s.id = "sensors.encoders";
    s.title = "sensors.encoders";
    s.table.real("rate_hz", &ScenarioEncoders::rate_hz, positive(), "Hz", "samples per second (at most one per simulation step)")
        .integer("ticks_per_rev", [](ScenarioEncoders& e) -> int& { return e.config.ticks_per_rev; }, closed(1, 1 << 30), "",
                 "ticks per wheel revolution")
        .real("slip_sigma", [](ScenarioEncoders& e) -> double& { return e.config.slip_sigma; }, non_negative(), "",
              "random wheel slip (fraction of the rotation)")
        .reals("scale_error", [](ScenarioEncoders& e) -> std::vector<double>& { return e.config.scale_error; }, closed(-0.5, 0.5), "",
               "systematic error of each wheel's count, in the drive's wheel order (Mecanum FL, FR, RL, RR; differential L, R): "
               "wheel i counts (1 + e_i) times its travel, a wrong tyre radius as odometry sees it ([]: none)");
    return s;
  }();
  return d;
}

// A library validation error of the robot or vehicle at the line of the YAML key it names.
[[noreturn]] void rethrow_vehicle_error(const Error& e, const Doc& doc, const Fields* robot, const Fields* vehicle,
                                        int fallback_line) {
  std::string key = e.field();
  const Fields* section = nullptr;
  for (const auto& [prefix, f] : {std::pair<std::string, const Fields*>{"robot.", robot}, {"vehicle.", vehicle}})
    if (key.rfind(prefix, 0) == 0) {
      key = key.substr(prefix.size());
      section = f;
    }
  // The library names angles in radians; the scenario writes degrees.
  const auto to_deg = [](std::string k) {
    for (const auto& [rad, deg] : {std::pair<std::string, std::string>{"_radps", "_degps"}, {"_rad", "_deg"}})
      if (k.size() > rad.size() && k.compare(k.size() - rad.size(), rad.size(), rad) == 0)
        return k.substr(0, k.size() - rad.size()) + deg;
    return k;
  };
  if (section) {
    const std::string deg = to_deg(key);
    const std::string yaml_key = section->line_of(deg) != section->line() ? deg : key;
    throw Error(e.message(), doc.file, section->line_of(yaml_key),
                section->field().empty() ? yaml_key : section->field() + "." + yaml_key);
  }
  throw Error(e.message(), doc.file, fallback_line, e.field());
}

ScenarioLidar parse_lidar(const Value& v, const RobotConfig& robot) {
  const Doc& doc = v.doc();
  Fields f(v, doc);
  ScenarioLidar l;
  l.source = {v.line(), v.field()};
  LidarKeys k;
  // The preset first: it gives the other keys' defaults.
  apply_section(f, lidar_decl(), k, {"horizontal_resolution_deg", "preset"});
  if (f.has("horizontal_resolution_deg")) {
    // A 3D preset gets scan angle / resolution beams per line: at most what `beams` allows (and a
    // finer resolution would overflow the beam count).
    if (360.0 / k.resolution_deg > 1000000.0)
      f.fail_at("horizontal_resolution_deg", "must be at least 0.00036 (360 deg / 1000000 beams, the most beams allows)");
    l.horizontal_resolution_deg = k.resolution_deg;
  }
  if (f.has("preset")) {
    l.preset = k.preset;
    try {
      k.config = lidar_preset(l.preset, deg_to_rad(k.resolution_deg));
    } catch (const Error& e) {
      f.fail_at("preset", e.message());
    }
  } else if (l.horizontal_resolution_deg > 0.0) {
    f.fail_at("horizontal_resolution_deg", "only with a 3D preset");
  }
  LidarConfig& c = k.config;
  if (auto e = f.take("elevations_deg")) {
    if (!e->node().IsSequence() || e->node().size() == 0) e->fail("expected a list of elevations (top first), found " + node_kind(e->node()));
    c.elevations.clear();
    for (std::size_t i = 0; i < e->node().size(); ++i) c.elevations.push_back(deg_to_rad(e->element(i).in_range(-90.0, 90.0)));
  }
  // Default mount: centred, 0.1 m above the top of the body.
  const double top = robot.ground_clearance_m + robot.body_height_m;
  MountKeys m;
  m.z_m = top + 0.1;
  if (auto mv = f.take("mount")) {
    Fields mf(*mv, doc);
    apply_section(mf, mount_decl(), m);
  }
  c.mount = Pose3::from_rpy(Vec3(m.x_m, m.y_m, m.z_m), m.roll_rad, m.pitch_rad, m.yaw_rad);
  c.noise_sigma = 0.0;
  apply_section(f, lidar_decl(), k);
  if (!(c.range_max > c.range_min)) {
    if (f.has("range_max_m")) f.fail_at("range_max_m", "must be > range_min_m");
    f.fail_at("range_min_m", "must be below range_max_m");
  }
  if (k.self_filter) {
    const Vec3 lo(-0.5 * robot.body_length_m, -0.5 * robot.body_width_m, robot.ground_clearance_m);
    const Vec3 hi(0.5 * robot.body_length_m, 0.5 * robot.body_width_m, top);
    c.self_filter = SelfFilterBox::around_body(lo, hi, c.mount, k.self_filter_margin_m);
  }
  try {
    c.validate();
  } catch (const Error& e) {
    rethrow_at(e, doc, v.line(), v.field());
  }
  l.config = c;
  return l;
}

}  // namespace

void parse_robot_and_vehicle(std::optional<Value> robot, std::optional<Value> vehicle, ScenarioSpec& s) {
  std::optional<Fields> robot_fields, vehicle_fields;
  const Doc* doc = robot ? &robot->doc() : vehicle ? &vehicle->doc() : nullptr;
  RobotConfig& rc = s.vehicle.robot;
  if (robot) {
    s.robot_source = {robot->line(), robot->field()};
    robot_fields.emplace(*robot, *doc);
    Fields& f = *robot_fields;
    s.start_source = {robot->line(), "robot.start"};
    if (auto st = f.take("start")) {
      s.start_source = {st->line(), st->field()};
      Fields sf(*st, *doc);
      PlanarPose p;
      apply_section(sf, start_decl(), p);
      s.start = Pose2(p.x_m, p.y_m, wrap_angle(p.yaw_rad));
    }
    apply_section(f, robot_decl(), rc);
  }
  if (vehicle) {
    vehicle_fields.emplace(*vehicle, *doc);
    apply_section(*vehicle_fields, vehicle_decl(), s.vehicle);
  }
  try {
    s.vehicle.validate();
  } catch (const Error& e) {
    if (!doc) throw;
    rethrow_vehicle_error(e, *doc, robot_fields ? &*robot_fields : nullptr, vehicle_fields ? &*vehicle_fields : nullptr,
                          s.robot_source.line);
  }
}

void parse_sensors(const Value& v, ScenarioSpec& s) {
  const Doc& doc = v.doc();
  const RobotConfig& rc = s.vehicle.robot;
  Fields f(v, doc);
  if (auto l = f.take("lidar")) s.lidar = parse_lidar(*l, rc);
  if (auto ls = f.take("lidars")) {
    if (!ls->node().IsMap()) ls->fail("expected LiDARs by name (rear: {preset: ..., mount: ...}), found " + node_kind(ls->node()));
    if (!s.lidar) ls->fail("more LiDARs need the first one (sensors.lidar)");
    Fields g(*ls, doc);
    for (const std::string& name : g.keys()) {
      const Value e = *g.take(name.c_str());
      const bool snake = !name.empty() && name[0] >= 'a' && name[0] <= 'z' &&
                         name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
      if (!snake || name == "lidar") e.fail("a LiDAR's name is lower_snake_case (its stream is lidar/NAME)");
      if (s.other_lidars.size() == kMaxOtherLidars) e.fail("more than " + std::to_string(kMaxOtherLidars) + " more LiDARs");
      ScenarioLidar l = parse_lidar(e, rc);
      l.stream = "lidar/" + name;
      s.other_lidars.push_back(std::move(l));
    }
  }
  if (auto i = f.take("imu")) {
    Fields g(*i, doc);
    ScenarioImu imu;
    imu.source = {i->line(), i->field()};
    apply_section(g, imu_decl(), imu.config);
    try {
      imu.config.validate();
    } catch (const Error& e) {
      rethrow_at(e, doc, i->line(), "sensors");
    }
    s.imu = imu;
  }
  if (auto i = f.take("encoders")) {
    Fields g(*i, doc);
    ScenarioEncoders enc;
    apply_section(g, encoders_decl(), enc);
    enc.source = {i->line(), i->field()};
    try {
      enc.config.validate();
    } catch (const Error& e) {
      rethrow_at(e, doc, i->line(), "sensors");
    }
    s.encoders = enc;
  }
  SensorsKeys k;
  apply_section(f, sensors_decl(), k);
  s.bumper = k.bumper;
}

std::vector<ScenarioKeySection> robot_sections() {
  return {robot_decl().describe(), start_decl().describe(),  vehicle_decl().describe(), sensors_decl().describe(),
          lidar_decl().describe(), mount_decl().describe(), imu_decl().describe(),     encoders_decl().describe()};
}

}  // namespace starnav::scenario_detail
