// The MPPI controller (control/mppi_*.hpp): its rollouts against the closed-form arcs of constant
// twists, its limits against hand-stepped acceleration bounds and (Ackermann) the minimum radius
// on random samples, the softmax-weighted mean and the Savitzky-Golay smoothing against hand
// computations and the polynomials the filter keeps, every critic on hand-built trajectories
// against its formula, determinism from the seed, one error naming the field for bad parameters,
// and closed loops: an ideal robot to goals beside it and past a wall, and the DWA sideways
// scenario run with mppi in the simulator.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "starnav/control/mppi_controller.hpp"
#include "starnav/control/mppi_critics.hpp"
#include "starnav/control/mppi_optimizer.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/planar_motion.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/sim/scenario.hpp"
#include "support/box_world.hpp"
#include "support/ideal_robots.hpp"
#include "support/test_support.hpp"

namespace starnav {
// A named namespace: the unity build puts this file beside other tests with helpers of the same names.
namespace mppi_test {

using test::read_text;
using test::scenario_path;

using test::empty_map;
using test::fill_box;

// Distance from a point's cell centre to the nearest occupied cell centre, by brute force.
double brute_clearance(const OccupancyGrid& m, const Vec2& p) {
  const GridGeometry& g = m.geometry();
  const std::optional<Cell> at = g.world_to_cell(p);
  const Vec2 c = g.cell_center(at->x, at->y);
  double best = std::numeric_limits<double>::infinity();
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      if (m(x, y) == kOccupiedOccupancy) best = std::min(best, (g.cell_center(x, y) - c).norm());
  return best;
}

MppiControls constant_controls(int batch, int steps, double vx, double vy, double wz) {
  MppiControls c;
  c.resize(batch, steps);
  c.vx.setConstant(static_cast<float>(vx));
  c.vy.setConstant(static_cast<float>(vy));
  c.wz.setConstant(static_cast<float>(wz));
  return c;
}

// --- The motion models -------------------------------------------------------------------------

TEST(MppiRollout, ConstantTwistsFollowTheClosedFormArc) {
  const Pose2 start(1.0, -2.0, 0.7);
  const double dt = 0.05;
  for (const BodyTwist& v : {BodyTwist{0.4, 0.0, 0.8}, BodyTwist{0.3, -0.2, -1.5}, BodyTwist{-0.35, 0.0, 1.9}, BodyTwist{0.5, 0.3, 0.0}}) {
    const MppiControls c = constant_controls(3, 56, v.vx, v.vy, v.wz);
    MppiTrajectories t;
    mppi_integrate(start, dt, c, t);
    for (int k = 0; k < 56; ++k) {
      const Pose2 exact = advance_on_arc(start, v.vx, v.vy, v.wz, dt * (k + 1));
      for (int r = 0; r < 3; ++r) {
        EXPECT_NEAR(t.x(r, k), exact.x, 2e-5) << k;
        EXPECT_NEAR(t.y(r, k), exact.y, 2e-5) << k;
        EXPECT_NEAR(wrap_angle(t.yaw(r, k) - exact.yaw), 0.0, 1e-5) << k;
      }
    }
  }
}

TEST(MppiLimits, AccelerationIsBoundedStepByStepFromTheCurrentVelocity) {
  MppiLimits l;
  l.model = MppiMotionModel::Omni;
  l.vx_max = 0.5;
  l.vx_min = -0.35;
  l.vy_max = 0.3;
  l.wz_max = 1.0;
  l.ax_max = 1.0;   // 0.05 m/s per 0.05 s step rising
  l.ax_min = -2.0;  // 0.1 m/s per step falling
  l.ay_max = 1.0;
  l.ay_min = -1.0;
  l.az_max = 2.0;
  MppiControls c = constant_controls(1, 12, 0.9, -0.5, -3.0);
  c.vx(0, 8) = c.vx(0, 9) = c.vx(0, 10) = c.vx(0, 11) = -0.3;  // then a reversal
  mppi_apply_limits(l, BodyTwist{0.2, 0.0, 0.5}, 0.05, c);
  // vx rises 0.05 a step from 0.2 to the 0.5 cap, then falls 0.1 a step toward -0.3 (rising again
  // in magnitude once past zero: 0.05 a step).
  const double vx[12] = {0.25, 0.30, 0.35, 0.40, 0.45, 0.50, 0.50, 0.50, 0.40, 0.30, 0.20, 0.10};
  for (int k = 0; k < 12; ++k) EXPECT_NEAR(c.vx(0, k), vx[k], 1e-6) << k;
  // vy from 0 toward -0.5, 0.05 a step, capped at -0.3.
  for (int k = 0; k < 12; ++k) EXPECT_NEAR(c.vy(0, k), -std::min(0.05 * (k + 1), 0.3), 1e-6) << k;
  // wz from 0.5 falls 0.1 a step, at most to -1.0.
  for (int k = 0; k < 12; ++k) EXPECT_NEAR(c.wz(0, k), std::max(0.5 - 0.1 * (k + 1), -1.0), 1e-6) << k;
  // A differential robot never moves sideways.
  l.model = MppiMotionModel::DiffDrive;
  MppiControls d = constant_controls(2, 4, 0.1, 0.2, 0.0);
  mppi_apply_limits(l, {}, 0.05, d);
  EXPECT_EQ(d.vy.abs().maxCoeff(), 0.0f);
}

TEST(MppiLimits, AckermannSamplesNeverTurnTighterThanTheMinimumRadius) {
  MppiLimits l;
  l.model = MppiMotionModel::Ackermann;
  l.min_turning_r = 1.2;
  Rng rng(7);
  MppiControls c;
  c.resize(500, 40);
  for (Eigen::Index j = 0; j < 40; ++j)
    for (Eigen::Index i = 0; i < 500; ++i) {
      c.vx(i, j) = static_cast<float>(0.4 * rng.normal());
      c.wz(i, j) = static_cast<float>(1.5 * rng.normal());
    }
  mppi_apply_limits(l, BodyTwist{0.1, 0.0, 0.0}, 0.05, c);
  MppiTrajectories t;
  mppi_integrate(Pose2(0.0, 0.0, 0.3), 0.05, c, t);
  int turning = 0;
  for (Eigen::Index i = 0; i < 500; ++i)
    for (Eigen::Index j = 0; j < 40; ++j) {
      if (std::abs(c.wz(i, j)) < 1e-6f) {
        continue;
      }
      ++turning;
      ASSERT_GE(std::abs(c.vx(i, j) / c.wz(i, j)), 1.2 * (1.0 - 1e-6)) << i << " " << j;
      // The pose's path: the step's heading change over its chord is at most 1 / R.
      const double x0 = j ? t.x(i, j - 1) : 0.0, y0 = j ? t.y(i, j - 1) : 0.0, yaw0 = j ? t.yaw(i, j - 1) : 0.3;
      const double chord = std::hypot(t.x(i, j) - x0, t.y(i, j) - y0);
      if (chord > 1e-4) {
        ASSERT_LE(std::abs(t.yaw(i, j) - yaw0) / chord, 1.0 / 1.2 * (1.0 + 1e-3)) << i << " " << j;
      }
    }
  EXPECT_GT(turning, 10000);
}

TEST(MppiLimits, AckermannCurvatureSamplesKeepTheirSteeringWhateverTheSpeed) {
  MppiLimits l;
  l.model = MppiMotionModel::Ackermann;
  l.min_turning_r = 0.8;
  Rng rng(11);
  MppiControls c;
  c.resize(300, 30);
  c.curvature.resize(300, 30);
  for (Eigen::Index j = 0; j < 30; ++j)
    for (Eigen::Index i = 0; i < 300; ++i) {
      c.vx(i, j) = static_cast<float>(0.3 * rng.normal());
      c.curvature(i, j) = static_cast<float>(2.0 * rng.normal());
      c.wz(i, j) = 5.0f;  // overwritten: the curvature decides
    }
  const Eigen::ArrayXXf before = c.curvature;
  mppi_apply_limits(l, BodyTwist{0.0, 0.0, 0.0}, 0.05, c);
  int clipped = 0;
  for (Eigen::Index j = 0; j < 30; ++j)
    for (Eigen::Index i = 0; i < 300; ++i) {
      const float k = c.curvature(i, j);
      ASSERT_LE(std::abs(k), 1.0f / 0.8f + 1e-6f);
      // The curvature drawn, or its bound when beyond it; the yaw rate its speed times it, in
      // reverse and through zero alike.
      const float expect = std::clamp(before(i, j), -1.25f, 1.25f);
      ASSERT_EQ(k, expect);
      clipped += std::abs(before(i, j)) > 1.25f ? 1 : 0;
      ASSERT_EQ(c.wz(i, j), c.vx(i, j) * k);
      ASSERT_LE(std::abs(c.wz(i, j)), std::abs(c.vx(i, j)) / 0.8f * (1.0f + 1e-6f));
    }
  EXPECT_GT(clipped, 1000);
  // The weighted mean averages the curvature as the other axes (two samples, weights 0.25, 0.75).
  MppiControls two;
  two.resize(2, 1);
  two.curvature.resize(2, 1);
  two.curvature << 1.0f, -0.6f;
  Eigen::ArrayXf w(2);
  w << 0.25f, 0.75f;
  MppiSequence m;
  mppi_weighted_mean(two, w, m);
  EXPECT_NEAR(m.curvature(0), 0.25 * 1.0 - 0.75 * 0.6, 1e-6);
}

// --- The update ------------------------------------------------------------------------------------

TEST(MppiUpdate, SoftmaxWeightedMeanMatchesAHandComputation) {
  // Three samples of two steps, costs 1, 2 and 4 at temperature 0.5:
  // w ~ (1, e^-2, e^-6) / (1 + e^-2 + e^-6) = (0.8788799, 0.1189437, 0.0021764).
  Eigen::ArrayXf costs(3);
  costs << 1.0f, 2.0f, 4.0f;
  Eigen::ArrayXf w;
  mppi_softmax_weights(costs, 0.5, w);
  const double sum = 1.0 + std::exp(-2.0) + std::exp(-6.0);
  EXPECT_NEAR(w(0), 1.0 / sum, 1e-6);
  EXPECT_NEAR(w(1), std::exp(-2.0) / sum, 1e-6);
  EXPECT_NEAR(w(2), std::exp(-6.0) / sum, 1e-6);
  MppiControls c;
  c.resize(3, 2);
  c.vx << 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f;  // rows: samples
  c.wz << 1.0f, -1.0f, 0.0f, 2.0f, 0.5f, 0.5f;
  MppiSequence m;
  mppi_weighted_mean(c, w, m);
  const double w0 = 1.0 / sum, w1 = std::exp(-2.0) / sum, w2 = std::exp(-6.0) / sum;
  EXPECT_NEAR(m.vx(0), 0.1 * w0 + 0.3 * w1 + 0.5 * w2, 1e-6);
  EXPECT_NEAR(m.vx(1), 0.2 * w0 + 0.4 * w1 + 0.6 * w2, 1e-6);
  EXPECT_NEAR(m.wz(0), 1.0 * w0 + 0.0 * w1 + 0.5 * w2, 1e-6);
  EXPECT_NEAR(m.wz(1), -1.0 * w0 + 2.0 * w1 + 0.5 * w2, 1e-6);
  EXPECT_NEAR(m.vy(0), 0.0, 1e-9);
  // Huge costs do not overflow: only differences count.
  Eigen::ArrayXf big(3);
  big << 1e30f, 1e30f, 2e30f;
  mppi_softmax_weights(big, 0.3, w);
  EXPECT_NEAR(w(0), 0.5, 1e-6);
  EXPECT_NEAR(w(2), 0.0, 1e-6);
}

TEST(MppiUpdate, SavitzkyGolayKeepsCubicsAndSmoothsNoise) {
  // A cubic continued into the history is reproduced exactly wherever the window holds it.
  const auto f = [](double i) { return 0.3 + 0.02 * i - 0.001 * i * i + 0.00005 * i * i * i; };
  Eigen::ArrayXf s(30);
  for (int i = 0; i < 30; ++i) s(i) = static_cast<float>(f(i));
  const std::array<float, 4> history = {static_cast<float>(f(-4)), static_cast<float>(f(-3)), static_cast<float>(f(-2)), static_cast<float>(f(-1))};
  Eigen::ArrayXf out = s;
  mppi_savitzky_golay(out, history);
  for (int i = 0; i + 5 < 30; ++i) EXPECT_NEAR(out(i), f(i), 1e-5) << i;
  // Near the end the last value is repeated past it; the last stays.
  EXPECT_EQ(out(29), s(29));
  // Alternating noise on a constant is damped to 1/231 of... the filter's response at Nyquist,
  // |sum (-1)^k c_k| / 231 = 59/231... computed here from the coefficients themselves.
  Eigen::ArrayXf zig(30);
  for (int i = 0; i < 30; ++i) zig(i) = (i % 2 ? -1.0f : 1.0f);
  mppi_savitzky_golay(zig, {1.0f, -1.0f, 1.0f, -1.0f});
  const double nyquist = std::abs(-21.0 - 14.0 + 39.0 - 54.0 + 59.0 - 54.0 + 39.0 - 14.0 - 21.0) / 231.0;
  for (int i = 0; i + 5 < 30; ++i) EXPECT_NEAR(std::abs(zig(i)), nyquist, 1e-6) << i;
  // Short sequences are left alone.
  Eigen::ArrayXf short_seq = Eigen::ArrayXf::LinSpaced(10, 0.0f, 1.0f);
  const Eigen::ArrayXf before = short_seq;
  mppi_savitzky_golay(short_seq, {5.0f, 5.0f, 5.0f, 5.0f});
  EXPECT_TRUE((short_seq == before).all());
}

// --- The critics -------------------------------------------------------------------------------------

// A scene of hand-built trajectories: every sample's poses and velocities given.
struct Batch {
  MppiControls controls;
  MppiTrajectories t;
  MppiScene scene;
  Batch(int n, int steps) {
    controls.resize(n, steps);
    t.x.setZero(n, steps);
    t.y.setZero(n, steps);
    t.yaw.setZero(n, steps);
    scene.controls = &controls;
    scene.trajectories = &t;
    scene.model_dt_s = 0.05;
  }
  // Sample r moves along a straight line from `from` by `step` each step with yaw `yaw`.
  void line(int r, const Vec2& from, const Vec2& step, double yaw) {
    for (Eigen::Index k = 0; k < t.x.cols(); ++k) {
      t.x(r, k) = static_cast<float>(from.x() + step.x() * (k + 1));
      t.y(r, k) = static_cast<float>(from.y() + step.y() * (k + 1));
      t.yaw(r, k) = static_cast<float>(yaw);
    }
  }
  Eigen::ArrayXf score(const MppiCritic& c) {
    MppiCosts costs;
    costs.total.setZero(t.x.rows());
    c.score(scene, costs);
    return costs.total;
  }
};

void straight_path(MppiScene& s, double x0, double x1, double step = 0.05) {
  s.path.clear();
  for (double x = x0; x <= x1 + 1e-9; x += step) s.path.emplace_back(x, 0.0);
  s.path_free.assign(s.path.size(), 1);
  s.goal = s.path.back();
}

TEST(MppiCritics, GoalAndGoalAngleAreWeightedMeansToThePower) {
  Batch b(2, 10);
  b.scene.pose = Pose2(0.0, 0.0, 0.0);
  b.scene.goal = Vec2(1.0, 0.0);
  b.scene.goal_yaw = 0.5;
  b.line(0, {0.0, 0.0}, {0.1, 0.0}, 0.0);  // distances 0.9, 0.8, ..., 0.0: mean 0.45
  b.line(1, {0.0, 0.3}, {0.0, 0.0}, 1.5);  // always hypot(1, 0.3) away
  const Eigen::ArrayXf g = b.score(MppiGoalCritic(5.0, 1, 1.4));
  EXPECT_NEAR(g(0), 5.0 * 0.45, 1e-5);
  EXPECT_NEAR(g(1), 5.0 * std::hypot(1.0, 0.3), 1e-5);
  const Eigen::ArrayXf g2 = b.score(MppiGoalCritic(5.0, 2, 1.4));
  EXPECT_NEAR(g2(0), std::pow(5.0 * 0.45, 2), 1e-4);
  // Beyond the threshold it says nothing.
  EXPECT_EQ(b.score(MppiGoalCritic(5.0, 1, 0.9)).abs().maxCoeff(), 0.0f);
  b.scene.pose = Pose2(0.8, 0.0, 0.0);
  const Eigen::ArrayXf a = b.score(MppiGoalAngleCritic(3.0, 1, 0.5));
  EXPECT_NEAR(a(0), 3.0 * 0.5, 1e-5);
  EXPECT_NEAR(a(1), 3.0 * 1.0, 1e-5);
  b.scene.goal_yaw.reset();
  EXPECT_EQ(b.score(MppiGoalAngleCritic(3.0, 1, 0.5)).abs().maxCoeff(), 0.0f);
}

TEST(MppiCritics, PathFollowPathAlignAndPathAngleMeasureFromThePath) {
  Batch b(3, 20);
  b.scene.pose = Pose2(0.0, 0.0, 0.0);
  straight_path(b.scene, 0.0, 3.0);  // points every 5 cm along y = 0
  b.line(0, {0.0, 0.0}, {0.05, 0.0}, 0.0);   // on the path, to x = 1.0
  b.line(1, {0.0, 0.2}, {0.05, 0.0}, 0.0);   // parallel, 0.2 m off
  b.line(2, {0.0, 0.0}, {0.0, 0.02}, 1.57);  // sideways off it
  // The furthest point reached: index 20 (x = 1.0) by sample 0 and 1 alike.
  EXPECT_EQ(b.scene.furthest_reached(), 20u);
  // Follow: distance from the last pose to path point 20 + 6 (x = 1.3).
  const Eigen::ArrayXf f = b.score(MppiPathFollowCritic(5.0, 1, 1.4, 6));
  EXPECT_NEAR(f(0), 5.0 * 0.3, 1e-5);
  EXPECT_NEAR(f(1), 5.0 * std::hypot(0.3, 0.2), 1e-5);
  EXPECT_NEAR(f(2), 5.0 * std::hypot(1.3, 0.4), 1e-5);
  // Align (every 4th pose): the on-path sample costs 0, the parallel one 0.2 at every pose (its
  // first chord from the robot's pose, 0.2 m aside, is longer: hypot(0.2, 0.2) for 0.2 along).
  MppiPathAlignOptions o;
  o.offset_from_furthest = 20;
  const Eigen::ArrayXf al = b.score(MppiPathAlignCritic(10.0, 1, o));
  EXPECT_NEAR(al(0), 0.0, 1e-5);
  {
    // Poses 4, 8, 12, 16, 20 (x = 0.2 k): travelled 0.2 sqrt(2), then 0.2 more each: the path
    // points nearest those lengths along the path (every 5 cm), up to the furthest reached.
    double sum = 0.0, travelled = 0.0, px = 0.0, py = 0.0;
    for (int p = 3; p < 20; p += 4) {
      const double x = 0.05 * (p + 1), y = 0.2;
      travelled += std::hypot(x - px, y - py);
      px = x, py = y;
      const double along = std::min(std::round(travelled / 0.05) * 0.05, 1.0);  // up to the furthest reached
      sum += std::hypot(along - x, y);
    }
    EXPECT_NEAR(al(1), 10.0 * sum / 5.0, 1e-4);
  }
  // Not before the batch reaches offset_from_furthest points, nor with the path blocked.
  o.offset_from_furthest = 21;
  EXPECT_EQ(b.score(MppiPathAlignCritic(10.0, 1, o)).abs().maxCoeff(), 0.0f);
  o.offset_from_furthest = 20;
  for (int i = 5; i < 9; ++i) b.scene.path_free[static_cast<std::size_t>(i)] = 0;  // 4 of 20 blocked > 7 %
  EXPECT_EQ(b.score(MppiPathAlignCritic(10.0, 1, o)).abs().maxCoeff(), 0.0f);
  b.scene.path_free.assign(b.scene.path.size(), 1);
  // Angle: off while the robot faces within 45 degrees of the point ahead.
  EXPECT_EQ(b.score(MppiPathAngleCritic(2.2, 1, 0.5, 20, kPi / 4.0, 0)).abs().maxCoeff(), 0.0f);
  b.scene.pose = Pose2(0.0, 0.0, kPi);  // facing away: mean |yaw - bearing to point 40 (x = 2.0)|
  const Eigen::ArrayXf an = b.score(MppiPathAngleCritic(2.2, 1, 0.5, 20, kPi / 4.0, 0));
  double expect2 = 0.0;
  for (int k = 0; k < 20; ++k) expect2 += std::abs(wrap_angle(1.57 - std::atan2(-0.02 * (k + 1), 2.0)));
  EXPECT_NEAR(an(0), 0.0, 1e-5);  // heading along the path to a point straight ahead
  EXPECT_NEAR(an(2), 2.2 * expect2 / 20.0, 1e-4);
  // Mode 1 takes the reverse direction as well: facing away costs nothing more there.
  EXPECT_EQ(b.score(MppiPathAngleCritic(2.2, 1, 0.5, 20, kPi / 4.0, 1)).abs().maxCoeff(), 0.0f);
  // Near the goal they all give way to the goal critics.
  b.scene.pose = Pose2(2.8, 0.0, kPi);
  EXPECT_EQ(b.score(MppiPathFollowCritic(5.0, 1, 1.4, 6)).abs().maxCoeff(), 0.0f);
  EXPECT_EQ(b.score(MppiPathAlignCritic(10.0, 1, o)).abs().maxCoeff(), 0.0f);
  // On a stretch of a path of poses the switch is the length of the stretch left, and
  // path_align needs the batch to reach at most the stretch's last point: the same robot 0.2 m
  // from the goal with 2 m of a winding stretch left still follows it.
  b.scene.path_left_m = 2.0;
  EXPECT_GT(b.score(MppiPathFollowCritic(5.0, 1, 1.4, 6)).abs().maxCoeff(), 0.0f);
  b.scene.pose = Pose2(0.0, 0.0, 0.0);
  b.scene.path.resize(11);  // a stretch of 0.5 m: 11 points, the batch reaches past its end
  b.scene.path_free.assign(b.scene.path.size(), 1);
  b.scene.furthest_cache.reset();
  b.scene.path_left_m.reset();
  EXPECT_EQ(b.score(MppiPathAlignCritic(10.0, 1, o)).abs().maxCoeff(), 0.0f);  // 20 points never reached
  b.scene.path_left_m = 0.6;
  EXPECT_GT(b.score(MppiPathAlignCritic(10.0, 1, o)).abs().maxCoeff(), 0.0f);
}

TEST(MppiCritics, ConstraintPreferForwardAndTwirlingInClosedForm) {
  Batch b(3, 10);
  b.scene.pose = Pose2(0.0, 0.0, 0.0);
  b.scene.goal = Vec2(5.0, 0.0);
  b.scene.limits.model = MppiMotionModel::DiffDrive;
  b.scene.limits.vx_max = 0.5;
  b.scene.limits.vx_min = -0.35;
  b.controls.vx.row(0).setConstant(0.6f);   // 0.1 over
  b.controls.vx.row(1).setConstant(-0.2f);  // reverse, within
  b.controls.vx.row(2).setConstant(-0.45f); // 0.1 under
  b.controls.wz.row(1).setConstant(-0.8f);
  const Eigen::ArrayXf c = b.score(MppiConstraintCritic(4.0, 1));
  EXPECT_NEAR(c(0), 4.0 * 0.1 * 0.05 * 10, 1e-5);
  EXPECT_NEAR(c(1), 0.0, 1e-6);
  EXPECT_NEAR(c(2), 4.0 * 0.1 * 0.05 * 10, 1e-5);
  const Eigen::ArrayXf f = b.score(MppiPreferForwardCritic(5.0, 1, 0.5));
  EXPECT_NEAR(f(0), 0.0, 1e-6);
  EXPECT_NEAR(f(1), 5.0 * 0.2 * 0.05 * 10, 1e-5);
  const Eigen::ArrayXf t = b.score(MppiTwirlingCritic(10.0, 1));
  EXPECT_NEAR(t(1), 10.0 * 0.8, 1e-5);
  EXPECT_NEAR(t(0), 0.0, 1e-6);
  // Ackermann: the radius below R_min counts too (vx 0.3, wz 0.6: radius 0.5 under R_min 1.0).
  b.scene.limits.model = MppiMotionModel::Ackermann;
  b.scene.limits.min_turning_r = 1.0;
  b.controls.vx.row(0).setConstant(0.3f);
  b.controls.wz.row(0).setConstant(0.6f);
  EXPECT_NEAR(b.score(MppiConstraintCritic(4.0, 1))(0), 4.0 * 0.5 * 0.05 * 10, 1e-5);
}

TEST(MppiCritics, OnAReverseStretchPreferForwardAndPathAnglePreferReverse) {
  Batch b(2, 10);
  b.scene.pose = Pose2(0.0, 0.0, 0.0);
  b.scene.goal = Vec2(-5.0, 0.0);
  b.controls.vx.row(0).setConstant(0.3f);   // forward
  b.controls.vx.row(1).setConstant(-0.2f);  // reverse
  b.scene.reversing = true;
  const Eigen::ArrayXf f = b.score(MppiPreferForwardCritic(5.0, 1, 0.5));
  EXPECT_NEAR(f(0), 5.0 * 0.3 * 0.05 * 10, 1e-5);  // now the forward motion pays
  EXPECT_NEAR(f(1), 0.0, 1e-6);
  // The path runs behind the robot (toward -x): reversing along it faces away from it, so the
  // heading error is to the bearing turned by pi.
  b.scene.path.clear();
  for (int i = 0; i <= 60; ++i) b.scene.path.emplace_back(-0.05 * i, 0.0);
  b.scene.path_free.assign(b.scene.path.size(), 1);
  b.line(0, {0.0, 0.0}, {-0.05, 0.0}, 0.0);    // backing along the path, facing +x
  b.line(1, {0.0, 0.0}, {-0.05, 0.0}, 0.6);    // the same, turned 0.6 rad
  const MppiPathAngleCritic angle(2.2, 1, 0.5, 20, kPi / 4.0, 0);
  EXPECT_EQ(b.score(angle).abs().maxCoeff(), 0.0f);  // facing +x is right: the critic is off
  b.scene.pose = Pose2(0.0, 0.0, 1.2);  // beyond 45 degrees: on
  const Eigen::ArrayXf a = b.score(angle);
  EXPECT_NEAR(a(0), 0.0, 1e-5);
  EXPECT_NEAR(a(1), 2.2 * 0.6, 1e-4);
  // The same path driven forward would want the opposite heading.
  b.scene.reversing = false;
  const Eigen::ArrayXf fwd = b.score(angle);
  EXPECT_NEAR(fwd(0), 2.2 * kPi, 1e-4);
}

TEST(MppiCritics, ObstaclesCostCollisionsCriticalGapsAndRepulsionExactly) {
  OccupancyGrid m = empty_map(4.0, 4.0);
  fill_box(m, 2.0, 0.0, 2.2, 4.0);  // a wall at x in [2.0, 2.2]
  ClearanceWindow window;
  window.build(m, Vec2(1.0, 2.0), 1.5, 1.0);
  FootprintModel fm;
  fm.circle = false;
  fm.half_length_m = 0.275;
  fm.half_width_m = 0.25;
  const FootprintChecker checker(fm, 0.0);
  Batch b(3, 8);
  b.scene.pose = Pose2(0.5, 2.0, 0.0);
  b.scene.goal = Vec2(0.5, 3.8);
  b.scene.map = &window;
  b.scene.prepare_map();
  b.scene.footprint = &checker;
  b.scene.inscribed_radius_m = fm.inscribed_radius_m();
  b.scene.circumscribed_radius_m = fm.bounding_radius_m();
  b.line(0, {0.5, 2.0}, {0.2, 0.0}, 0.0);   // into the wall
  b.line(1, {0.5, 1.0}, {0.0, 0.05}, 0.0);  // far from it: x = 0.5, 1.5 m away
  b.line(2, {1.6, 1.0}, {0.0, 0.05}, 0.0);  // along it, x = 1.6 (0.4 m between cell centres)
  MppiObstaclesOptions o;  // Nav2's defaults
  const MppiObstaclesCritic critic(o);
  const Eigen::ArrayXf c = b.score(critic);
  // The expected costs from brute-force clearances.
  const auto expected = [&](int r) {
    double critical = 0.0, repulsive = 0.0;
    for (int k = 0; k < 8; ++k) {
      const Vec2 p(b.t.x(r, k), b.t.y(r, k));
      const double d = brute_clearance(m, p);
      if (d < fm.inscribed_radius_m()) return o.critical_weight * o.collision_cost + o.repulsion_weight * repulsive / 8.0;
      if (d - fm.inscribed_radius_m() < o.collision_margin_distance_m) critical += o.collision_margin_distance_m - (d - fm.inscribed_radius_m());
      if (d < o.inflation_radius_m) repulsive += o.inflation_radius_m - d;
    }
    return o.critical_weight * critical + o.repulsion_weight * repulsive / 8.0;
  };
  EXPECT_GE(c(0), o.critical_weight * o.collision_cost);
  EXPECT_NEAR(c(0), expected(0), 1.0);  // 2e6 in single precision
  EXPECT_NEAR(c(1), 0.0, 1e-6);
  EXPECT_GT(c(2), 0.0);
  EXPECT_NEAR(c(2), expected(2), 1e-4);
  // The critical term: x = 1.6 lies 0.4 m from the wall (cell centres 1.625 and 2.025), a gap of
  // 0.15 m beyond the inscribed radius: with a 0.35 m margin it counts (margin - gap) at each of
  // the 8 poses.
  MppiObstaclesOptions wide = o;
  wide.collision_margin_distance_m = 0.35;
  const double d2 = brute_clearance(m, {1.6, 1.5});
  EXPECT_NEAR(d2, 0.4, 1e-9);
  const double gap = d2 - fm.inscribed_radius_m();
  ASSERT_LT(gap, 0.35);
  EXPECT_NEAR(b.score(MppiObstaclesCritic(wide))(2), wide.critical_weight * 8 * (0.35 - gap) + wide.repulsion_weight * (0.55 - d2), 1e-3);
  // Power 2 squares the whole term.
  MppiObstaclesOptions squared = o;
  squared.power = 2;
  EXPECT_NEAR(b.score(MppiObstaclesCritic(squared))(2), std::pow(expected(2), 2), 1e-4);
  // Every sample colliding fails the batch.
  MppiCosts costs;
  costs.total.setZero(3);
  critic.score(b.scene, costs);
  EXPECT_FALSE(costs.failed);
  b.line(1, {1.9, 2.0}, {0.0, 0.0}, 0.0);
  b.line(2, {1.95, 2.0}, {0.0, 0.0}, 0.0);
  costs.total.setZero(3);
  critic.score(b.scene, costs);
  EXPECT_TRUE(costs.failed);
  // The footprint: its long side reaches the wall where the inscribed circle does not.
  Batch f(1, 1);
  f.scene = b.scene;
  f.scene.controls = &f.controls;
  f.scene.trajectories = &f.t;
  f.t.x(0, 0) = 1.74f;  // clearance 0.3 m (cell centres 1.725, 2.025) over r_in 0.25; facing the wall, its nose at 2.015
  f.t.y(0, 0) = 2.0f;
  MppiObstaclesOptions foot = o;
  EXPECT_LT(f.score(MppiObstaclesCritic(foot))(0), o.collision_cost);
  foot.consider_footprint = true;
  EXPECT_GE(f.score(MppiObstaclesCritic(foot))(0), o.critical_weight * o.collision_cost);
}

// --- The controller ----------------------------------------------------------------------------------

using test::differential;
using test::mecanum;

ParamSetting set(const std::string& key, const std::string& value) { return {key, value, "test.yaml", 3, "navigation.mppi." + key}; }

std::unique_ptr<LocalController> mppi(const RobotConfig& robot, std::vector<ParamSetting> settings = {}, std::uint64_t seed = 1) {
  return find_local_controller("mppi").make(LocalControllerContext{robot, "test.yaml", 0.05, seed}, settings);
}

ControlInput input_at(const Pose2& pose, const BodyTwist& v, const OccupancyGrid& m, const Vec2& goal, const RobotConfig& robot) {
  ControlInput in;
  in.pose = pose;
  in.velocity = v;
  in.local_map = &m;
  in.limits = velocity_limits_of(robot);
  in.goal = goal;
  in.goal_tolerance_m = 0.05;
  in.goal_yaw_tolerance_rad = deg_to_rad(3.0);
  return in;
}

TEST(MppiController, SameSeedSameCommandsAnotherSeedOthers) {
  const OccupancyGrid m = empty_map(6.0, 6.0);
  const auto commands = [&](std::uint64_t seed) {
    auto c = mppi(mecanum(), {set("batch_size", "300")}, seed);
    c->set_path(std::vector<Vec2>{{1.0, 1.0}, {4.0, 3.0}});
    std::vector<BodyTwist> out;
    for (int k = 0; k < 5; ++k) out.push_back(c->compute(input_at(Pose2(1.0 + 0.01 * k, 1.0, 0.0), {}, m, {4.0, 3.0}, mecanum())).twist);
    return out;
  };
  const auto a = commands(1), b = commands(1), c = commands(2);
  bool differs = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].vx, b[k].vx);
    EXPECT_EQ(a[k].vy, b[k].vy);
    EXPECT_EQ(a[k].wz, b[k].wz);
    differs = differs || a[k].vx != c[k].vx || a[k].wz != c[k].wz;
  }
  EXPECT_TRUE(differs);
}

TEST(MppiController, AckermannNoiseIsCorrelatedInTimeWithItsStandardDeviation) {
  // From rest the samples are the noise itself (rotated in time): per step a standard deviation of
  // curvature_std_per_m and speed std, and from one step to the next the correlation
  // exp(-model_dt / noise_correlation_time) of a first-order low-pass.
  const OccupancyGrid m = empty_map(6.0, 6.0);
  RobotConfig car = mecanum();
  car.drive = DriveKind::Ackermann;
  MppiConfig config;
  config.curvature_std_per_m = 0.2;  // far inside 1 / R_min (1.37): no clipping
  config.vx_std_mps = 0.05;
  config.vx_min_mps = -0.5;
  config.ax_max_mps2 = 100.0, config.ax_min_mps2 = -100.0;  // no acceleration limit on the noise
  MppiController c(config, car, 5);
  c.set_path(std::vector<Vec2>{{1.0, 1.0}, {4.0, 1.0}});
  c.compute(input_at(Pose2(1.0, 1.0, 0.0), {}, m, {4.0, 1.0}, car));
  const auto stats = [](const Eigen::ArrayXXf& a) {
    std::vector<double> sd, corr;
    for (Eigen::Index j = 0; j + 1 < a.cols(); ++j) {
      const Eigen::ArrayXf x = a.col(j) - a.col(j).mean(), y = a.col(j + 1) - a.col(j + 1).mean();
      sd.push_back(std::sqrt(x.square().mean()));
      corr.push_back((x * y).sum() / std::sqrt(x.square().sum() * y.square().sum()));
    }
    std::sort(sd.begin(), sd.end());
    std::sort(corr.begin(), corr.end());
    return std::pair{sd[sd.size() / 2], corr[corr.size() / 2]};  // medians (one pair wraps round)
  };
  const double rho = std::exp(-0.05 / 0.5);
  const auto [k_sd, k_corr] = stats(c.samples().curvature);
  EXPECT_NEAR(k_sd, 0.2, 0.2 * 0.06);  // 2,000 samples: the sd's own error about 1.6 %
  EXPECT_NEAR(k_corr, rho, 0.02);
  const auto [v_sd, v_corr] = stats(c.samples().vx);
  EXPECT_NEAR(v_sd, 0.05, 0.05 * 0.06);
  EXPECT_NEAR(v_corr, rho, 0.02);
  // White noise (time constant 0), as Nav2's: no correlation.
  config.noise_correlation_time_s = 0.0;
  MppiController white(config, car, 5);
  white.set_path(std::vector<Vec2>{{1.0, 1.0}, {4.0, 1.0}});
  white.compute(input_at(Pose2(1.0, 1.0, 0.0), {}, m, {4.0, 1.0}, car));
  EXPECT_NEAR(stats(white.samples().curvature).second, 0.0, 0.1);
}

TEST(MppiController, BadParametersGiveOneErrorNamingTheField) {
  const auto field_of = [](const RobotConfig& robot, std::vector<ParamSetting> s) {
    try {
      mppi(robot, std::move(s));
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      return e.field();
    }
    return std::string("no error");
  };
  EXPECT_EQ(field_of(mecanum(), {set("batch_size", "0")}), "navigation.mppi.batch_size");
  EXPECT_EQ(field_of(mecanum(), {set("temperature", "-1")}), "navigation.mppi.temperature");
  EXPECT_EQ(field_of(mecanum(), {set("critics", "[goal, nonsense]")}), "navigation.mppi.critics");
  EXPECT_EQ(field_of(mecanum(), {set("goal.cost_power", "0")}), "navigation.mppi.goal.cost_power");
  EXPECT_EQ(field_of(mecanum(), {set("vx_min_mps", "0.1")}), "navigation.mppi.vx_min_mps");
  EXPECT_EQ(field_of(differential(), {set("motion_model", "omni")}), "navigation.mppi.motion_model");
  RobotConfig car = mecanum();
  car.drive = DriveKind::Ackermann;
  EXPECT_EQ(field_of(car, {set("motion_model", "diff_drive")}), "navigation.mppi.motion_model");
  EXPECT_EQ(field_of(car, {set("ackermann_constraints.min_turning_r_m", "0.1")}), "navigation.mppi.ackermann_constraints.min_turning_r_m");
  EXPECT_EQ(field_of(car, {}), "no error");
}

// The ideal robot: it reaches the command within the controller's acceleration limits and moves on
// the exact arc.
struct LoopResult {
  ControlStatus status = ControlStatus::Idle;
  Pose2 pose;
  std::vector<BodyTwist> commands;
  double min_clearance_m = std::numeric_limits<double>::infinity();
};

LoopResult drive(MppiController& c, const OccupancyGrid& m, const RobotConfig& robot, const Pose2& start, const std::vector<Vec2>& path,
                 std::optional<double> goal_yaw, double max_s) {
  Pose2 pose = start;
  BodyTwist v;
  c.set_path(path);
  LoopResult r;
  const double dt = c.control_period_s();
  const MppiLimits& l = c.limits();
  for (double t = 0.0; t < max_s; t += dt) {
    ControlInput in = input_at(pose, v, m, path.back(), robot);
    in.t_s = t;
    in.goal_yaw = goal_yaw;
    const ControlOutput out = c.compute(in);
    r.status = out.status;
    if (out.status == ControlStatus::Arrived || out.status == ControlStatus::Blocked) break;
    const auto toward = [dt](double from, double to, double a) { return from + std::clamp(to - from, -a * dt, a * dt); };
    const BodyTwist next{toward(v.vx, out.twist.vx, l.ax_max), toward(v.vy, out.twist.vy, l.ay_max), toward(v.wz, out.twist.wz, l.az_max)};
    pose = advance_on_arc(pose, 0.5 * (v.vx + next.vx), 0.5 * (v.vy + next.vy), 0.5 * (v.wz + next.wz), dt);
    v = next;
    r.commands.push_back(out.twist);
    if (std::getenv("MPPI_TRACE"))
      std::printf("%.2f pose %.3f %.3f %.3f cmd %.3f %.3f %.3f costs %.4f %.4f seq %.4f %.4f %.4f\n", t, pose.x, pose.y, pose.yaw, out.twist.vx, out.twist.vy, out.twist.wz, c.costs().minCoeff(), c.costs().maxCoeff(), c.sequence().vy(0), c.sequence().vy(20), c.sequence().vy(50));
    if (std::optional<Cell> cell = m.geometry().world_to_cell(pose.translation())) {
      (void)cell;
      r.min_clearance_m = std::min(r.min_clearance_m, brute_clearance(m, pose.translation()));
    }
  }
  r.pose = pose;
  return r;
}

TEST(MppiController, AMecanumRobotReachesAGoalBesideItAndItsHeading) {
  const OccupancyGrid m = empty_map(6.0, 6.0);
  MppiConfig config;
  config.batch_size = 400;
  MppiController c(config, mecanum(), 3);
  const Pose2 start(3.0, 2.0, kPi / 2.0);
  const Vec2 goal(1.5, 2.0);  // 1.5 m to its left
  const LoopResult r = drive(c, m, mecanum(), start, {start.translation(), goal}, kPi / 2.0, 40.0);
  ASSERT_EQ(r.status, ControlStatus::Arrived) << r.pose.x << " " << r.pose.y << " " << r.pose.yaw;
  EXPECT_LE((r.pose.translation() - goal).norm(), 0.05);
  EXPECT_LE(std::abs(wrap_angle(r.pose.yaw - kPi / 2.0)), deg_to_rad(3.0));
  double max_vy = 0.0;
  for (const BodyTwist& t : r.commands) max_vy = std::max(max_vy, std::abs(t.vy));
  EXPECT_GT(max_vy, 0.1);  // it translated sideways
}

TEST(MppiController, AnAckermannRobotTurnsNeverTighterThanItsRadius) {
  const OccupancyGrid m = empty_map(8.0, 8.0);
  RobotConfig car = mecanum();
  car.drive = DriveKind::Ackermann;
  MppiConfig config;
  config.batch_size = 400;
  config.vx_min_mps = 0.0;  // forward only
  MppiController c(config, car, 2);
  EXPECT_TRUE(c.wants_smoothed_path());
  const double r_min = 2.0 * car.half_wheelbase_m / std::tan(car.max_steer_rad);
  EXPECT_NEAR(c.limits().min_turning_r, r_min, 1e-12);
  const Pose2 start(1.0, 1.0, 0.0);
  const std::vector<Vec2> path{start.translation(), {3.5, 1.0}, {6.5, 4.0}};  // a 45 degree turn
  const LoopResult r = drive(c, m, car, start, path, std::nullopt, 60.0);
  ASSERT_EQ(r.status, ControlStatus::Arrived) << r.pose.x << " " << r.pose.y;
  for (const BodyTwist& t : r.commands) {
    EXPECT_EQ(t.vy, 0.0);
    EXPECT_LE(std::abs(t.wz), std::abs(t.vx) / r_min * (1.0 + 1e-5) + 1e-6);
  }
}

// A path of poses along y = 2: forward from x = 1 to x = 3, then in reverse back to x = 2 (the
// heading 0 throughout), as a planner between poses gives it: per pose 1 when the motion leaving
// it (for the last, arriving at it) drives in reverse, so the cusp at x = 3 is the first 1.
void forward_then_reverse(std::vector<Pose2>& poses, std::vector<std::uint8_t>& reversing) {
  for (int i = 0; i <= 40; ++i) poses.emplace_back(1.0 + 0.05 * i, 2.0, 0.0), reversing.push_back(i == 40 ? 1 : 0);
  for (int i = 1; i <= 20; ++i) poses.emplace_back(3.0 - 0.05 * i, 2.0, 0.0), reversing.push_back(1);
}

// A car on an empty 6 x 4 m map with the forward-then-reverse path and its end as the goal.
class MppiCarOnReversingPath : public ::testing::Test {
 protected:
  OccupancyGrid m = empty_map(6.0, 4.0);
  RobotConfig car = [] {
    RobotConfig r = mecanum();
    r.drive = DriveKind::Ackermann;
    return r;
  }();
  std::vector<Pose2> poses;
  std::vector<std::uint8_t> reversing;
  Vec2 goal;
  MppiCarOnReversingPath() {
    forward_then_reverse(poses, reversing);
    goal = poses.back().translation();
  }
};

TEST_F(MppiCarOnReversingPath, IsFollowedOneStretchAtATime) {
  MppiConfig config;
  config.batch_size = 400;
  // Ten steps from `pose` (held there): the last command and status.
  const auto steps_at = [&](MppiController& c, const Pose2& pose) {
    ControlOutput out;
    for (int k = 0; k < 10; ++k) {
      ControlInput in = input_at(pose, {}, m, goal, car);
      in.t_s = 0.05 * k;
      in.goal_yaw = 0.0;
      out = c.compute(in);
      if (out.status != ControlStatus::Tracking) break;
    }
    return out;
  };
  for (const bool replan : {false, true}) {
    config.replan_at_cusps = replan;
    MppiController c(config, car, 4);
    c.set_path_poses(poses, reversing);
    EXPECT_EQ(c.path().size(), poses.size());  // the whole path, for the pictures
    // Before the cusp: forward, toward it (the reverse stretch beyond is not seen yet).
    const ControlOutput before = steps_at(c, Pose2(2.2, 2.0, 0.0));
    EXPECT_EQ(before.status, ControlStatus::Tracking);
    EXPECT_GT(before.twist.vx, 0.01);  // from rest: the sign is what counts
    // At the cusp (within 0.2 m and 0.4 rad of its pose): the next stretch, backwards, or (the
    // default) a new plan from here asked for.
    const ControlOutput at = steps_at(c, Pose2(2.85, 2.03, 0.2));
    if (replan) {
      EXPECT_EQ(at.status, ControlStatus::AtCusp);
      EXPECT_EQ(at.twist.vx, 0.0);
    } else {
      EXPECT_EQ(at.status, ControlStatus::Tracking);
      EXPECT_LT(at.twist.vx, -0.01);
    }
  }
  {
    // A plan that starts at the cusp: its first stretch ends where it starts, so it is done
    // already and the reverse stretch is driven.
    MppiController c(config, car, 4);
    std::vector<Pose2> rest(poses.begin() + 39, poses.end());
    std::vector<std::uint8_t> rest_reversing(reversing.begin() + 39, reversing.end());
    c.set_path_poses(rest, rest_reversing);
    const ControlOutput out = steps_at(c, Pose2(2.95, 2.0, 0.0));
    EXPECT_EQ(out.status, ControlStatus::Tracking);
    EXPECT_LT(out.twist.vx, -0.01);
  }
  // Sizes that differ, a pose not finite: errors naming the path.
  MppiController c(config, car, 4);
  EXPECT_THROW(c.set_path_poses(poses, std::vector<std::uint8_t>(3, 0)), Error);
  poses[3].yaw = std::nan("");
  EXPECT_THROW(c.set_path_poses(poses, reversing), Error);
}

// A car held short of its cusp while MPPI keeps commanding (stopping is the stall check's, off
// here): the stretch is given up, and a new plan asked for, at the first step at or after its
// time, stretch_time_s plus its length at the top speed; with 0, never.
TEST_F(MppiCarOnReversingPath, AStretchNotDoneInItsTimeIsPlannedAnew) {
  MppiConfig config;
  config.batch_size = 200;
  config.stall_time_s = 0.0;
  const double length = 2.0;  // the forward stretch: x from 1 to 3 m
  const double due = 1.0 + length / std::min(config.vx_max_mps, velocity_limits_of(car).max_vx_mps);
  const auto first_stop = [&](double stretch_time_s) {
    config.stretch_time_s = stretch_time_s;
    MppiController c(config, car, 4);
    c.set_path_poses(poses, reversing);
    for (int k = 0; k <= 200; ++k) {
      ControlInput in = input_at(Pose2(1.5, 2.0, 0.0), {0.2, 0.0, 0.0}, m, goal, car);
      in.t_s = 0.05 * k;
      in.goal_yaw = 0.0;
      const ControlOutput out = c.compute(in);
      if (out.status != ControlStatus::Tracking) {
        EXPECT_EQ(out.status, ControlStatus::AtCusp);
        EXPECT_EQ(out.twist.vx, 0.0);
        return in.t_s;
      }
    }
    return -1.0;
  };
  const double t = first_stop(1.0);
  EXPECT_GE(t, due - 1e-9);
  EXPECT_LT(t, due + 0.05);
  EXPECT_EQ(first_stop(0.0), -1.0);
}

TEST(MppiController, ADifferentialRobotPassesADoorWithoutTouching) {
  OccupancyGrid m = empty_map(6.0, 4.0);
  fill_box(m, 2.95, 0.0, 3.05, 1.5);  // a wall at x = 3 with a 1 m door from y = 1.5 to 2.5
  fill_box(m, 2.95, 2.5, 3.05, 4.0);
  MppiConfig config;
  config.batch_size = 400;
  config.obstacles.consider_footprint = true;
  MppiController c(config, differential(), 5);
  c.keep_diagnostics(true);
  const Pose2 start(1.0, 2.0, 0.0);
  const LoopResult r = drive(c, m, differential(), start, {start.translation(), {3.0, 2.0}, {5.0, 2.0}}, std::nullopt, 40.0);
  ASSERT_EQ(r.status, ControlStatus::Arrived) << r.pose.x << " " << r.pose.y;
  for (const BodyTwist& t : r.commands) EXPECT_EQ(t.vy, 0.0);
  // The body box (0.55 x 0.5) never reached a wall cell: its centre kept more than its half width
  // plus half a cell from every wall cell centre.
  EXPECT_GT(r.min_clearance_m, 0.25 + 0.025);
}

TEST(MppiController, DiagnosticsHoldSampledTrajectoriesWithCostsAndTheChosenOne) {
  OccupancyGrid m = empty_map(6.0, 6.0);
  fill_box(m, 2.5, 0.0, 2.7, 6.0);
  MppiConfig config;
  config.batch_size = 200;
  config.diagnostics_samples = 20;
  MppiController c(config, differential(), 1);
  c.set_path(std::vector<Vec2>{{1.0, 3.0}, {5.0, 3.0}});
  EXPECT_FALSE(c.diagnostics());
  c.keep_diagnostics(true);
  // Driving at the wall at 0.4 m/s, 0.3 m from where the inscribed circle touches it: braking at
  // the limit stops in time, the noisier samples do not.
  const ControlOutput out = c.compute(input_at(Pose2(2.2, 3.0, 0.0), {0.4, 0.0, 0.0}, m, {5.0, 3.0}, differential()));
  const auto d = c.diagnostics();
  ASSERT_TRUE(d);
  ASSERT_EQ(d->candidates.size(), 21u);
  ASSERT_EQ(d->chosen, 20);
  EXPECT_EQ(d->command.vx, out.twist.vx);
  int colliding = 0;
  for (int i = 0; i < 20; ++i) {
    EXPECT_EQ(d->candidates[static_cast<std::size_t>(i)].trajectory.size(), 56u);
    EXPECT_EQ(d->candidates[static_cast<std::size_t>(i)].cost, c.costs()(i * 10));
    colliding += d->candidates[static_cast<std::size_t>(i)].status == CandidateStatus::Collides;
  }
  EXPECT_GT(colliding, 0);
  for (const ControlCandidate& k : d->candidates) {
    if (k.status == CandidateStatus::Collides) {
      EXPECT_GE(k.cost, config.obstacles.critical_weight * config.obstacles.collision_cost * 0.999);
    }
  }
}

// The DWA sideways scenario (Mecanum, goal 1.5 m to the left) driven by mppi in the simulator.
TEST(MppiController, TheSidewaysScenarioReachesItsGoalWithMppi) {
  std::vector<ScenarioOverride> sets = {parse_scenario_override("navigation.controller=mppi"),
                                        parse_scenario_override("navigation.mppi.batch_size=500"),
                                        parse_scenario_override("navigation.mppi.critics=[constraint, obstacles, goal, goal_angle, path_align, path_follow, path_angle, prefer_forward, twirling]")};
  const ScenarioSpec spec = parse_scenario(read_text(scenario_path("dwa_sideways.yaml")), scenario_path("dwa_sideways.yaml"), sets);
  NavigationOptions o;
  o.record_steps = false;
  NavigationRun run(spec, o);
  run.run();
  const NavigationMetrics metrics = run.metrics();
  EXPECT_TRUE(metrics.success) << metrics.outcome;
  EXPECT_EQ(metrics.collisions, 0);
  EXPECT_LE(metrics.goal_distance_m, 0.03 + 1e-9);
}

// The car's scenarios (docs/local_planning.md, "Car-like robots"; they do not reach their goals
// yet): the first seconds of each, Hybrid-A* planning and MPPI driving the Ackermann robot
// through its first stretches with its body never touching an obstacle.
TEST(MppiController, TheAckermannScenariosDriveWithoutCollision) {
  for (const char* name : {"ackermann_parking.yaml", "ackermann_three_point_turn.yaml", "ackermann_rooms.yaml"}) {
    const std::vector<ScenarioOverride> sets = {parse_scenario_override("sim.duration_s=8")};
    const ScenarioSpec spec = parse_scenario(read_text(scenario_path(name)), scenario_path(name), sets);
    NavigationOptions o;
    o.record_steps = false;
    NavigationRun run(spec, o);
    run.run();
    const NavigationMetrics metrics = run.metrics();
    EXPECT_GE(metrics.plans, 1) << name;
    EXPECT_GT(metrics.distance_m, 0.3) << name;
    EXPECT_EQ(metrics.collisions, 0) << name;
  }
}

}  // namespace mppi_test
}  // namespace starnav
