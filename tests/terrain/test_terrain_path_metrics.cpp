// Path metrics: exact on planes of known tilt (roll only, pitch only, both), lv/av/hv/Sv by
// hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "starnav/core/error.hpp"
#include "starnav/terrain/terrain_path_metrics.hpp"
#include "terrain_test_util.hpp"

namespace {

using namespace starnav;
using terrain_test::geometry;

ElevationMap plane(double a, double b, int w = 40, int h = 40, double res = 0.1, Pose2 origin = {}) {
  ElevationMap m(geometry(w, h, res, origin));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) m.set_height(x, y, 1.0 + a * (x + 0.5) * res + b * (y + 0.5) * res);
  return m;
}

std::vector<Cell> row_path(int y, int x0, int x1) {
  std::vector<Cell> p;
  for (int x = x0; x <= x1; ++x) p.push_back({x, y});
  return p;
}

double deg(double rad) { return rad * 180.0 / std::numbers::pi; }

TEST(PathMetrics, PitchOnlyPlane) {
  const double a = 0.2;  // rises along +x: heading +x is nose up, pitch negative (REP-103)
  const TerrainAnalysis t(plane(a, 0.0));
  std::vector<AttitudeSample> samples;
  const TerrainPathMetrics m = terrain_path_metrics(t, row_path(20, 10, 30), {}, &samples);
  ASSERT_EQ(samples.size(), 21u);
  for (const auto& s : samples) {
    ASSERT_TRUE(s.attitude.valid);
    EXPECT_NEAR(s.attitude.pitch, -std::atan(a), 1e-12);
    EXPECT_NEAR(s.attitude.roll, 0.0, 1e-12);
    EXPECT_NEAR(s.attitude.tilt, std::atan(a), 1e-12);
    EXPECT_NEAR(s.heading, 0.0, 1e-15);
  }
  EXPECT_NEAR(m.pitch_mean_deg, deg(std::atan(a)), 1e-10);
  EXPECT_NEAR(m.pitch_max_deg, deg(std::atan(a)), 1e-10);
  EXPECT_NEAR(m.roll_mean_deg, 0.0, 1e-10);
  EXPECT_NEAR(m.tilt_mean_deg, deg(std::atan(a)), 1e-10);
  EXPECT_EQ(m.attitude_nodes, 21u);
  // Along the path: 20 moves of 0.1 m rising 0.02 m each.
  EXPECT_EQ(m.moves, 20u);
  EXPECT_NEAR(m.length_2d_m, 2.0, 1e-12);
  EXPECT_NEAR(m.lv_m, 20 * std::hypot(0.1, 0.02), 1e-12);
  EXPECT_NEAR(m.hv_m, 0.02, 1e-12);
  EXPECT_NEAR(m.av_rad, std::atan(0.2), 1e-12);
  // S of a plane z = a x in a full 3x3 block: (2/3) (a res)^2.
  EXPECT_NEAR(m.sv_m2, 2.0 / 3.0 * 0.02 * 0.02, 1e-15);
  // Going the other way: nose down, pitch positive; |mean| and max unchanged.
  std::vector<Cell> back = row_path(20, 10, 30);
  std::reverse(back.begin(), back.end());
  const TerrainPathMetrics mb = terrain_path_metrics(t, back, {}, &samples);
  EXPECT_NEAR(samples[5].attitude.pitch, std::atan(a), 1e-12);
  EXPECT_NEAR(mb.pitch_mean_deg, m.pitch_mean_deg, 1e-10);
}

TEST(PathMetrics, RollOnlyPlane) {
  const double b = 0.3;  // rises toward +y: heading +x has its left side up, roll positive
  const TerrainAnalysis t(plane(0.0, b));
  std::vector<AttitudeSample> samples;
  const TerrainPathMetrics m = terrain_path_metrics(t, row_path(20, 10, 30), {}, &samples);
  for (const auto& s : samples) {
    EXPECT_NEAR(s.attitude.roll, std::atan(b), 1e-12);
    EXPECT_NEAR(s.attitude.pitch, 0.0, 1e-12);
    EXPECT_NEAR(s.attitude.tilt, std::atan(b), 1e-12);
  }
  EXPECT_NEAR(m.roll_mean_deg, deg(std::atan(b)), 1e-10);
  EXPECT_NEAR(m.roll_max_deg, deg(std::atan(b)), 1e-10);
  EXPECT_NEAR(m.pitch_max_deg, 0.0, 1e-10);
  EXPECT_NEAR(m.hv_m, 0.0, 1e-12);
  EXPECT_NEAR(m.lv_m, 2.0, 1e-12);
}

TEST(PathMetrics, PitchAndRollPlaneMatchTheRotation) {
  const double a = 0.25, b = -0.15;
  const TerrainAnalysis t(plane(a, b));
  std::vector<AttitudeSample> samples;
  terrain_path_metrics(t, row_path(20, 10, 30), {}, &samples);
  // R = Ry(pitch) Rx(roll) (yaw 0): x axis along (1, 0, a), z axis along (-a, -b, 1).
  const Attitude& att = samples[10].attitude;
  EXPECT_NEAR(att.pitch, -std::atan(a), 1e-12);
  EXPECT_NEAR(att.roll, std::atan2(b, std::sqrt(1 + a * a)), 1e-12);
  EXPECT_NEAR(att.tilt, std::atan(std::hypot(a, b)), 1e-12);
  const Eigen::Matrix3d r = Pose3::from_rpy(Vec3::Zero(), att.roll, att.pitch, 0.0).rotation();
  EXPECT_NEAR((r.col(0) - Vec3(1, 0, a).normalized()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((r.col(2) - Vec3(-a, -b, 1).normalized()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(std::acos(r(2, 2)), att.tilt, 1e-12);
}

TEST(PathMetrics, HeadingAlongTheDiagonalOnARotatedMap) {
  // World plane z = c x_w (x_w the world x); the map is rotated by 0.4 rad. A path along the
  // grid's NE diagonal heads at yaw 0.4 + pi/4 in the world: its forward slope is
  // c cos(heading), its left slope -c sin(heading).
  const double yaw = 0.4, c = 0.2, res = 0.1;
  const Pose2 origin(3.0, -1.0, yaw);
  ElevationMap m(geometry(40, 40, res, origin));
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) m.set_height(x, y, c * m.geometry().cell_center(x, y).x());
  const TerrainAnalysis t(m);
  std::vector<Cell> path;
  for (int i = 10; i <= 30; ++i) path.push_back({i, i});
  std::vector<AttitudeSample> samples;
  terrain_path_metrics(t, path, {}, &samples);
  const double heading = yaw + std::numbers::pi / 4;
  const double px = c * std::cos(heading), py = -c * std::sin(heading);
  for (const auto& s : samples) {
    EXPECT_NEAR(s.heading, heading, 1e-12);
    EXPECT_NEAR(s.attitude.pitch, -std::atan(px), 1e-12);
    EXPECT_NEAR(s.attitude.roll, std::atan2(py, std::sqrt(1 + px * px)), 1e-12);
    EXPECT_NEAR(s.attitude.tilt, std::atan(c), 1e-12);
  }
}

TEST(PathMetrics, MeanIsAbsoluteOfSignedMeanAndMaxIsOfMagnitudes) {
  // Roll +atan(b) on the way out (heading +x) and -atan(b) on the way back: signed mean ~ 0.
  const double b = 0.3;
  const TerrainAnalysis t(plane(0.0, b));
  std::vector<Cell> path = row_path(20, 10, 20);
  path.push_back({21, 21});  // step up a row and come back along it
  for (int x = 20; x >= 10; --x) path.push_back({x, 22});
  std::vector<AttitudeSample> samples;
  const TerrainPathMetrics m = terrain_path_metrics(t, path, {}, &samples);
  double sum = 0, abs_sum = 0, mx = 0;
  for (const auto& s : samples) {
    sum += s.attitude.roll;
    abs_sum += std::abs(s.attitude.roll);
    mx = std::max(mx, std::abs(s.attitude.roll));
  }
  const double n = static_cast<double>(samples.size());
  EXPECT_NEAR(m.roll_mean_deg, deg(std::abs(sum / n)), 1e-10);
  EXPECT_NEAR(m.roll_mean_abs_deg, deg(abs_sum / n), 1e-10);
  EXPECT_NEAR(m.roll_max_deg, deg(mx), 1e-10);
  EXPECT_LT(m.roll_mean_deg, 0.25 * m.roll_mean_abs_deg);
  EXPECT_NEAR(m.roll_max_deg, deg(std::atan(b)), 1e-10);
}

TEST(PathMetrics, UnobservedCellsAndErrors) {
  ElevationMap m = plane(0.1, 0.0, 12, 6);
  m.clear_cell(5, 3);
  const TerrainAnalysis t(m);
  const TerrainPathMetrics r = terrain_path_metrics(t, row_path(3, 2, 8));
  EXPECT_EQ(r.moves, 6u);
  EXPECT_EQ(r.moves_measured, 4u);  // 4->5 and 5->6 unknown
  EXPECT_EQ(r.cells_measured, 6u);
  EXPECT_NEAR(r.lv_m, 4 * std::hypot(0.1, 0.01) + 2 * 0.1, 1e-12);
  EXPECT_NEAR(r.hv_m, 0.01, 1e-12);
  EXPECT_THROW(terrain_path_metrics(t, {{0, 0}, {2, 0}}), Error);
  EXPECT_THROW(terrain_path_metrics(t, {{0, 0}, {-1, 0}}), Error);
  const TerrainPathMetrics empty = terrain_path_metrics(t, {});
  EXPECT_EQ(empty.nodes, 0u);
  EXPECT_EQ(empty.lv_m, 0.0);
}

TEST(PathMetrics, BilinearHeightsBetweenCentres) {
  const TerrainAnalysis t(plane(0.2, -0.1, 10, 10));
  double z = 0;
  ASSERT_TRUE(terrain_height_at(t, Vec2(0.37, 0.52), z));
  EXPECT_NEAR(z, 1.0 + 0.2 * 0.37 - 0.1 * 0.52, 1e-12);
  // Beyond the outermost centres: clamped.
  ASSERT_TRUE(terrain_height_at(t, Vec2(-5.0, 0.55), z));
  EXPECT_NEAR(z, 1.0 + 0.2 * 0.05 - 0.1 * 0.55, 1e-12);
}

}  // namespace
