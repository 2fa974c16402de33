#include "starnav/sense/lidar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

int beams_for(double scan_angle, double resolution) {
  const bool full = std::abs(scan_angle - 2.0 * kPi) <= 1e-9;
  const double n = scan_angle / resolution;
  return static_cast<int>(std::lround(n)) + (full ? 0 : 1);
}

LidarConfig planar(const char* model, double fov_deg, int beams, double rmin, double rmax, double rate) {
  LidarConfig c;
  c.model = model;
  c.scan_angle = deg_to_rad(fov_deg);
  c.beams = beams;
  c.elevations = {0.0};
  c.range_min = rmin;
  c.range_max = rmax;
  c.rate_hz = rate;
  return c;
}

LidarConfig spatial(const char* model, double fov_deg, double resolution, int lines, double top_deg,
                    double bottom_deg, double rmin, double rmax) {
  LidarConfig c;
  c.model = model;
  c.scan_angle = deg_to_rad(fov_deg);
  c.beams = beams_for(c.scan_angle, resolution);
  c.set_lines(lines, deg_to_rad(top_deg), deg_to_rad(top_deg - bottom_deg) / (lines - 1));
  c.range_min = rmin;
  c.range_max = rmax;
  c.rate_hz = 10.0;
  return c;
}

}  // namespace

SelfFilterBox SelfFilterBox::around_body(const Vec3& body_min, const Vec3& body_max, const Pose3& mount,
                                         double margin) {
  SelfFilterBox b;
  b.min = Vec3::Constant(kInf);
  b.max = Vec3::Constant(-kInf);
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? body_max.x() : body_min.x(), (k & 2) ? body_max.y() : body_min.y(),
                      (k & 4) ? body_max.z() : body_min.z());
    const Vec3 s = mount.inverse_transform(corner);
    b.min = b.min.cwiseMin(s);
    b.max = b.max.cwiseMax(s);
  }
  b.min -= Vec3::Constant(margin);
  b.max += Vec3::Constant(margin);
  return b;
}

bool LidarConfig::full_circle() const { return std::abs(scan_angle - 2.0 * kPi) <= 1e-9; }

double LidarConfig::delta() const {
  if (full_circle()) return scan_angle / beams;
  return beams > 1 ? scan_angle / (beams - 1) : 0.0;
}

void LidarConfig::set_lines(int lines, double max_line, double delta_line) {
  require(lines >= 1, "lines", "must be at least 1");
  elevations.resize(static_cast<std::size_t>(lines));
  for (int j = 0; j < lines; ++j) elevations[static_cast<std::size_t>(j)] = max_line - j * delta_line;
}

void LidarConfig::validate() const {
  require(std::isfinite(scan_angle) && scan_angle > 0.0 && scan_angle <= 2.0 * kPi + 1e-9, "scan_angle",
          "must be in (0, 360] deg");
  require(beams >= 1, "beams", "must be at least 1");
  require(full_circle() || beams >= 2, "beams", "a scan narrower than 360 deg needs at least 2 beams");
  require(!elevations.empty(), "lines", "needs at least one line");
  require(ray_count() <= kMaxLidarRaysPerScan, "beams",
          "beams x lines = " + std::to_string(ray_count()) + " rays per scan, more than the " +
              std::to_string(kMaxLidarRaysPerScan) + " allowed (fewer beams, a coarser resolution or fewer lines)");
  for (double e : elevations)
    require(std::isfinite(e) && std::abs(e) <= 0.5 * kPi, "elevations", "must be within [-90, 90] deg");
  require(std::isfinite(range_min) && range_min >= 0.0, "range_min", "must be >= 0");
  require(std::isfinite(range_max) && range_max > range_min, "range_max", "must be > range_min");
  require(std::isfinite(rate_hz) && rate_hz > 0.0, "rate_hz", "must be > 0");
  require(std::isfinite(noise_sigma) && noise_sigma >= 0.0, "noise_sigma", "must be >= 0");
  require(dropout >= 0.0 && dropout <= 1.0, "dropout", "must be in [0, 1]");
  require(mount.position.allFinite() && mount.orientation.coeffs().allFinite(), "mount", "must be finite");
  if (self_filter)
    require(self_filter->min.allFinite() && self_filter->max.allFinite() &&
                (self_filter->min.array() <= self_filter->max.array()).all(),
            "self_filter", "needs finite corners with min <= max");
}

LidarConfig lidar_preset(std::string_view name, double res) {
  if (!(std::isfinite(res) && res > 0.0)) throw Error("must be > 0", {}, 0, "horizontal_resolution");
  if (name == "hokuyo_utm30lx") return planar("hokuyo_utm30lx", 270.0, 1081, 0.1, 30.0, 40.0);
  if (name == "sick_lms151") return planar("sick_lms151", 270.0, 541, 0.5, 50.0, 50.0);
  if (name == "generic_360") return planar("generic_360", 360.0, 360, 0.15, 12.0, 10.0);
  // 3D: the paper gives no minimum ranges; these follow the data sheets where they state one
  // (IBEO LUX 0.3 m) and are conservative guesses otherwise (docs/simulator.md).
  if (name == "ibeo_lux4") return spatial("ibeo_lux4", 110.0, res, 4, 1.2, -1.2, 0.3, 200.0);
  if (name == "ibeo_lux8") return spatial("ibeo_lux8", 110.0, res, 8, 2.8, -2.8, 0.3, 200.0);
  if (name == "vlp16") return spatial("vlp16", 360.0, res, 16, 15.0, -15.0, 0.5, 100.0);
  if (name == "hdl32e") return spatial("hdl32e", 360.0, res, 32, 10.67, -30.67, 1.0, 70.0);
  if (name == "hdl64e") return spatial("hdl64e", 360.0, res, 64, 2.0, -24.9, 0.9, 120.0);
  throw Error("unknown LiDAR model '" + std::string(name) + "' (known: hokuyo_utm30lx, sick_lms151, generic_360, "
              "ibeo_lux4, ibeo_lux8, vlp16, hdl32e, hdl64e)", {}, 0, "model");
}

std::vector<std::string> lidar_preset_names() {
  return {"hokuyo_utm30lx", "sick_lms151", "generic_360", "ibeo_lux4", "ibeo_lux8", "vlp16", "hdl32e", "hdl64e"};
}

Lidar::Lidar(LidarConfig config, Rng rng) : config_(std::move(config)), rng_(rng) {
  config_.validate();
  dirs_.reserve(config_.ray_count());
  for (double phi : config_.elevations) {
    const double cp = std::cos(phi), sp = std::sin(phi);
    for (int i = 0; i < config_.beams; ++i) {
      const double theta = config_.azimuth(i);
      dirs_.emplace_back(cp * std::cos(theta), cp * std::sin(theta), sp);
    }
  }
  world_dirs_.resize(dirs_.size());
  hits_.resize(dirs_.size());
}

LidarScan Lidar::scan(const RayCaster& world, const Pose3& robot_pose, double time) {
  LidarScan s;
  scan(world, robot_pose, time, s);
  return s;
}

void Lidar::scan(const RayCaster& world, const Pose3& robot, double time, LidarScan& out) {
  const LidarConfig& c = config_;
  out.time = time;
  out.lines = c.lines();
  out.beams = c.beams;
  out.sensor_pose = robot.compose(c.mount);
  out.azimuths.resize(static_cast<std::size_t>(c.beams));
  for (int i = 0; i < c.beams; ++i) out.azimuths[static_cast<std::size_t>(i)] = c.azimuth(i);
  out.elevations = c.elevations;
  out.ranges.assign(dirs_.size(), kInf);
  out.points_sensor.clear();
  out.points_world.clear();
  out.point_ray.clear();
  out.dropped = 0;
  out.self_filtered = 0;

  // Sensor origin and ray directions in the world: p_world = R_robot (R_mount p + t_mount) + t_robot.
  const Eigen::Matrix3d r_robot = robot.rotation();
  const Eigen::Matrix3d r_mount = c.mount.rotation();
  const Eigen::Matrix3d r_ws = r_robot * r_mount;
  const Vec3 origin = r_robot * c.mount.position + robot.position;
  for (std::size_t k = 0; k < dirs_.size(); ++k) world_dirs_[k] = r_ws * dirs_[k];
  world.cast_many(origin, world_dirs_, c.range_max, time, hits_);

  for (std::size_t k = 0; k < dirs_.size(); ++k) {
    const bool drop = c.dropout > 0.0 && rng_.uniform() < c.dropout;
    const double noise = c.noise_sigma > 0.0 ? c.noise_sigma * rng_.normal() : 0.0;
    const RayHit& h = hits_[k];
    if (!h.hit() || !(h.distance >= c.range_min && h.distance <= c.range_max)) continue;
    if (drop) {
      ++out.dropped;
      continue;
    }
    const double range = std::max(0.0, h.distance + noise);
    const Vec3 p_sensor = range * dirs_[k];
    if (c.self_filter && c.self_filter->contains(p_sensor)) {
      ++out.self_filtered;
      continue;
    }
    out.ranges[k] = range;
    out.points_sensor.push_back(p_sensor);
    out.points_world.push_back(r_robot * (r_mount * p_sensor + c.mount.position) + robot.position);
    out.point_ray.push_back(static_cast<std::uint32_t>(k));
  }
}

ScanMessage planar_scan_message(const LidarScan& scan, const LidarConfig& config, const std::string& stream) {
  ScanMessage m;
  m.header = {scan.time, stream};
  m.mount = config.mount;
  m.angles_rad = scan.azimuths;
  m.range_min_m = config.range_min;
  m.range_max_m = config.range_max;
  m.ranges_m = scan.ranges;
  return m;
}

}  // namespace starnav
