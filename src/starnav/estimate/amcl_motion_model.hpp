#pragma once
// The odometry motion models of AMCL, exactly as Nav2's nav2_amcl (after Player's amcl and
// Probabilistic Robotics, sample_motion_model_odometry, Table 5.6). The odometry increment is
// taken between two odom-frame poses; every particle moves by it, rotated into the particle's
// heading, with noise drawn per particle from the starnav Rng.
#include <cstdint>
#include <span>

#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"

namespace starnav {

enum class MotionModelType : std::uint8_t { Differential, Omnidirectional };

// alpha1: rotation noise from rotation, alpha2: rotation from translation, alpha3: translation
// from translation, alpha4: translation from rotation, alpha5: strafe from translation (omni
// only). They scale variances (sigma^2 = alpha * delta^2), as in Nav2.
struct MotionNoise {
  double alpha1 = 0.2;
  double alpha2 = 0.2;
  double alpha3 = 0.2;
  double alpha4 = 0.2;
  double alpha5 = 0.2;
  // Throws Error (field "amcl.alphaN") for a negative or non-finite alpha.
  void validate() const;
};

// Differential drive (rotate, translate, rotate). With dx, dy, dyaw the odom-frame increment:
//   rot1 = 0 if sqrt(dx^2 + dy^2) < 0.01 (in-place rotation) else atan2(dy, dx) - yaw_old
//   trans = sqrt(dx^2 + dy^2), rot2 = dyaw - rot1
// and rot_n = min(|r|, |r - pi|) (backward motion treated like forward motion for the noise):
//   rot1' = rot1 - N(0, a1 rot1_n^2 + a2 trans^2)
//   trans' = trans - N(0, a3 trans^2 + a4 rot1_n^2 + a4 rot2_n^2)
//   rot2' = rot2 - N(0, a1 rot2_n^2 + a2 trans^2)
//   x += trans' cos(yaw + rot1'), y += trans' sin(yaw + rot1'), yaw += rot1' + rot2'.
class DifferentialMotionModel {
 public:
  explicit DifferentialMotionModel(const MotionNoise& noise) : noise_(noise) {}
  void apply(const Pose2& odom_old, const Pose2& odom_new, std::span<Pose2> poses, Rng& rng) const;

 private:
  MotionNoise noise_;
};

// Omnidirectional (holonomic): with trans = sqrt(dx^2 + dy^2), rot = dyaw and for each particle
// the bearing b = (atan2(dy, dx) - yaw_old) + yaw:
//   trans' = trans + N(0, a3 trans^2 + a4 rot^2), rot' = rot + N(0, a1 rot^2 + a2 trans^2),
//   strafe' = N(0, a4 rot^2 + a5 trans^2)
//   x += trans' cos b + strafe' sin b, y += trans' sin b - strafe' cos b, yaw += rot'.
class OmniMotionModel {
 public:
  explicit OmniMotionModel(const MotionNoise& noise) : noise_(noise) {}
  void apply(const Pose2& odom_old, const Pose2& odom_new, std::span<Pose2> poses, Rng& rng) const;

 private:
  MotionNoise noise_;
};

// The model of `type` applied to `poses`. Yaw comes back wrapped into (-pi, pi].
void apply_motion_model(MotionModelType type, const MotionNoise& noise, const Pose2& odom_old, const Pose2& odom_new,
                        std::span<Pose2> poses, Rng& rng);

}  // namespace starnav
