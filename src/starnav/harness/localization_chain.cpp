#include "starnav/harness/localization_chain.hpp"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/harness/scenario_settings.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/registry/components.hpp"

namespace starnav {

namespace {


// Covariances span many decades (1e-10 m^2 after a standstill, metres squared when lost).
std::string format_covariance(double v) {
  char buf[64];
  const int n = std::snprintf(buf, sizeof buf, "%.6e", v);
  return std::string(buf, static_cast<std::size_t>(n));
}

}  // namespace

LocalizationConfig localization_config(const ScenarioSpec& spec) {
  LocalizationConfig c;
  // Wheel odometry needs encoders and wheels that carry the body (not an Ackermann robot's steering).
  const bool wheel_ok = spec.encoders && spec.vehicle.robot.drive != DriveKind::Ackermann;
  c.odometry = wheel_ok ? "wheel" : "none";
  c.localizer = {"ground_truth", {}, "localization.localizer", 0, spec.file};
  if (spec.occupancy_map) c.map_file = spec.occupancy_map->resolved_file;
  if (!spec.localization) return c;
  std::vector<ParamSetting> rest = spec.localization->settings;
  c.localizer = choice_of(rest, "localizer", "ground_truth", "localization", spec);
  const LocalizerDef* def = nullptr;
  try {
    def = &find_localizer(c.localizer.name, c.localizer.field);
  } catch (const Error& e) {
    throw Error(e.message(), spec.file, c.localizer.line, c.localizer.field);
  }
  c.localizer.settings = settings_under(rest, def->info.section);
  const LocalizerDef* filter_def = nullptr;
  for (const ParamSetting& v : rest)
    if (v.key == "odometry") {
      // wheel, none, or a localizer that filters the wheel odometry with the IMU (by its name).
      const LocalizerDef* filter = nullptr;
      if (v.value != "wheel" && v.value != "none") {
        for (const LocalizerDef& l : localizers())
          if (l.info.name == v.value && l.info.has(Capability::FiltersOdometry)) filter = &l;
        if (!filter) {
          std::string known = "wheel, none";
          for (const ComponentInfo& i : all_components())
            if (i.role == Role::Localizer && i.has(Capability::FiltersOdometry)) known += ", " + i.name;
          throw Error("unknown odometry '" + one_line(v.value, 40) + "' (" + known + ")", v.file, v.line, v.field);
        }
      }
      if (v.value != "none" && !wheel_ok)
        throw Error(spec.encoders ? "wheel odometry needs a mecanum or differential robot" : "wheel odometry needs sensors.encoders",
                    v.file, v.line, v.field);
      if (filter && !spec.imu) throw Error("odometry " + filter->info.name + " needs sensors.imu", v.file, v.line, v.field);
      if (filter && filter == def)
        throw Error("the " + filter->info.name + " would run twice (as the odometry and as the localizer): use odometry wheel with localizer " +
                        filter->info.name,
                    v.file, v.line, v.field);
      c.odometry = filter ? "wheel" : v.value;
      c.odometry_filter = {};
      filter_def = filter;
      if (filter) c.odometry_filter = ComponentChoice{filter->info.name, {}, v.field, v.line, v.file};
    }
  if (filter_def) c.odometry_filter->settings = settings_under(rest, filter_def->info.section);
  for (const ParamSetting& v : rest) {
    if (v.key == "localizer" || v.key == "odometry") continue;
    if (v.key == "map") {
      c.map_file = (std::filesystem::path(spec.file).parent_path() / v.value).lexically_normal().string();
      continue;
    }
    const std::string head = v.key.substr(0, v.key.find('.'));
    for (const ComponentInfo& i : all_components())
      if (i.role == Role::Localizer && i.section == head && v.key != head)
        throw Error("parameters of " + i.name + ", but localization.localizer is " + def->info.name, v.file, v.line, v.field);
    throw Error("unknown key (known: odometry, localizer, map, " + def->info.section + ".*)", v.file, v.line, v.field);
  }
  return c;
}

LocalizationChain::LocalizationChain(Simulation& sim, const LocalizationConfig& config)
    : sim_(&sim), config_(config) {
  const ScenarioSpec& spec = sim.spec();
  LocalizerContext ctx = context();
  const LocalizerDef& def = find_localizer(config_.localizer.name, config_.localizer.field);
  if (def.info.has(Capability::NeedsMap)) {
    if (config_.map_file.empty())
      throw Error(def.info.name + " needs a map: world.occupancy_map or localization.map", spec.file, config_.localizer.line,
                  config_.localizer.field);
    LoadedMap loaded = load_map(config_.map_file);
    if (loaded.is_elevation())
      throw Error("an elevation map; " + def.info.name + " needs an occupancy map", config_.map_file, 0, "localization.map");
    thresholds_ = loaded.thresholds();
    map_ = std::make_unique<OccupancyGrid>(std::move(std::get<OccupancyGrid>(loaded.map)));
    ctx = context();
  }
  try {
    localizers_.push_back(def.make(ctx, config_.localizer.settings));
    records_.emplace_back();
    if (config_.odometry_filter) filter_ = find_localizer(config_.odometry_filter->name).make(ctx, config_.odometry_filter->settings);
  } catch (const Error& e) {
    if (!e.file().empty()) throw;
    throw Error(e.message(), spec.file, 0, "localization." + e.field());
  }
  // The simulation's samples become the messages a robot's drivers publish, onto the chain's bus;
  // the parts below are subscribed to streams, as on a robot: the wheel odometry integrator to the
  // encoders, the odometry filter to the wheel odometry and the IMU, the localizers to the odometry
  // they read, the IMU and the planar scans. Each sample is delivered at once (with whatever its
  // delivery publishes at its time), before the navigation sees it.
  const std::string& odometry_stream = config_.odometry_filter ? kFilteredOdometryStream : kOdometryStream;
  if (config_.odometry != "none") {
    odometry_model_ = make_robot_model(spec.vehicle.robot);
    odometry_ = std::make_unique<WheelOdometry>(*odometry_model_, spec.encoders->config.ticks_per_rev, spec.start);
    last_odometry_.pose = spec.start;
    last_odometry_.header.stream = kOdometryStream;
    bus_.subscribe<EncoderMessage>(kEncoderStream, [this](const EncoderMessage& e) {
      odometry_->add_ticks(e.ticks);
      OdometryMessage o;
      o.header = {e.header.t_s, kOdometryStream};
      o.pose = odometry_->pose();
      const double dt = o.header.t_s - last_odometry_.header.t_s;
      if (dt > 0.0) {
        // The body twist over the period, in the body frame at its start.
        const Pose2 d = last_odometry_.pose.inverse().compose(o.pose);
        o.twist = {d.x / dt, d.y / dt, wrap_angle(d.yaw) / dt};
      }
      last_odometry_ = o;
      bus_.publish(std::move(o));
    });
    sim.encoder_feed.subscribe(SampleStage::Estimate, [this, ticks_per_rev = spec.encoders->config.ticks_per_rev](const EncoderSample& e) {
      EncoderMessage m;
      m.header = {e.t_s, kEncoderStream};
      m.ticks = e.ticks;
      m.ticks_per_rev = ticks_per_rev;
      bus_.publish(std::move(m));
      bus_.deliver_all();
    });
  }
  if (filter_) {
    // The filtered odometry, as robot_pose_ekf publishes it: the filter's pose with the wheels' twist.
    bus_.subscribe<OdometryMessage>(kOdometryStream, [this](const OdometryMessage& o) {
      filter_->on_odometry(o);
      OdometryMessage fused = o;
      fused.header.stream = kFilteredOdometryStream;
      fused.pose = filter_->estimate().pose;
      bus_.publish(std::move(fused));
    });
    bus_.subscribe<ImuMessage>(kImuStream, [this](const ImuMessage& m) { filter_->on_imu(m); });
  }
  // One subscription per input for all the localizers, so that a localizer added later is fed in
  // the same delivery, before the record of the estimates.
  bus_.subscribe<OdometryMessage>(odometry_stream, [this](const OdometryMessage& o) {
    for (auto& l : localizers_) l->on_odometry(o);
    record(o.header.t_s, false);
  });
  bus_.subscribe<ImuMessage>(kImuStream, [this](const ImuMessage& m) {
    for (auto& l : localizers_) l->on_imu(m);
  });
  bus_.subscribe<ScanMessage>("", [this](const ScanMessage& scan) {
    for (auto& l : localizers_) l->on_scan(scan);
  });
  sim.imu_feed.subscribe(SampleStage::Estimate, [this](const ImuModel::ImuReading& r) {
    bus_.publish(imu_message(r, kImuStream));
    bus_.deliver_all();
  });
  // The localizers take planar scans as a robot's driver publishes them (a 3D LiDAR's go to none);
  // the first LiDAR's scans also close a record of the estimate.
  if (spec.lidar)
    sim.lidar_feed("lidar").subscribe(SampleStage::Estimate, [this, planar = spec.lidar->config.lines() == 1,
                                                              config = spec.lidar->config](const LidarScan& scan) {
      if (planar) {
        bus_.publish(planar_scan_message(scan, config, "lidar"));
        bus_.deliver_all();
      }
      record(scan.time, true);
    });
  for (const ScenarioLidar& other : spec.other_lidars)
    if (other.config.lines() == 1)
      sim.lidar_feed(other.stream).subscribe(SampleStage::Estimate, [this, config = other.config, stream = other.stream](const LidarScan& scan) {
        bus_.publish(planar_scan_message(scan, config, stream));
        bus_.deliver_all();
      });
}

LocalizationChain::~LocalizationChain() = default;

LocalizerContext localizer_context(const ScenarioSpec& spec) {
  LocalizerContext ctx{spec.start, spec.seed, spec.file};
  ctx.robot = &spec.vehicle.robot;
  if (spec.lidar) {
    ctx.laser_in_base = spec.lidar->config.mount.to_pose2();
    ctx.laser_range_min_m = spec.lidar->config.range_min;
    ctx.laser_range_max_m = spec.lidar->config.range_max;
    ctx.laser_lines = spec.lidar->config.lines();
  }
  return ctx;
}

LocalizerContext LocalizationChain::context() const {
  LocalizerContext ctx = localizer_context(sim_->spec());
  ctx.map = map_.get();
  if (map_) ctx.thresholds = thresholds_;
  return ctx;
}

std::size_t LocalizationChain::add_localizer(const std::string& name, std::span<const ParamSetting> settings) {
  localizers_.push_back(find_localizer(name).make(context(), settings));
  records_.emplace_back();
  return localizers_.size() - 1;
}

Pose2 LocalizationChain::pose(double t_s) {
  localizers_.front()->on_ground_truth(t_s, sim_->vehicle().state().pose.to_pose2());
  return localizers_.front()->estimate().pose;
}

void LocalizationChain::record(double t_s, bool scan) {
  EstimateRecord r;
  r.t_s = t_s;
  r.truth = sim_->vehicle().state().pose.to_pose2();
  r.scan = scan;
  // No truth handed over here: a noisy ground_truth localizer draws its noise only when the run
  // asks for its pose.
  for (std::size_t i = 0; i < localizers_.size(); ++i) {
    r.estimate = localizers_[i]->estimate();
    records_[i].push_back(r);
  }
}

std::string estimate_csv(const std::vector<EstimateRecord>& records) {
  std::string out =
      "t_s,source,true_x_m,true_y_m,true_yaw_rad,x_m,y_m,yaw_rad,cov_xx,cov_xy,cov_yy,cov_yawyaw,particles,updates,converged\n";
  for (const EstimateRecord& r : records) {
    const PoseEstimate& e = r.estimate;
    out += format_fixed6(r.t_s);
    out += r.scan ? ",scan," : ",odometry,";
    for (const double v : {r.truth.x, r.truth.y, r.truth.yaw, e.pose.x, e.pose.y, e.pose.yaw}) {
      out += format_fixed6(v);
      out += ',';
    }
    for (const double v : {e.covariance(0, 0), e.covariance(0, 1), e.covariance(1, 1), e.covariance(2, 2)}) {
      out += format_covariance(v);
      out += ',';
    }
    out += std::to_string(e.particles);
    out += ',';
    out += std::to_string(e.updates);
    out += e.converged ? ",1\n" : ",0\n";
  }
  return out;
}

}  // namespace starnav
