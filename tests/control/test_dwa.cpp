// The DWA controller (control/dwa*.hpp): the dynamic window against hand-computed bounds, the
// rollout against the closed-form arc, the local map and footprint test against brute force, each
// critic on hand-built cases, and the controller in closed loop on an ideal robot: a chosen
// command never touches an obstacle (random maps, checked with the cells as squares), no valid
// sample gives Blocked, a Mecanum robot reaches a goal to its side by translating, a doorway.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "starnav/control/dwa.hpp"
#include "starnav/control/dwa_controller.hpp"
#include "starnav/control/dwa_critics.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/planar_motion.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/registry/components.hpp"
#include "support/box_world.hpp"
#include "support/ideal_robots.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

using test::empty_map;
using test::fill_box;

using test::differential;
using test::mecanum;

// --- The dynamic window and sampling ------------------------------------------------------------

TEST(DynamicWindow, ReachesWhatTheAccelerationAllowsInOnePeriod) {
  DwaLimits l;
  l.min_vx = 0.0;
  l.max_vx = 0.5;
  l.max_vy = 0.3;
  l.max_wz = 1.0;
  l.acc_x = 1.0;
  l.acc_y = 0.5;
  l.acc_yaw = 2.0;
  const DynamicWindow w = dynamic_window({0.2, -0.1, 0.5}, l, 0.05);
  EXPECT_NEAR(w.vx_lo, 0.15, 1e-12);
  EXPECT_NEAR(w.vx_hi, 0.25, 1e-12);
  EXPECT_NEAR(w.vy_lo, -0.125, 1e-12);
  EXPECT_NEAR(w.vy_hi, -0.075, 1e-12);
  EXPECT_NEAR(w.wz_lo, 0.4, 1e-12);
  EXPECT_NEAR(w.wz_hi, 0.6, 1e-12);
  // At rest the backward side is cut at min_vx; near a limit it is cut there.
  const DynamicWindow rest = dynamic_window({0.0, 0.0, 0.98}, l, 0.05);
  EXPECT_EQ(rest.vx_lo, 0.0);
  EXPECT_NEAR(rest.vx_hi, 0.05, 1e-12);
  EXPECT_NEAR(rest.wz_lo, 0.88, 1e-12);
  EXPECT_EQ(rest.wz_hi, 1.0);
  // Faster than the limit (a manual command): the window is the limit itself.
  const DynamicWindow over = dynamic_window({0.9, 0.0, 0.0}, l, 0.05);
  EXPECT_EQ(over.vx_lo, 0.5);
  EXPECT_EQ(over.vx_hi, 0.5);
}

TEST(DynamicWindow, LimitsAreTheTighterOfTheConfigurationAndTheRobot) {
  DwaConfig c;
  c.max_vx_mps = 2.0;
  c.max_vy_mps = 0.3;
  c.min_vx_mps = -0.2;
  const VelocityLimits robot = velocity_limits_of(mecanum());  // 0.76 m/s along each axis
  const DwaLimits l = dwa_limits(c, robot, true);
  EXPECT_NEAR(l.max_vx, 10.0 * 0.076, 1e-12);
  EXPECT_EQ(l.max_vy, 0.3);
  EXPECT_EQ(l.min_vx, -0.2);
  EXPECT_EQ(dwa_limits(c, robot, false).max_vy, 0.0);
}

TEST(WindowSamples, SpreadEvenlyWithZeroExactWhereTheWindowHoldsIt) {
  const std::vector<double> a = window_samples(-0.2, 0.2, 5);
  ASSERT_EQ(a.size(), 5u);
  EXPECT_DOUBLE_EQ(a[0], -0.2);
  EXPECT_DOUBLE_EQ(a[1], -0.1);
  EXPECT_EQ(a[2], 0.0);
  EXPECT_DOUBLE_EQ(a[4], 0.2);
  const std::vector<double> b = window_samples(-0.05, 0.25, 4);  // -0.05, 0.05, 0.15, 0.25
  EXPECT_EQ(std::count(b.begin(), b.end(), 0.0), 1);
  EXPECT_DOUBLE_EQ(b.back(), 0.25);
  EXPECT_EQ(window_samples(0.1, 0.3, 1), std::vector<double>{0.1});
  EXPECT_EQ(window_samples(-0.3, 0.3, 1), std::vector<double>{0.0});
  const std::vector<double> c = window_samples(0.1, 0.3, 3);
  EXPECT_EQ(std::count(c.begin(), c.end(), 0.0), 0);
}

TEST(DwaCheckTime, CoversThePeriodTheLagAndHalfTheBraking) {
  DwaLimits l;
  l.acc_x = 0.5;
  l.acc_y = 1.0;
  l.acc_yaw = 1.0;
  // 2 m/s at 0.5 m/s^2: 4 s of braking, 2 s of it counted on the same arc, plus 0.05 + 0.1.
  EXPECT_NEAR(dwa_check_time({2.0, 0.0, 0.0}, l, 1.7, 0.05, 0.1), 2.15, 1e-12);
  EXPECT_NEAR(dwa_check_time({0.5, 0.0, 0.0}, l, 1.7, 0.05, 0.1), 1.7, 1e-12);
}

TEST(DwaRollout, FollowsTheClosedFormArc) {
  const Pose2 start(1.0, 2.0, 0.3);
  const BodyTwist t{0.4, 0.1, 0.8};
  std::vector<Pose2> poses;
  dwa_rollout(start, t, 0.05, 34, poses);
  ASSERT_EQ(poses.size(), 34u);
  // A constant body twist moves the point on a circle about the instantaneous centre.
  const double v = std::hypot(t.vx, t.vy), r = v / t.wz;
  const double heading = start.yaw + std::atan2(t.vy, t.vx);
  const Vec2 centre = start.translation() + r * Vec2(-std::sin(heading), std::cos(heading));
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const double tk = 0.05 * static_cast<double>(k + 1);
    EXPECT_NEAR((poses[k].translation() - centre).norm(), r, 1e-9);
    EXPECT_NEAR(wrap_angle(poses[k].yaw - start.yaw - t.wz * tk), 0.0, 1e-9);
  }
  const Pose2 direct = advance_on_arc(start, t.vx, t.vy, t.wz, 1.7);
  EXPECT_NEAR((poses.back().translation() - direct.translation()).norm(), 0.0, 1e-9);
}

// --- The local map and the footprint ------------------------------------------------------------

OccupancyGrid random_map(Rng& rng, double w, double h, double density) {
  OccupancyGrid m = empty_map(w, h);
  for (std::size_t i = 0; i < m.cell_count(); ++i)
    if (rng.bernoulli(density)) m.data()[i] = kOccupiedOccupancy;
  return m;
}

TEST(ClearanceWindow, ClearanceIsTheDistanceToTheNearestObstacleCentre) {
  Rng rng(3);
  const OccupancyGrid m = random_map(rng, 6.0, 5.0, 0.01);
  ClearanceWindow local;
  local.build(m, {2.0, 2.5}, 1.0, 0.5);
  ASSERT_GE(local.width(), 41);
  std::vector<Vec2> obstacles;
  for (int y = -20; y < m.height() + 20; ++y)
    for (int x = -20; x < m.width() + 20; ++x)
      if (!m.contains(x, y) || m(x, y) == kOccupiedOccupancy) obstacles.push_back(m.geometry().cell_center(x, y));
  for (int y = 0; y < local.height(); y += 3)
    for (int x = 0; x < local.width(); x += 3) {
      const Vec2 c = local.cell_center(x, y);
      double best = 1e9;
      for (const Vec2& o : obstacles) best = std::min(best, (o - c).norm());
      const double got = local.clearance_m(local.index(x, y));
      if (best <= 0.5) EXPECT_NEAR(got, best, 1e-9) << x << "," << y;  // exact within the padding
      else EXPECT_GE(got, 0.5 - 1e-9);
    }
}

TEST(ClearanceWindow, CellsBeyondTheMapAreObstacles) {
  const OccupancyGrid m = empty_map(4.0, 4.0);
  ClearanceWindow local;
  local.build(m, {0.3, 2.0}, 1.0, 0.5);
  const Cell c = local.cell_of({0.325, 2.025});
  EXPECT_NEAR(local.clearance_m(local.index(c.x, c.y)), 0.35, 1e-9);  // to the centre of the cell at x = -0.025
}

// A window is judged by its cells before anything is allocated: (2 ceil(half / res) + 1 +
// 2 (ceil(pad / res) + 1))^2 against 4e6, whatever the map behind it (a map of 4 x 4 cells here).
TEST(ClearanceWindow, AWindowOfMoreCellsThanTheLimitIsRefusedBeforeItIsBuilt) {
  const OccupancyGrid m = empty_map(0.004, 0.004, 0.001);
  ClearanceWindow local;
  local.build(m, {0.002, 0.002}, 0.3, 0.09);  // 601 + 2 x 91 = 783 cells a side
  EXPECT_EQ(local.width(), 601);
  EXPECT_DOUBLE_EQ(clearance_window_cells(0.9, 0.09, 0.001), 1983.0 * 1983.0);  // 3.9e6: within the limit
  for (const double half : {1.0, 1e9}) {  // 2001 + 182 cells a side: 4.8e6; and 2e12
    try {
      local.build(m, {0.002, 0.002}, half, 0.09);
      ADD_FAILURE() << "built a window " << half << " m wide";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "navigation.map.resolution_m");
      EXPECT_NE(std::string(e.what()).find(format_number(clearance_window_cells(half, 0.09, 0.001)) + " cells, more than 4000000"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(ClearanceWindow, WavefrontGoesRoundWallsWithOctileSteps) {
  OccupancyGrid m = empty_map(4.0, 4.0);
  ClearanceWindow local;
  local.build(m, {2.0, 2.0}, 1.5, 0.5);
  const Cell seed = local.cell_of({2.0, 2.0});
  std::vector<double> d;
  local.wavefront(std::span<const Cell>(&seed, 1), 0.0, d);
  EXPECT_NEAR(d[local.index(seed.x + 10, seed.y)], 0.5, 1e-12);
  EXPECT_NEAR(d[local.index(seed.x + 10, seed.y + 10)], 0.5 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(d[local.index(seed.x + 10, seed.y + 4)], 0.3 + 0.2 * std::sqrt(2.0), 1e-12);
  // A wall from y = 1 to y = 3 at x = 2.5: the way to the far side goes round its end.
  fill_box(m, 2.45, 1.0, 2.55, 3.0);
  local.build(m, {2.0, 2.0}, 1.5, 0.5);
  local.wavefront(std::span<const Cell>(&seed, 1), 0.0, d);
  const Cell far = local.cell_of({3.0, 2.0});
  EXPECT_GT(d[local.index(far.x, far.y)], 2.0);
  // Impassable cells (clearance below the threshold) stop it; the seed itself always counts.
  local.wavefront(std::span<const Cell>(&seed, 1), 10.0, d);
  EXPECT_EQ(d[local.index(seed.x, seed.y)], 0.0);
  EXPECT_TRUE(std::isinf(d[local.index(seed.x + 1, seed.y)]));
}

TEST(FootprintChecker, AgreesWithBruteForceOnRandomMaps) {
  Rng rng(11);
  int hits = 0, n = 0;
  for (int trial = 0; trial < test::scaled(20); ++trial) {
    const OccupancyGrid m = random_map(rng, 5.0, 5.0, rng.uniform(0.002, 0.03));
    ClearanceWindow local;
    local.build(m, {2.5, 2.5}, 1.5, 1.0);
    for (const int shape : {0, 1, 2}) {
      FootprintModel fm;
      fm.circle = shape == 0;
      fm.radius_m = 0.3;
      fm.half_length_m = shape == 1 ? 0.275 : 0.15;  // shape 2: wider than long
      fm.half_width_m = shape == 1 ? 0.25 : 0.4;
      const FootprintChecker check(fm, 0.02);
      for (int k = 0; k < 200; ++k) {
        const Pose2 p(rng.uniform(1.2, 3.8), rng.uniform(1.2, 3.8), rng.uniform(-kPi, kPi));
        const double extra = rng.uniform(0.0, 0.02);
        const bool got = check.collides(local, p, extra);
        EXPECT_EQ(got, check.collides_brute_force(local, p, extra)) << trial << " " << k;
        hits += got;
        ++n;
      }
    }
  }
  EXPECT_GT(hits, n / 10);  // both answers occur
  EXPECT_LT(hits, n - n / 10);
}

// The exact test alone (the scanline over the cells under the outline) against brute force over
// every obstacle of the window, poses near the outline's edge included: denser maps, a window
// whose map is rotated, bodies ahead of base_link, poses partly beyond the padded window.
TEST(FootprintChecker, TheExactTestIsBruteForcesAnswer) {
  Rng rng(19);
  int hits = 0, n = 0;
  for (int trial = 0; trial < test::scaled(12); ++trial) {
    OccupancyGrid m = random_map(rng, 5.0, 5.0, rng.uniform(0.003, 0.03));
    m.mutable_geometry().origin = Pose2(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), trial % 2 ? rng.uniform(-kPi, kPi) : 0.0);
    ClearanceWindow local;
    const Vec2 mid = m.geometry().grid_to_world({2.5, 2.5});
    local.build(m, mid, 1.5, 0.6);
    for (const int shape : {0, 1, 2}) {
      FootprintModel fm;
      fm.circle = shape == 0;
      fm.radius_m = rng.uniform(0.1, 0.35);
      fm.half_length_m = rng.uniform(0.1, 0.5);
      fm.half_width_m = rng.uniform(0.1, 0.3);
      fm.center_x_m = shape == 2 ? rng.uniform(-0.5, 0.5) : 0.0;
      const FootprintChecker check(fm, rng.uniform(0.0, 0.03));
      for (int k = 0; k < 150; ++k) {
        const Vec2 q = m.geometry().grid_to_world({rng.uniform(0.8, 4.2), rng.uniform(0.8, 4.2)});
        const Pose2 p(q.x(), q.y(), rng.uniform(-kPi, kPi));
        const Cell c = local.cell_of(q);
        if (!local.contains(c.x, c.y)) continue;
        const double extra = rng.uniform(-0.02, 0.05);
        const Vec2 heading(std::cos(p.yaw), std::sin(p.yaw));
        const bool got = check.exact_test(local, p, heading, extra);
        EXPECT_EQ(got, check.collides_brute_force(local, p, extra)) << trial << " " << shape << " " << k;
        hits += got;
        ++n;
      }
    }
  }
  EXPECT_GT(hits, n / 10);
  EXPECT_LT(hits, n - n / 10);
}

TEST(FootprintChecker, AnOutlineAheadOfBaseLinkIsTheCentredOneMovedForward) {
  // A car's body centred 0.35 m ahead of its rear axle (base_link): every answer equals the
  // centred outline's at the pose moved 0.35 m along the heading, and brute force's.
  Rng rng(12);
  int hits = 0, n = 0;
  for (int trial = 0; trial < test::scaled(10); ++trial) {
    const OccupancyGrid m = random_map(rng, 5.0, 5.0, rng.uniform(0.002, 0.03));
    ClearanceWindow local;
    local.build(m, {2.5, 2.5}, 1.5, 1.5);
    for (const bool circle : {false, true}) {
      FootprintModel centred;
      centred.circle = circle;
      centred.radius_m = 0.25;
      centred.half_length_m = 0.45;
      centred.half_width_m = 0.2;
      FootprintModel ahead = centred;
      ahead.center_x_m = 0.35;
      const FootprintChecker a(ahead, 0.02), c(centred, 0.02);
      for (int k = 0; k < 200; ++k) {
        const Pose2 p(rng.uniform(1.4, 3.6), rng.uniform(1.4, 3.6), rng.uniform(-kPi, kPi));
        const Pose2 moved(p.x + 0.35 * std::cos(p.yaw), p.y + 0.35 * std::sin(p.yaw), p.yaw);
        const bool got = a.collides(local, p);
        EXPECT_EQ(got, c.collides(local, moved)) << trial << " " << k;
        EXPECT_EQ(got, a.collides_brute_force(local, p)) << trial << " " << k;
        hits += got;
        ++n;
      }
    }
  }
  EXPECT_GT(hits, n / 10);
  EXPECT_LT(hits, n - n / 10);
  // About base_link: the farthest corner and the nearest edge.
  FootprintModel box;
  box.circle = false;
  box.half_length_m = 0.45;
  box.half_width_m = 0.2;
  box.center_x_m = 0.35;
  EXPECT_NEAR(box.bounding_radius_m(), std::hypot(0.8, 0.2), 1e-12);
  EXPECT_NEAR(box.inscribed_radius_m(), 0.1, 1e-12);  // the rear edge, 0.1 m behind base_link
  box.center_x_m = 0.6;                                // base_link outside the box
  EXPECT_EQ(box.inscribed_radius_m(), 0.0);
}

// Independent truth: does the rectangle (or circle) at `pose` overlap the square cell?
// Separating axis theorem for two rectangles; distance to the square for a circle.
bool overlaps_cell(const FootprintModel& fm, const Pose2& pose, const Vec2& cell_centre, double half_cell) {
  if (fm.circle) {
    const Vec2 d = (pose.translation() - cell_centre).cwiseAbs() - Vec2::Constant(half_cell);
    return d.cwiseMax(0.0).norm() <= fm.radius_m;
  }
  const Vec2 ax(std::cos(pose.yaw), std::sin(pose.yaw)), ay(-std::sin(pose.yaw), std::cos(pose.yaw));
  const Vec2 d = cell_centre - pose.translation();
  const auto separated = [&](const Vec2& axis) {
    const double r_robot = fm.half_length_m * std::abs(ax.dot(axis)) + fm.half_width_m * std::abs(ay.dot(axis));
    const double r_cell = half_cell * (std::abs(axis.x()) + std::abs(axis.y()));
    return std::abs(d.dot(axis)) > r_robot + r_cell;
  };
  return !(separated(ax) || separated(ay) || separated({1.0, 0.0}) || separated({0.0, 1.0}));
}

// The chosen command's motion, at fine steps until the robot could have stopped, overlaps no
// occupied cell.
bool chosen_motion_touches(const OccupancyGrid& m, const FootprintModel& fm, const Pose2& start, const BodyTwist& t,
                           double duration) {
  const GridGeometry& g = m.geometry();
  const int steps = static_cast<int>(std::ceil(duration / 0.005));
  for (int k = 0; k <= steps; ++k) {
    const Pose2 p = advance_on_arc(start, t.vx, t.vy, t.wz, 0.005 * k);
    const double reach = (fm.circle ? fm.radius_m : std::hypot(fm.half_length_m, fm.half_width_m)) + g.resolution;
    const Cell lo = g.world_to_cell_unchecked(p.translation() - Vec2::Constant(reach));
    const Cell hi = g.world_to_cell_unchecked(p.translation() + Vec2::Constant(reach));
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const bool obstacle = !m.contains(x, y) || m(x, y) == kOccupiedOccupancy;
        if (obstacle && overlaps_cell(fm, p, g.cell_center(x, y), 0.5 * g.resolution)) return true;
      }
  }
  return false;
}

TEST(DwaController, NeverChoosesAMotionThatTouchesAnObstacle) {
  Rng rng(5);
  int chosen = 0;
  for (int trial = 0; trial < test::scaled(30); ++trial) {
    const bool holonomic = trial % 2 == 0;
    const RobotConfig robot = holonomic ? mecanum() : differential();
    DwaConfig c;
    c.vx_samples = 7;
    c.vy_samples = 5;
    c.wz_samples = 7;
    c.min_vx_mps = -0.1;
    c.footprint = trial % 3 == 0 ? "circle" : "rectangle";
    c.safety_margin_m = 0.0;
    DwaController dwa(c, robot);
    OccupancyGrid m = random_map(rng, 6.0, 6.0, 0.0);
    for (int b = 0; b < 12; ++b) {
      const double x = rng.uniform(0.5, 5.5), y = rng.uniform(0.5, 5.5);
      fill_box(m, x, y, x + rng.uniform(0.05, 0.6), y + rng.uniform(0.05, 0.6));
    }
    const Pose2 start(3.0, 3.0, rng.uniform(-kPi, kPi));
    ClearanceWindow around;
    around.build(m, start.translation(), 1.0, 1.0);
    if (dwa.footprint().collides(around, start)) continue;  // the robot must start clear
    const Vec2 goal(rng.uniform(0.5, 5.5), rng.uniform(0.5, 5.5));
    const std::vector<Vec2> path{start.translation(), goal};
    dwa.set_path(path);
    ControlInput in;
    in.limits = velocity_limits_of(dwa.robot());
    in.pose = start;
    in.velocity = {rng.uniform(-0.05, 0.4), holonomic ? rng.uniform(-0.2, 0.2) : 0.0, rng.uniform(-0.8, 0.8)};
    in.local_map = &m;
    const ControlOutput out = dwa.compute(in);
    if (out.status == ControlStatus::Blocked) {
      EXPECT_EQ(out.twist.vx, 0.0);
      continue;
    }
    ASSERT_EQ(out.status, ControlStatus::Tracking);
    ++chosen;
    const double t_check = dwa_check_time(out.twist, dwa.limits(), c.sim_time_s, c.control_period_s, 0.0);
    EXPECT_FALSE(chosen_motion_touches(m, dwa.footprint().model(), start, out.twist, t_check))
        << "trial " << trial << " twist " << out.twist.vx << " " << out.twist.vy << " " << out.twist.wz;
  }
  EXPECT_GT(chosen, 10);
}

TEST(DwaController, TestingInOrderOfCostChoosesWhatTestingEverySampleChooses) {
  Rng rng(17);
  int blocked = 0;
  for (int trial = 0; trial < test::scaled(30); ++trial) {
    OccupancyGrid m = empty_map(6.0, 6.0);
    for (int b = 0; b < 15; ++b) {
      const double x = rng.uniform(0.5, 5.5), y = rng.uniform(0.5, 5.5);
      fill_box(m, x, y, x + rng.uniform(0.05, 0.8), y + rng.uniform(0.05, 0.8));
    }
    DwaConfig c;
    c.vx_samples = 9;
    c.vy_samples = 5;
    c.wz_samples = 9;
    c.min_vx_mps = -0.1;
    DwaController pruned(c, mecanum()), exhaustive(c, mecanum());
    exhaustive.keep_samples(true);
    const std::vector<Vec2> path{{3.0, 3.0}, {rng.uniform(0.5, 5.5), rng.uniform(0.5, 5.5)}};
    pruned.set_path(path);
    exhaustive.set_path(path);
    ControlInput in;
    in.limits = velocity_limits_of(mecanum());
    in.pose = Pose2(3.0, 3.0, rng.uniform(-kPi, kPi));
    in.velocity = {rng.uniform(0.0, 0.4), rng.uniform(-0.2, 0.2), rng.uniform(-0.8, 0.8)};
    in.local_map = &m;
    const ControlOutput a = pruned.compute(in), b = exhaustive.compute(in);
    EXPECT_EQ(a.status, b.status) << trial;
    EXPECT_EQ(a.twist.vx, b.twist.vx) << trial;
    EXPECT_EQ(a.twist.vy, b.twist.vy) << trial;
    EXPECT_EQ(a.twist.wz, b.twist.wz) << trial;
    blocked += b.status == ControlStatus::Blocked;
  }
  EXPECT_LT(blocked, test::scaled(30));
}

TEST(DwaController, SaysBlockedWhenItCannotStopInTime) {
  OccupancyGrid m = empty_map(4.0, 4.0);
  fill_box(m, 2.36, 1.0, 2.39, 3.0);  // cells centred 0.375 m ahead: 10 cm ahead of the body
  DwaConfig c;
  c.safety_margin_m = 0.0;
  DwaController dwa(c, mecanum());
  const std::vector<Vec2> path{{2.0, 2.0}, {3.5, 2.0}};
  dwa.set_path(path);
  dwa.keep_samples(true);
  ControlInput in;
  in.limits = velocity_limits_of(dwa.robot());
  in.pose = Pose2(2.0, 2.0, 0.0);
  in.local_map = &m;
  // At rest it may stand (or creep): something is valid.
  EXPECT_NE(dwa.compute(in).status, ControlStatus::Blocked);
  // At 0.5 m/s every velocity of the window needs more than the 6.5 cm left (less the cell's half
  // diagonal) to stop.
  in.velocity = {0.5, 0.0, 0.0};
  const ControlOutput out = dwa.compute(in);
  EXPECT_EQ(out.status, ControlStatus::Blocked);
  EXPECT_EQ(out.twist.vx, 0.0);
  EXPECT_EQ(out.twist.vy, 0.0);
  EXPECT_EQ(out.twist.wz, 0.0);
  EXPECT_EQ(dwa.last_step().chosen, -1);
  ASSERT_FALSE(dwa.last_step().samples.empty());
  for (const DwaSample& s : dwa.last_step().samples) EXPECT_FALSE(s.valid);
}

// --- Critics on hand-built cases ----------------------------------------------------------------

struct SceneFixture {
  OccupancyGrid grid = empty_map(6.0, 6.0);
  ClearanceWindow map;
  DwaScene scene;
  std::vector<Pose2> poses;

  void build(const Pose2& pose) {
    map.build(grid, pose.translation(), 2.0, 1.0);
    scene.map = &map;
    scene.pose = pose;
    scene.limits.max_vx = 0.5;
    scene.limits.max_vy = 0.3;
    scene.limits.max_wz = 1.0;
    scene.limits.max_speed_xy = 0.5;
    scene.limits.acc_yaw = 2.0;
    const Cell g = map.cell_of(scene.local_goal);
    map.wavefront(std::span<const Cell>(&g, 1), 0.0, scene.goal_distance);
  }
  DwaRollout rollout(const BodyTwist& t, double time = 1.0) {
    dwa_rollout(scene.pose, t, 0.05, static_cast<int>(std::lround(time / 0.05)), poses);
    return {t, poses};
  }
};

TEST(DwaCritics, PathDistAndPathAlignMeasureFromThePath) {
  SceneFixture f;
  f.scene.local_path = {{1.0, 3.0}, {5.0, 3.0}};
  f.scene.align_path = f.scene.local_path;
  f.scene.local_goal = {5.0, 3.0};
  f.build(Pose2(1.0, 3.0, 0.0));
  // 0.4 m/s sideways to the left for 1 s ends 0.4 m off the path; facing along it.
  const DwaRollout side = f.rollout({0.0, 0.4, 0.0});
  EXPECT_NEAR(PathDistCritic(1.0).score(f.scene, side), 0.4, 1e-9);
  f.scene.align_by_motion = false;
  EXPECT_NEAR(PathAlignCritic(1.0, 0.3).score(f.scene, side), 0.4, 1e-9);  // heading along the path
  f.scene.align_by_motion = true;
  EXPECT_NEAR(PathAlignCritic(1.0, 0.3).score(f.scene, side), 0.7, 1e-9);  // the motion points away
  // Straight along the path: nothing.
  EXPECT_NEAR(PathDistCritic(1.0).score(f.scene, f.rollout({0.4, 0.0, 0.0})), 0.0, 1e-12);
  // In the goal window only the heading counts.
  f.scene.in_goal_window = true;
  EXPECT_EQ(PathAlignCritic(1.0, 0.3).score(f.scene, side), 0.0);
  EXPECT_EQ(PathDistCritic(1.0).score(f.scene, side), 0.0);
}

TEST(DwaCritics, GoalDistGoesRoundWallsAndRejectsTheUnreachable) {
  SceneFixture f;
  fill_box(f.grid, 2.45, 1.5, 2.55, 4.5);  // a wall between the robot and the goal
  f.scene.local_goal = {3.0, 3.0};
  f.build(Pose2(1.5, 3.0, 0.0));
  const DwaRollout r = f.rollout({0.5, 0.0, 0.0});  // ends at (2.0, 3.0), 1 m from the goal in a line
  const double d = GoalDistCritic(1.0).score(f.scene, r);
  EXPECT_GT(d, 2.5);  // round the wall's end, 1.5 m away
  const double straight = GoalDistCritic(1.0).score(f.scene, f.rollout({0.0, 0.0, 0.0}));
  EXPECT_GT(straight, d);
  // Free space: at least the straight-line distance, at most that plus a cell's diagonal.
  SceneFixture open;
  open.scene.local_goal = {3.0, 3.0};
  open.build(Pose2(1.5, 2.6, 0.0));
  const DwaRollout o = open.rollout({0.5, 0.0, 0.0});
  const double line = (o.poses.back().translation() - open.scene.local_goal).norm();
  const double got = GoalDistCritic(1.0).score(open.scene, o);
  EXPECT_GE(got, line - 1e-12);
  EXPECT_LE(got, line + 0.05 * std::sqrt(2.0) + 1e-9);
  // Enclosed goal: unreachable ends are rejected.
  SceneFixture boxed;
  fill_box(boxed.grid, 3.5, 2.5, 4.5, 2.55);
  fill_box(boxed.grid, 3.5, 3.45, 4.5, 3.5);
  fill_box(boxed.grid, 3.5, 2.5, 3.55, 3.5);
  fill_box(boxed.grid, 4.45, 2.5, 4.5, 3.5);
  boxed.scene.local_goal = {4.0, 3.0};
  boxed.build(Pose2(2.0, 3.0, 0.0));
  EXPECT_EQ(GoalDistCritic(1.0).score(boxed.scene, boxed.rollout({0.3, 0.0, 0.0})), kInvalidTrajectory);
}

TEST(DwaCritics, GoalAlignMeasuresTheForwardPointToTheGoal) {
  SceneFixture f;
  f.scene.local_path = {{1.0, 3.0}, {5.0, 3.0}};
  f.scene.align_path = f.scene.local_path;
  f.scene.local_goal = {3.0, 3.0};
  f.build(Pose2(1.0, 3.0, 0.0));
  f.scene.distance_to_goal_m = 4.0;
  // 0.5 m/s for 1 s ends at (1.5, 3); the forward point 0.3 m ahead is 1.2 m from the goal (a
  // straight line through free cells: the wavefront less a cell diagonal, at least the line).
  const double d = GoalAlignCritic(1.0, 0.3).score(f.scene, f.rollout({0.5, 0.0, 0.0}));
  EXPECT_GE(d, 1.2 - 1e-9);
  EXPECT_LE(d, 1.2 + 0.05 * std::sqrt(2.0));
  // Near the goal it measures to the path carried on past it.
  f.scene.local_goal_is_goal = true;
  f.scene.align_goal = {3.3, 3.0};
  EXPECT_NEAR(GoalAlignCritic(1.0, 0.3).score(f.scene, f.rollout({0.5, 0.0, 0.0})), 1.5, 1e-9);
  // Within the forward distance of the goal, off.
  f.scene.distance_to_goal_m = 0.2;
  EXPECT_EQ(GoalAlignCritic(1.0, 0.3).score(f.scene, f.rollout({0.5, 0.0, 0.0})), 0.0);
}

TEST(DwaCritics, ObstacleIsTheWorstProximityCostAlongTheRollout) {
  SceneFixture f;
  f.scene.local_goal = {5.0, 3.0};
  f.build(Pose2(1.0, 3.0, 0.0));
  f.scene.obstacle_cost.assign(f.map.width() * f.map.height(), 0.0);
  const DwaRollout r = f.rollout({0.5, 0.0, 0.0});
  const Cell c = f.map.cell_of(r.poses[7].translation());
  f.scene.obstacle_cost[f.map.index(c.x, c.y)] = 0.6;
  EXPECT_DOUBLE_EQ(ObstacleCritic(1.0).score(f.scene, r), 0.6);
}

TEST(DwaCritics, VelocityTwirlingPreferForwardInClosedForm) {
  SceneFixture f;
  f.scene.local_goal = {5.0, 3.0};
  f.build(Pose2(1.0, 3.0, 0.0));
  EXPECT_NEAR(VelocityCritic(1.0).score(f.scene, f.rollout({0.3, 0.4, 0.0})), 0.0, 1e-12);
  EXPECT_NEAR(VelocityCritic(1.0).score(f.scene, f.rollout({0.2, 0.0, 0.0})), 0.6, 1e-12);
  EXPECT_NEAR(TwirlingCritic(1.0).score(f.scene, f.rollout({0.2, 0.0, -0.5})), 0.5, 1e-12);
  EXPECT_NEAR(PreferForwardCritic(1.0).score(f.scene, f.rollout({-0.1, 0.0, 0.0})), 0.2, 1e-12);
  EXPECT_EQ(PreferForwardCritic(1.0).score(f.scene, f.rollout({0.1, 0.0, 0.0})), 0.0);
}

TEST(DwaCritics, PathAngleIsTheHeadingErrorAtTheRolloutsEnd) {
  SceneFixture f;
  f.scene.local_goal = {5.0, 3.0};
  f.build(Pose2(1.0, 3.0, 0.2));
  EXPECT_EQ(PathAngleCritic(1.0).score(f.scene, f.rollout({0.2, 0.0, 0.1})), 0.0);  // no heading to aim at
  f.scene.path_heading = 1.0;
  // 0.2 + 0.1 rad/s x 1 s = 0.3: 0.7 short of the path's heading.
  EXPECT_NEAR(PathAngleCritic(1.0).score(f.scene, f.rollout({0.2, 0.0, 0.1})), 0.7, 1e-9);
  f.scene.path_heading = -3.0;  // across +-pi: the short way round
  EXPECT_NEAR(PathAngleCritic(1.0).score(f.scene, f.rollout({0.0, 0.0, 0.1})), 2.0 * kPi - 3.3, 1e-9);
  f.scene.in_goal_window = true;
  EXPECT_EQ(PathAngleCritic(1.0).score(f.scene, f.rollout({0.0, 0.0, -0.1})), 0.0);
}

TEST(DwaCritics, OscillationPenalisesASecondReversalUntilTheRobotMoves) {
  SceneFixture f;
  f.scene.local_goal = {5.0, 3.0};
  f.build(Pose2(1.0, 3.0, 0.0));
  OscillationCritic osc(1.0, 0.05, 0.2);
  osc.prepare(f.scene);
  osc.chosen(f.scene, {0.1, 0.0, 0.3});
  EXPECT_EQ(osc.score(f.scene, f.rollout({-0.1, 0.0, -0.3})), 0.0);  // the first reversal is free
  osc.chosen(f.scene, {-0.1, 0.0, 0.3});                            // vx reversed
  EXPECT_TRUE(osc.reversed()[0]);
  EXPECT_FALSE(osc.reversed()[2]);
  EXPECT_EQ(osc.score(f.scene, f.rollout({0.1, 0.0, 0.3})), 1.0);   // back again: penalised
  EXPECT_EQ(osc.score(f.scene, f.rollout({0.0, 0.0, 0.3})), 0.0);   // stopping is not a reversal
  EXPECT_EQ(osc.score(f.scene, f.rollout({-0.2, 0.0, -0.3})), 0.0); // wz has not reversed yet
  // Moving (not at rest), it stays until the robot has gone far enough.
  f.scene.velocity = {-0.1, 0.0, 0.3};
  f.scene.pose = Pose2(1.03, 3.0, 0.0);
  osc.prepare(f.scene);
  EXPECT_TRUE(osc.reversed()[0]);
  // After moving oscillation_reset_m the axis may reverse again.
  f.scene.pose = Pose2(1.06, 3.0, 0.0);
  osc.prepare(f.scene);
  EXPECT_FALSE(osc.reversed()[0]);
  EXPECT_EQ(osc.score(f.scene, f.rollout({0.1, 0.0, 0.3})), 0.0);
  // Coming to rest forgets the reversals too.
  osc.chosen(f.scene, {-0.1, 0.0, 0.3});
  osc.chosen(f.scene, {0.1, 0.0, 0.3});
  EXPECT_TRUE(osc.reversed()[0]);
  f.scene.velocity = {};
  osc.prepare(f.scene);
  EXPECT_FALSE(osc.reversed()[0]);
  EXPECT_EQ(osc.score(f.scene, f.rollout({-0.1, 0.0, 0.3})), 0.0);
}

TEST(DwaCritics, RotateToGoalScoresTheYawWhereTheTurnWouldStop) {
  SceneFixture f;
  f.scene.local_goal = {1.0, 3.0};
  f.build(Pose2(1.0, 3.0, 0.0));
  f.scene.goal_yaw = 0.5;
  f.scene.period_s = 0.05;
  EXPECT_EQ(RotateToGoalCritic(1.0).score(f.scene, f.rollout({0.0, 0.0, 0.8})), 0.0);  // not in the goal window
  f.scene.in_goal_window = true;
  // 0.8 rad/s: 0.04 rad in the period, 0.16 rad braking at 2 rad/s^2 -> stops at 0.2.
  EXPECT_NEAR(RotateToGoalCritic(1.0).score(f.scene, f.rollout({0.0, 0.0, 0.8})), 0.3, 1e-12);
  EXPECT_NEAR(RotateToGoalCritic(1.0).score(f.scene, f.rollout({0.0, 0.0, -0.4})), 0.5 + 0.02 + 0.04, 1e-12);
}

// --- Closed loop on an ideal robot ----------------------------------------------------------------

// The robot reaches the commanded twist within the acceleration limits and moves on the exact arc.
struct IdealRobot {
  Pose2 pose;
  BodyTwist v;
  void step(const BodyTwist& cmd, const DwaLimits& l, double dt) {
    const auto toward = [dt](double from, double to, double a) { return from + std::clamp(to - from, -a * dt, a * dt); };
    const BodyTwist next{toward(v.vx, cmd.vx, l.acc_x), toward(v.vy, cmd.vy, l.acc_y), toward(v.wz, cmd.wz, l.acc_yaw)};
    const BodyTwist mean{0.5 * (v.vx + next.vx), 0.5 * (v.vy + next.vy), 0.5 * (v.wz + next.wz)};
    pose = advance_on_arc(pose, mean.vx, mean.vy, mean.wz, dt);
    v = next;
  }
};

struct LoopResult {
  ControlStatus status = ControlStatus::Idle;
  std::vector<Pose2> poses;
  std::vector<BodyTwist> commands;
  bool touched = false;
};

LoopResult drive(DwaController& dwa, const OccupancyGrid& m, const Pose2& start, const std::vector<Vec2>& path,
                 std::optional<double> goal_yaw, double max_s, double yaw_tolerance = 0.05) {
  IdealRobot robot{start, {}};
  dwa.set_path(path);
  LoopResult r;
  const double dt = dwa.config().control_period_s;
  for (double t = 0.0; t < max_s; t += dt) {
    ControlInput in;
    in.limits = velocity_limits_of(dwa.robot());
    in.t_s = t;
    in.pose = robot.pose;
    in.velocity = robot.v;
    in.local_map = &m;
    in.goal = path.back();
    in.goal_yaw = goal_yaw;
    in.goal_yaw_tolerance_rad = yaw_tolerance;
    const ControlOutput out = dwa.compute(in);
    r.status = out.status;
    if (out.status == ControlStatus::Arrived || out.status == ControlStatus::Blocked) break;
    robot.step(out.twist, dwa.limits(), dt);
    if (std::getenv("DWA_TRACE"))
      std::printf("%.2f pose %.3f %.3f %.3f v %.3f %.3f %.3f cmd %.3f %.3f %.3f\n", t, robot.pose.x, robot.pose.y, robot.pose.yaw,
                  robot.v.vx, robot.v.vy, robot.v.wz, out.twist.vx, out.twist.vy, out.twist.wz);
    r.poses.push_back(robot.pose);
    r.commands.push_back(out.twist);
    r.touched = r.touched || chosen_motion_touches(m, dwa.footprint().model(), robot.pose, {}, 0.0);
  }
  return r;
}

TEST(DwaController, AMecanumRobotReachesAGoalToItsSideByTranslating) {
  const OccupancyGrid m = empty_map(6.0, 6.0);
  DwaController dwa(DwaConfig{}, mecanum());
  const Pose2 start(2.0, 1.5, kPi / 2.0);
  const Vec2 goal(0.5, 1.5);  // 1.5 m straight to its left
  const LoopResult r = drive(dwa, m, start, {start.translation(), goal}, start.yaw, 30.0);
  ASSERT_EQ(r.status, ControlStatus::Arrived);
  EXPECT_LE((r.poses.back().translation() - goal).norm(), 0.05);
  double max_vy = 0.0, max_turn = 0.0;
  for (const BodyTwist& c : r.commands) max_vy = std::max(max_vy, std::abs(c.vy));
  for (const Pose2& p : r.poses) max_turn = std::max(max_turn, std::abs(wrap_angle(p.yaw - start.yaw)));
  EXPECT_GT(max_vy, 0.1);
  EXPECT_LT(max_turn, deg_to_rad(10.0));
}

TEST(DwaController, ADifferentialRobotNeverCommandsSideways) {
  const OccupancyGrid m = empty_map(6.0, 6.0);
  DwaController dwa(DwaConfig{}, differential());
  const Pose2 start(1.0, 1.0, 0.0);
  const LoopResult r = drive(dwa, m, start, {start.translation(), {4.5, 4.0}}, std::nullopt, 60.0);
  ASSERT_EQ(r.status, ControlStatus::Arrived) << r.poses.back().x << " " << r.poses.back().y << " " << r.poses.back().yaw;
  for (const BodyTwist& c : r.commands) EXPECT_EQ(c.vy, 0.0);
}

TEST(DwaController, ArrivesWithTheGoalsHeading) {
  const OccupancyGrid m = empty_map(6.0, 6.0);
  DwaController dwa(DwaConfig{}, mecanum());
  const Pose2 start(1.0, 1.0, 0.0);
  const Vec2 goal(4.0, 3.0);
  const LoopResult r = drive(dwa, m, start, {start.translation(), goal}, 2.5, 60.0, deg_to_rad(2.0));
  ASSERT_EQ(r.status, ControlStatus::Arrived) << r.poses.back().x << " " << r.poses.back().y << " " << r.poses.back().yaw;
  EXPECT_LE((r.poses.back().translation() - goal).norm(), 2.0 * 0.05);
  EXPECT_LE(std::abs(wrap_angle(r.poses.back().yaw - 2.5)), deg_to_rad(2.0));
}

TEST(DwaController, PassesADoorwayWithoutTouchingOrOscillating) {
  OccupancyGrid m = empty_map(6.0, 4.0);
  fill_box(m, 2.95, 0.0, 3.05, 1.6);  // a wall at x = 3 with a 0.8 m door from y = 1.6 to 2.4
  fill_box(m, 2.95, 2.4, 3.05, 4.0);
  for (const bool holonomic : {true, false}) {
    DwaController dwa(DwaConfig{}, holonomic ? mecanum() : differential());
    const Pose2 start(1.0, 2.0, 0.0);
    const std::vector<Vec2> path{start.translation(), {3.0, 2.0}, {5.0, 2.0}};
    const LoopResult r = drive(dwa, m, start, path, std::nullopt, 60.0);
    EXPECT_EQ(r.status, ControlStatus::Arrived) << holonomic;
    EXPECT_FALSE(r.touched);
    // At most two sign changes of vx or wz in any 2 s window.
    const double dt = dwa.config().control_period_s;
    const std::size_t span = static_cast<std::size_t>(std::lround(2.0 / dt));
    for (std::size_t i = 0; i + 1 < r.commands.size(); ++i) {
      int changes = 0;
      int last_vx = 0, last_wz = 0;
      for (std::size_t k = i; k < std::min(r.commands.size(), i + span); ++k) {
        const int sx = r.commands[k].vx > 1e-3 ? 1 : (r.commands[k].vx < -1e-3 ? -1 : 0);
        const int sw = r.commands[k].wz > 1e-3 ? 1 : (r.commands[k].wz < -1e-3 ? -1 : 0);
        if (sx != 0 && last_vx != 0 && sx != last_vx) ++changes;
        if (sw != 0 && last_wz != 0 && sw != last_wz) ++changes;
        if (sx != 0) last_vx = sx;
        if (sw != 0) last_wz = sw;
      }
      ASSERT_LE(changes, 2) << "holonomic " << holonomic << " at " << i * dt << " s";
    }
  }
}

// --- The component --------------------------------------------------------------------------------

TEST(DwaController, IsFoundByNameWithItsParameters) {
  const LocalControllerDef& d = find_local_controller("dwa");
  const std::vector<ParamSetting> settings{{"vx_samples", "9", "s.yaml", 7, "navigation.dwa.vx_samples"}};
  const auto c = d.make({mecanum(), "s.yaml"}, settings);
  EXPECT_EQ(c->name(), "dwa");
  EXPECT_EQ(dynamic_cast<const DwaController&>(*c).config().vx_samples, 9);
  const std::vector<ParamSetting> bad{{"sim_step_s", "3.0", "s.yaml", 8, "navigation.dwa.sim_step_s"}};
  try {
    d.make({mecanum(), "s.yaml"}, bad);
    FAIL() << "accepted a step longer than the horizon";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sim_step_s"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("s.yaml"), std::string::npos) << e.what();
  }
  RobotConfig car;
  car.drive = DriveKind::Ackermann;
  EXPECT_THROW(d.make({car, ""}, {}), Error);

  // The window it rebuilds at every command is judged on the map's cells when it is made: window_m
  // (or, at 0, what its rollouts reach) padded by the footprint and inflation_radius_m.
  struct Row {
    std::vector<ParamSetting> settings;
    double resolution_m;
    std::string refused;  // the setting named; "": accepted
  };
  const std::vector<Row> rows = {
      {{{"window_m", "50", "s.yaml", 3, "navigation.dwa.window_m"}}, 0.005, "navigation.dwa.window_m"},
      {{{"inflation_radius_m", "10", "s.yaml", 4, "navigation.dwa.inflation_radius_m"}}, 0.005, "navigation.dwa.inflation_radius_m"},
      {{{"window_m", "50", "s.yaml", 3, "navigation.dwa.window_m"}}, 0.05, ""},
      {{{"inflation_radius_m", "10", "s.yaml", 4, "navigation.dwa.inflation_radius_m"}}, 0.05, ""},
      {{}, 0.005, ""},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE(std::to_string(r.resolution_m) + (r.settings.empty() ? std::string() : " " + r.settings[0].key));
    if (r.refused.empty()) {
      const auto made = d.make({mecanum(), "s.yaml", r.resolution_m}, r.settings);
      const auto w = dynamic_cast<const DwaController&>(*made).window_extent(r.resolution_m);
      EXPECT_LE(clearance_window_cells(w.half_m, w.pad_m, r.resolution_m), 4e6);
      continue;
    }
    const std::string what = test::error_of([&] { d.make({mecanum(), "s.yaml", r.resolution_m}, r.settings); });
    EXPECT_EQ(what.find("s.yaml:" + std::to_string(r.settings[0].line) + ": " + r.refused + ": "), 0u) << what;
    EXPECT_NE(what.find("more than 4000000"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace starnav
