// LiDAR models: presets and beam order (spec li2019 sections 1, 2), scans of a closed-form room,
// frame transforms (section 6, including the paper's Unity ZXY form), noise, dropout, range
// limits, self-filter, determinism. The scene is an analytic RayCaster written here, so these
// tests need nothing from the simulator.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "starnav/core/error.hpp"
#include "starnav/sense/lidar.hpp"

namespace starnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The inside of an axis-aligned box room: distance to the first wall, floor or ceiling.
class Room : public RayCaster {
 public:
  Room(const Vec3& lo, const Vec3& hi) : lo_(lo), hi_(hi) {}
  RayHit cast(const Vec3& o, const Vec3& d, double max_range, double time) const override {
    last_time = time;
    RayHit h;
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0.0) continue;
      const double wall = d[a] > 0 ? hi_[a] : lo_[a];
      const double t = (wall - o[a]) / d[a];
      if (t >= 0 && t <= max_range && t < h.distance) {
        h.distance = t;
        h.kind = HitKind::obstacle;
        h.normal = Vec3::Zero();
        h.normal[a] = d[a] > 0 ? -1.0 : 1.0;
      }
    }
    return h;
  }
  mutable double last_time = -1.0;

 private:
  Vec3 lo_, hi_;
};

Eigen::Matrix3d rot(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  Eigen::Matrix3d rx, ry, rz;
  rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  return rz * ry * rx;
}

struct PresetExpect {
  const char* name;
  double fov_deg;
  int beams;
  double delta_deg;
  int lines;
  double top_deg, bottom_deg;
  double range_min, range_max, rate;
};

TEST(Lidar, PresetsMatchTheSpec) {
  const PresetExpect expect[] = {
      {"hokuyo_utm30lx", 270, 1081, 0.25, 1, 0, 0, 0.1, 30, 40},
      {"sick_lms151", 270, 541, 0.5, 1, 0, 0, 0.5, 50, 50},
      {"generic_360", 360, 360, 1.0, 1, 0, 0, 0.15, 12, 10},
      {"ibeo_lux4", 110, 551, 0.2, 4, 1.2, -1.2, 0.3, 200, 10},
      {"ibeo_lux8", 110, 551, 0.2, 8, 2.8, -2.8, 0.3, 200, 10},
      {"vlp16", 360, 1800, 0.2, 16, 15, -15, 0.5, 100, 10},
      {"hdl32e", 360, 1800, 0.2, 32, 10.67, -30.67, 1.0, 70, 10},
      {"hdl64e", 360, 1800, 0.2, 64, 2, -24.9, 0.9, 120, 10},
  };
  ASSERT_EQ(lidar_preset_names().size(), std::size(expect));
  for (const PresetExpect& e : expect) {
    SCOPED_TRACE(e.name);
    const LidarConfig c = lidar_preset(e.name);
    EXPECT_EQ(c.model, e.name);
    EXPECT_NEAR(c.scan_angle, deg_to_rad(e.fov_deg), 1e-12);
    EXPECT_EQ(c.beams, e.beams);
    EXPECT_NEAR(c.delta(), deg_to_rad(e.delta_deg), 1e-12);
    ASSERT_EQ(c.lines(), e.lines);
    EXPECT_NEAR(c.elevations.front(), deg_to_rad(e.top_deg), 1e-12);
    EXPECT_NEAR(c.elevations.back(), deg_to_rad(e.bottom_deg), 1e-12);
    for (int j = 1; j < c.lines(); ++j)  // evenly spaced, top first
      EXPECT_NEAR(c.elevations[static_cast<std::size_t>(j - 1)] - c.elevations[static_cast<std::size_t>(j)],
                  deg_to_rad(e.top_deg - e.bottom_deg) / (e.lines - 1), 1e-12);
    EXPECT_EQ(c.range_min, e.range_min);
    EXPECT_EQ(c.range_max, e.range_max);
    EXPECT_EQ(c.rate_hz, e.rate);
    // First beam on the left edge of the field of view; the last on the right edge, or one step
    // short of it for a full circle (no duplicate beam at +-180 deg).
    EXPECT_NEAR(c.azimuth(0), 0.5 * c.scan_angle, 1e-12);
    if (c.full_circle()) {
      EXPECT_NEAR(c.azimuth(c.beams - 1), -kPi + c.delta(), 1e-12);
      std::set<long> seen;
      for (int i = 0; i < c.beams; ++i) {
        const double a = wrap_angle(c.azimuth(i));
        EXPECT_TRUE(seen.insert(std::lround(a / c.delta() * 8)).second) << "duplicate beam " << i;
      }
    } else {
      EXPECT_NEAR(c.azimuth(c.beams - 1), -0.5 * c.scan_angle, 1e-12);
    }
    for (int i = 1; i < c.beams; ++i) EXPECT_LT(c.azimuth(i), c.azimuth(i - 1));
  }
  // The spec's line spacings: VLP-16 2 deg, IBEO 0.8 deg, HDL-32E ~1.333 deg, HDL-64E ~0.42 deg.
  EXPECT_NEAR(rad_to_deg(lidar_preset("vlp16").elevations[1] - lidar_preset("vlp16").elevations[2]), 2.0, 1e-12);
  EXPECT_NEAR(rad_to_deg(lidar_preset("ibeo_lux8").elevations[0] - lidar_preset("ibeo_lux8").elevations[1]), 0.8, 1e-12);
  EXPECT_NEAR(rad_to_deg(lidar_preset("hdl32e").elevations[0] - lidar_preset("hdl32e").elevations[1]), 1.333, 0.001);
  EXPECT_NEAR(rad_to_deg(lidar_preset("hdl64e").elevations[0] - lidar_preset("hdl64e").elevations[1]), 0.42, 0.01);
  // Horizontal resolution is a parameter of the 3D presets.
  EXPECT_EQ(lidar_preset("vlp16", deg_to_rad(1.0)).beams, 360);
  EXPECT_EQ(lidar_preset("ibeo_lux4", deg_to_rad(0.5)).beams, 221);
  EXPECT_EQ(lidar_preset("vlp16").ray_count(), 28800u);
  try {
    lidar_preset("velodyne");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "model");
  }
}

TEST(Lidar, RayDirectionsFollowTheSpecsBeamOrder) {
  const Lidar lidar(lidar_preset("hdl32e", deg_to_rad(2.0)));
  const LidarConfig& c = lidar.config();
  ASSERT_EQ(lidar.directions().size(), c.ray_count());
  for (int j = 0; j < c.lines(); ++j)
    for (int i = 0; i < c.beams; ++i) {
      const double phi = c.elevations[static_cast<std::size_t>(j)], theta = c.azimuth(i);
      const Vec3& d = lidar.directions()[static_cast<std::size_t>(j * c.beams + i)];
      EXPECT_NEAR((d - Vec3(std::cos(phi) * std::cos(theta), std::cos(phi) * std::sin(theta), std::sin(phi))).norm(), 0.0, 1e-15);
    }
  // 2D, 270 deg: beam 0 looks back-left (azimuth +135 deg), the middle beam straight ahead, the
  // last back-right.
  const Lidar utm(lidar_preset("hokuyo_utm30lx"));
  const auto& d = utm.directions();
  EXPECT_NEAR((d[0] - Vec3(-std::sqrt(0.5), std::sqrt(0.5), 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((d[540] - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((d[1080] - Vec3(-std::sqrt(0.5), -std::sqrt(0.5), 0)).norm(), 0.0, 1e-12);
}

TEST(Lidar, RoomScanGivesClosedFormRanges) {
  const Room room(Vec3(-3, -2, -0.5), Vec3(4, 5, 2.0));
  Lidar lidar(lidar_preset("vlp16", deg_to_rad(1.0)));
  const LidarScan s = lidar.scan(room, Pose3(), 7.5);
  EXPECT_EQ(room.last_time, 7.5);
  EXPECT_EQ(s.time, 7.5);
  ASSERT_EQ(s.lines, 16);
  ASSERT_EQ(s.beams, 360);
  ASSERT_EQ(s.points_sensor.size(), s.ranges.size());  // every ray returns within 100 m
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 360; ++i) {
      const double phi = deg_to_rad(15.0 - 2.0 * j), theta = s.azimuths[static_cast<std::size_t>(i)];
      const double dx = std::cos(phi) * std::cos(theta), dy = std::cos(phi) * std::sin(theta), dz = std::sin(phi);
      double want = kInf;
      if (dx > 0) want = std::min(want, 4 / dx);
      if (dx < 0) want = std::min(want, -3 / dx);
      if (dy > 0) want = std::min(want, 5 / dy);
      if (dy < 0) want = std::min(want, -2 / dy);
      if (dz > 0) want = std::min(want, 2 / dz);
      if (dz < 0) want = std::min(want, -0.5 / dz);
      EXPECT_NEAR(s.range(j, i), want, 1e-12);
      const std::size_t k = static_cast<std::size_t>(j * 360 + i);
      EXPECT_EQ(s.point_ray[k], k);
      // The spec's point: (L cos(phi) cos(theta), L cos(phi) sin(theta), L sin(phi)).
      EXPECT_NEAR((s.points_sensor[k] - want * Vec3(dx, dy, dz)).norm(), 0.0, 1e-12);
    }
}

TEST(Lidar, RangeLimitsGiveNoReturn) {
  const Room room(Vec3(-20, -0.3, -1), Vec3(20, 0.3, 1));
  LidarConfig c = lidar_preset("generic_360");  // 0.15 .. 12 m
  Lidar lidar(c);
  const LidarScan s = lidar.scan(room, Pose3(), 0.0);
  // Straight ahead the wall is 20 m away (beyond 12 m): inf; sideways 0.3 m: a return.
  EXPECT_TRUE(std::isinf(s.range(0, 180)));  // azimuth 0
  EXPECT_NEAR(s.range(0, 90), 0.3, 1e-12);   // azimuth +90 deg
  c.range_min = 0.31;
  Lidar near_blind(c);
  const LidarScan b = near_blind.scan(room, Pose3(), 0.0);
  EXPECT_TRUE(std::isinf(b.range(0, 90)));
  EXPECT_EQ(b.points_world.size() + std::count_if(b.ranges.begin(), b.ranges.end(), [](double r) { return std::isinf(r); }),
            b.ranges.size());
}

TEST(Lidar, SensorToWorldTransform) {
  const Room room(Vec3(-6, -5, -3), Vec3(7, 8, 4));
  LidarConfig c = lidar_preset("hdl32e", deg_to_rad(3.0));
  const double m_roll = 0.05, m_pitch = -0.1, m_yaw = 0.4;
  const Vec3 t_mount(0.2, -0.05, 0.45);
  c.mount = Pose3::from_rpy(t_mount, m_roll, m_pitch, m_yaw);
  Lidar lidar(c);
  const double roll = 0.1, pitch = 0.15, yaw = -2.0;
  const Vec3 t_robot(1.0, 2.0, 0.3);
  const LidarScan s = lidar.scan(room, Pose3::from_rpy(t_robot, roll, pitch, yaw), 0.0);
  const Eigen::Matrix3d r_robot = rot(roll, pitch, yaw), r_mount = rot(m_roll, m_pitch, m_yaw);
  const Vec3 sensor = r_robot * t_mount + t_robot;
  EXPECT_NEAR((s.sensor_pose.position - sensor).norm(), 0.0, 1e-12);
  ASSERT_GT(s.points_world.size(), 1000u);
  for (std::size_t k = 0; k < s.points_world.size(); ++k) {
    // Spec section 6: p_world = R_robot (R_mount p_sensor + t_mount) + t_robot.
    const Vec3 want = r_robot * (r_mount * s.points_sensor[k] + t_mount) + t_robot;
    EXPECT_NEAR((s.points_world[k] - want).norm(), 0.0, 1e-12);
    // ... and the point lies on one of the room's six planes.
    const Vec3& p = s.points_world[k];
    const double off = std::min({std::abs(p.x() + 6), std::abs(p.x() - 7), std::abs(p.y() + 5), std::abs(p.y() - 8),
                                 std::abs(p.z() + 3), std::abs(p.z() - 4)});
    EXPECT_LT(off, 1e-9);
  }
}

TEST(Lidar, PaperUnityRotationIsTheSameTransform) {
  // The paper writes the LiDAR-to-world rotation in Unity's left-handed, y-up frame as
  // R_w = R_y(beta) R_x(alpha) R_z(gamma) (Euler order ZXY). Unity axes (x right, y up, z
  // forward) map to REP-103 (x forward, y left, z up) by P: ros = (z_u, -x_u, y_u). The same
  // rotation in REP-103 is P R_w P^T = Rz(-beta) Ry(alpha) Rx(-gamma): yaw = -beta, pitch =
  // alpha, roll = -gamma. Check on points of a scan.
  Eigen::Matrix3d p;
  p << 0, 0, 1, -1, 0, 0, 0, 1, 0;
  const double alpha = 0.2, beta = 0.7, gamma = -0.3;
  auto rx = [](double a) { return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(); };
  auto ry = [](double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); };
  auto rz = [](double a) { return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(); };
  const Eigen::Matrix3d r_unity = ry(beta) * rx(alpha) * rz(gamma);
  const Vec3 t_unity(1.0, 0.4, 2.0);  // position in Unity coordinates
  const Room room(Vec3(-10, -10, -2), Vec3(10, 10, 3));
  Lidar lidar(lidar_preset("ibeo_lux8", deg_to_rad(2.0)));
  const Pose3 robot = Pose3::from_rpy(p * t_unity, -gamma, alpha, -beta);
  const LidarScan s = lidar.scan(room, robot, 0.0);
  ASSERT_FALSE(s.points_world.empty());
  for (std::size_t k = 0; k < s.points_world.size(); ++k) {
    const Vec3 p_unity_sensor = p.transpose() * s.points_sensor[k];
    const Vec3 p_unity_world = r_unity * p_unity_sensor + t_unity;  // the paper's formula
    EXPECT_NEAR((p * p_unity_world - s.points_world[k]).norm(), 0.0, 1e-12);
  }
}

TEST(Lidar, NoiseAndDropoutStatistics) {
  const Room room(Vec3(-5, -5, -1), Vec3(5, 5, 3));
  LidarConfig c = lidar_preset("vlp16", deg_to_rad(0.5));
  c.noise_sigma = 0.03;
  c.dropout = 0.1;
  Lidar clean(lidar_preset("vlp16", deg_to_rad(0.5)));
  Lidar noisy(c, Rng(99));
  const LidarScan truth = clean.scan(room, Pose3(), 0.0);
  double sum = 0, sum2 = 0;
  std::size_t n = 0, lost = 0, total = 0;
  for (int scan = 0; scan < 4; ++scan) {
    const LidarScan s = noisy.scan(room, Pose3(), 0.1 * scan);
    lost += s.dropped;
    for (std::size_t k = 0; k < s.ranges.size(); ++k) {
      ++total;
      if (std::isinf(s.ranges[k])) continue;
      const double e = s.ranges[k] - truth.ranges[k];
      sum += e;
      sum2 += e * e;
      ++n;
    }
  }
  EXPECT_EQ(n + lost, total);
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_LT(std::abs(mean), 4 * 0.03 / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(sd, 0.03, 0.03 * 0.02);
  const double p = static_cast<double>(lost) / total;
  EXPECT_NEAR(p, 0.1, 4 * std::sqrt(0.1 * 0.9 / total));
}

TEST(Lidar, SameSeedSameScansDifferentSeedDifferentScans) {
  const Room room(Vec3(-5, -5, -1), Vec3(5, 5, 3));
  LidarConfig c = lidar_preset("hokuyo_utm30lx");
  c.noise_sigma = 0.01;
  c.dropout = 0.05;
  Lidar a(c, Rng(7)), b(c, Rng(7)), other(c, Rng(8));
  for (int k = 0; k < 3; ++k) {
    const LidarScan sa = a.scan(room, Pose3(), k), sb = b.scan(room, Pose3(), k), so = other.scan(room, Pose3(), k);
    EXPECT_EQ(sa.ranges, sb.ranges);
    EXPECT_NE(sa.ranges, so.ranges);
  }
  // Without noise the scan is a pure function of the scene and the pose.
  Lidar x(lidar_preset("sick_lms151"), Rng(1)), y(lidar_preset("sick_lms151"), Rng(2));
  EXPECT_EQ(x.scan(room, Pose3(), 0).ranges, y.scan(room, Pose3(), 0).ranges);
}

TEST(Lidar, SelfFilterDropsReturnsInsideTheBodyBox) {
  // Sensor 0.3 m above the floor; the body box reaches down to the floor within 1 m around it.
  const Room room(Vec3(-10, -10, -0.3), Vec3(10, 10, 5));
  LidarConfig c = lidar_preset("vlp16", deg_to_rad(1.0));
  c.self_filter = SelfFilterBox{Vec3(-1, -1, -0.35), Vec3(1, 1, 0.1)};
  Lidar lidar(c);
  const LidarScan s = lidar.scan(room, Pose3(), 0.0);
  Lidar unfiltered(lidar_preset("vlp16", deg_to_rad(1.0)));
  const LidarScan u = unfiltered.scan(room, Pose3(), 0.0);
  std::size_t inside = 0;
  for (const Vec3& p : u.points_sensor) inside += c.self_filter->contains(p);
  EXPECT_GT(inside, 0u);
  EXPECT_EQ(s.self_filtered, inside);
  EXPECT_EQ(s.points_sensor.size() + inside, u.points_sensor.size());
  for (const Vec3& p : s.points_sensor) EXPECT_FALSE(c.self_filter->contains(p));
  // From a body box in base_link: the Mecanum body (0.55 x 0.50 m, 0.3 m tall) with the LiDAR
  // 0.35 m up and turned 90 deg: in the sensor frame x and y swap.
  const Pose3 mount = Pose3::from_rpy(Vec3(0.1, 0, 0.35), 0, 0, kPi / 2);
  const SelfFilterBox b = SelfFilterBox::around_body(Vec3(-0.275, -0.25, 0.0), Vec3(0.275, 0.25, 0.3), mount, 0.05);
  EXPECT_NEAR((b.min - Vec3(-0.3, -0.225, -0.4)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((b.max - Vec3(0.3, 0.425, 0.0)).norm(), 0.0, 1e-12);
}

TEST(Lidar, ValidationNamesTheField) {
  auto field_of = [](const LidarConfig& c) {
    try {
      c.validate();
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("(none)");
  };
  LidarConfig c = lidar_preset("sick_lms151");
  EXPECT_EQ(field_of(c), "(none)");
  LidarConfig bad = c;
  bad.beams = 1;
  EXPECT_EQ(field_of(bad), "beams");
  // Rays per scan: the largest allowed passes, one line more does not.
  bad = c;
  bad.beams = static_cast<int>(kMaxLidarRaysPerScan / 64);
  bad.set_lines(64, 0.3, 0.01);
  EXPECT_EQ(field_of(bad), "(none)");
  bad.set_lines(65, 0.3, 0.01);
  EXPECT_EQ(field_of(bad), "beams");
  bad = c;
  bad.scan_angle = deg_to_rad(400);
  EXPECT_EQ(field_of(bad), "scan_angle");
  bad = c;
  bad.range_max = 0.2;
  EXPECT_EQ(field_of(bad), "range_max");
  bad = c;
  bad.dropout = 1.5;
  EXPECT_EQ(field_of(bad), "dropout");
  bad = c;
  bad.noise_sigma = -1;
  EXPECT_EQ(field_of(bad), "noise_sigma");
  bad = c;
  bad.elevations = {};
  EXPECT_EQ(field_of(bad), "lines");
  bad = c;
  bad.rate_hz = 0;
  EXPECT_EQ(field_of(bad), "rate_hz");
  bad = c;
  bad.self_filter = SelfFilterBox{Vec3(1, 0, 0), Vec3(0, 1, 1)};
  EXPECT_EQ(field_of(bad), "self_filter");
  EXPECT_THROW(Lidar{bad}, Error);
  // A 360 deg scan may have a single beam; delta is then the whole circle.
  LidarConfig one = lidar_preset("generic_360");
  one.beams = 1;
  EXPECT_EQ(field_of(one), "(none)");
}

}  // namespace
}  // namespace starnav
