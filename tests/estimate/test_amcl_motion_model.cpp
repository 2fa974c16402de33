// AMCL's odometry motion models (Nav2's differential and omni models): sample moments of many
// particles moved from one pose against closed forms, and noiseless motion against pose
// composition.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/amcl_motion_model.hpp"

namespace starnav {
namespace {

struct AmclMotionMoments {
  double mx = 0, my = 0, myaw = 0;  // means of x, y and of the wrapped yaw deviation from `yaw_ref`
  double vx = 0, vy = 0, vyaw = 0;
};

AmclMotionMoments amcl_motion_sample_moments(const std::vector<Pose2>& poses, double yaw_ref) {
  AmclMotionMoments m;
  const double n = static_cast<double>(poses.size());
  for (const Pose2& p : poses) {
    m.mx += p.x;
    m.my += p.y;
    m.myaw += angle_diff(p.yaw, yaw_ref);
  }
  m.mx /= n;
  m.my /= n;
  m.myaw /= n;
  for (const Pose2& p : poses) {
    m.vx += (p.x - m.mx) * (p.x - m.mx);
    m.vy += (p.y - m.my) * (p.y - m.my);
    const double e = angle_diff(p.yaw, yaw_ref) - m.myaw;
    m.vyaw += e * e;
  }
  m.vx /= n - 1;
  m.vy /= n - 1;
  m.vyaw /= n - 1;
  return m;
}

double amcl_test_rotation_noise(double r) { return std::min(std::abs(wrap_angle(r)), std::abs(wrap_angle(r - kPi))); }

// Differential model, particle at p: with rot1' = rot1 - n1, trans' = trans - n2 (n independent
// normals of sd s1, s2, s3),
//   E[x'] = x + trans cos(phi) e^{-s1^2/2},  phi = yaw + rot1
//   Var[x'] = (trans^2 + s2^2)(1 + cos(2 phi) e^{-2 s1^2}) / 2 - trans^2 cos^2(phi) e^{-s1^2}
//   (sin for y), E[yaw'] = yaw + rot1 + rot2, Var[yaw'] = s1^2 + s3^2.
void amcl_expect_differential_moments(const MotionNoise& a, const Pose2& odom_old, const Pose2& odom_new, const Pose2& p,
                                 std::size_t n, std::uint64_t seed) {
  const double dx = odom_new.x - odom_old.x, dy = odom_new.y - odom_old.y;
  const double t = std::hypot(dx, dy);
  const double rot1 = t < 0.01 ? 0.0 : angle_diff(std::atan2(dy, dx), odom_old.yaw);
  const double rot2 = angle_diff(angle_diff(odom_new.yaw, odom_old.yaw), rot1);
  const double r1 = amcl_test_rotation_noise(rot1), r2 = amcl_test_rotation_noise(rot2);
  const double s1 = std::sqrt(a.alpha1 * r1 * r1 + a.alpha2 * t * t);
  const double s2 = std::sqrt(a.alpha3 * t * t + a.alpha4 * r1 * r1 + a.alpha4 * r2 * r2);
  const double s3 = std::sqrt(a.alpha1 * r2 * r2 + a.alpha2 * t * t);
  const double phi = p.yaw + rot1;
  const double ex = p.x + t * std::cos(phi) * std::exp(-s1 * s1 / 2);
  const double ey = p.y + t * std::sin(phi) * std::exp(-s1 * s1 / 2);
  const double vx = (t * t + s2 * s2) * (1 + std::cos(2 * phi) * std::exp(-2 * s1 * s1)) / 2 -
                    t * t * std::cos(phi) * std::cos(phi) * std::exp(-s1 * s1);
  const double vy = (t * t + s2 * s2) * (1 - std::cos(2 * phi) * std::exp(-2 * s1 * s1)) / 2 -
                    t * t * std::sin(phi) * std::sin(phi) * std::exp(-s1 * s1);
  const double vyaw = s1 * s1 + s3 * s3;

  std::vector<Pose2> poses(n, p);
  Rng rng(seed);
  DifferentialMotionModel(a).apply(odom_old, odom_new, poses, rng);
  const double yaw_ref = p.yaw + rot1 + rot2;
  const AmclMotionMoments m = amcl_motion_sample_moments(poses, yaw_ref);
  const double k = 4.0 / std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(m.mx, ex, k * std::sqrt(vx) + 1e-12);
  EXPECT_NEAR(m.my, ey, k * std::sqrt(vy) + 1e-12);
  EXPECT_NEAR(m.myaw, 0.0, k * std::sqrt(vyaw) + 1e-12);
  // Sample variances: relative sd about sqrt(2 / n) for near-normal samples; 5 of them.
  const double rel = 5.0 * std::sqrt(2.0 / static_cast<double>(n));
  EXPECT_NEAR(m.vx / vx, 1.0, rel);
  EXPECT_NEAR(m.vy / vy, 1.0, rel);
  EXPECT_NEAR(m.vyaw / vyaw, 1.0, rel);
}

TEST(MotionDifferential, ForwardMomentsMatchClosedForm) {
  const MotionNoise a{0.1, 0.05, 0.2, 0.03, 0.07};
  const Pose2 odom_old(1.0, 2.0, 0.3);
  const Pose2 odom_new = odom_old.compose(Pose2(0.4, 0.1, 0.25));
  amcl_expect_differential_moments(a, odom_old, odom_new, Pose2(-3.0, 5.0, 2.0), 400'000, 1);
}

// Driving backwards: the bearing turns by about pi, and the noise sees it as the small turn it is.
TEST(MotionDifferential, BackwardMotionNoiseIsFolded) {
  const MotionNoise a{0.3, 0.1, 0.2, 0.1, 0.0};
  const Pose2 odom_old(0.0, 0.0, -2.8);
  const Pose2 odom_new = odom_old.compose(Pose2(-0.5, 0.04, -0.1));
  amcl_expect_differential_moments(a, odom_old, odom_new, Pose2(4.0, -1.0, 3.1), 400'000, 2);
}

// Rotation on the spot: below 1 cm of translation the first rotation is 0 and the whole turn
// goes into the second.
TEST(MotionDifferential, InPlaceRotation) {
  const MotionNoise a{0.2, 0.2, 0.2, 0.2, 0.2};
  const Pose2 odom_old(0.0, 0.0, 0.0);
  const Pose2 odom_new(0.004, -0.003, 0.6);
  amcl_expect_differential_moments(a, odom_old, odom_new, Pose2(1.0, 1.0, -3.0), 400'000, 3);
}

// Omni model: E[x'] = x + t cos b, Var[x'] = st^2 cos^2 b + ss^2 sin^2 b, Var[y'] = st^2 sin^2 b
// + ss^2 cos^2 b, E[yaw'] = yaw + rot, Var[yaw'] = sr^2 (b = atan2(dy, dx) - yaw_old + yaw).
TEST(MotionOmni, MomentsMatchClosedForm) {
  const MotionNoise a{0.1, 0.05, 0.2, 0.03, 0.07};
  const Pose2 odom_old(1.0, 2.0, 0.3);
  const Pose2 odom_new = odom_old.compose(Pose2(0.3, -0.2, 0.25));
  const Pose2 p(-3.0, 5.0, 2.0);
  const double dx = odom_new.x - odom_old.x, dy = odom_new.y - odom_old.y;
  const double t = std::hypot(dx, dy), rot = angle_diff(odom_new.yaw, odom_old.yaw);
  const double st = std::sqrt(a.alpha3 * t * t + a.alpha4 * rot * rot);
  const double sr = std::sqrt(a.alpha1 * rot * rot + a.alpha2 * t * t);
  const double ss = std::sqrt(a.alpha4 * rot * rot + a.alpha5 * t * t);
  const double b = std::atan2(dy, dx) - odom_old.yaw + p.yaw;
  const double cb = std::cos(b), sb = std::sin(b);
  const double vx = st * st * cb * cb + ss * ss * sb * sb, vy = st * st * sb * sb + ss * ss * cb * cb;
  const std::size_t n = 400'000;
  std::vector<Pose2> poses(n, p);
  Rng rng(4);
  OmniMotionModel(a).apply(odom_old, odom_new, poses, rng);
  const AmclMotionMoments m = amcl_motion_sample_moments(poses, p.yaw + rot);
  const double k = 4.0 / std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(m.mx, p.x + t * cb, k * std::sqrt(vx));
  EXPECT_NEAR(m.my, p.y + t * sb, k * std::sqrt(vy));
  EXPECT_NEAR(m.myaw, 0.0, k * sr);
  const double rel = 5.0 * std::sqrt(2.0 / static_cast<double>(n));
  EXPECT_NEAR(m.vx / vx, 1.0, rel);
  EXPECT_NEAR(m.vy / vy, 1.0, rel);
  EXPECT_NEAR(m.vyaw / (sr * sr), 1.0, rel);
}

// Without noise both models move a particle by the odometry increment in its own frame.
TEST(MotionModels, NoiselessMotionIsComposition) {
  const MotionNoise zero{0.0, 0.0, 0.0, 0.0, 0.0};
  const Pose2 odom_old(1.0, -2.0, 2.9);
  const Pose2 increment(0.35, 0.12, 0.4);
  const Pose2 odom_new = odom_old.compose(increment);
  const Pose2 p(-5.0, 3.0, -3.0);
  const Pose2 truth = p.compose(increment);
  for (const MotionModelType type : {MotionModelType::Differential, MotionModelType::Omnidirectional}) {
    std::vector<Pose2> poses{p};
    Rng rng(5);
    apply_motion_model(type, zero, odom_old, odom_new, poses, rng);
    EXPECT_NEAR(poses[0].x, truth.x, 1e-12);
    EXPECT_NEAR(poses[0].y, truth.y, 1e-12);
    EXPECT_NEAR(angle_diff(poses[0].yaw, truth.yaw), 0.0, 1e-12);
    EXPECT_GT(poses[0].yaw, -kPi);
    EXPECT_LE(poses[0].yaw, kPi);
  }
}

TEST(MotionModels, RejectNegativeAlphas) {
  MotionNoise a;
  a.alpha3 = -0.1;
  try {
    a.validate();
    FAIL() << "negative alpha accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "amcl.alpha3");
  }
}

}  // namespace
}  // namespace starnav
