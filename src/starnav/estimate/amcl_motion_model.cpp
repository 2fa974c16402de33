#include "starnav/estimate/amcl_motion_model.hpp"

#include <algorithm>
#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

namespace {

// Nav2's noise size of a rotation: the same for a turn by r and by r +- pi (driving backwards).
double amcl_rotation_noise_size(double r) {
  return std::min(std::abs(wrap_angle(r)), std::abs(wrap_angle(r - kPi)));
}

}  // namespace

void MotionNoise::validate() const {
  require_non_negative(alpha1, "amcl.alpha1");
  require_non_negative(alpha2, "amcl.alpha2");
  require_non_negative(alpha3, "amcl.alpha3");
  require_non_negative(alpha4, "amcl.alpha4");
  require_non_negative(alpha5, "amcl.alpha5");
}

void DifferentialMotionModel::apply(const Pose2& odom_old, const Pose2& odom_new, std::span<Pose2> poses,
                                    Rng& rng) const {
  const double dx = odom_new.x - odom_old.x, dy = odom_new.y - odom_old.y;
  const double dyaw = angle_diff(odom_new.yaw, odom_old.yaw);
  const double trans = std::sqrt(dx * dx + dy * dy);
  // A bearing between two nearly equal positions is noise (in-place rotation).
  const double rot1 = trans < 0.01 ? 0.0 : angle_diff(std::atan2(dy, dx), odom_old.yaw);
  const double rot2 = angle_diff(dyaw, rot1);
  const double rot1_n = amcl_rotation_noise_size(rot1), rot2_n = amcl_rotation_noise_size(rot2);
  const MotionNoise& a = noise_;
  const double sd_rot1 = std::sqrt(a.alpha1 * rot1_n * rot1_n + a.alpha2 * trans * trans);
  const double sd_trans = std::sqrt(a.alpha3 * trans * trans + a.alpha4 * rot1_n * rot1_n + a.alpha4 * rot2_n * rot2_n);
  const double sd_rot2 = std::sqrt(a.alpha1 * rot2_n * rot2_n + a.alpha2 * trans * trans);
  for (Pose2& p : poses) {
    const double rot1_hat = angle_diff(rot1, sd_rot1 * rng.normal());
    const double trans_hat = trans - sd_trans * rng.normal();
    const double rot2_hat = angle_diff(rot2, sd_rot2 * rng.normal());
    p.x += trans_hat * std::cos(p.yaw + rot1_hat);
    p.y += trans_hat * std::sin(p.yaw + rot1_hat);
    p.yaw = wrap_angle(p.yaw + rot1_hat + rot2_hat);
  }
}

void OmniMotionModel::apply(const Pose2& odom_old, const Pose2& odom_new, std::span<Pose2> poses, Rng& rng) const {
  const double dx = odom_new.x - odom_old.x, dy = odom_new.y - odom_old.y;
  const double trans = std::sqrt(dx * dx + dy * dy);
  const double rot = angle_diff(odom_new.yaw, odom_old.yaw);
  const MotionNoise& a = noise_;
  const double sd_trans = std::sqrt(a.alpha3 * trans * trans + a.alpha4 * rot * rot);
  const double sd_rot = std::sqrt(a.alpha1 * rot * rot + a.alpha2 * trans * trans);
  const double sd_strafe = std::sqrt(a.alpha4 * rot * rot + a.alpha5 * trans * trans);
  const double bearing_odom = angle_diff(std::atan2(dy, dx), odom_old.yaw);
  for (Pose2& p : poses) {
    const double b = bearing_odom + p.yaw;
    const double cb = std::cos(b), sb = std::sin(b);
    const double trans_hat = trans + sd_trans * rng.normal();
    const double rot_hat = rot + sd_rot * rng.normal();
    const double strafe_hat = sd_strafe * rng.normal();
    p.x += trans_hat * cb + strafe_hat * sb;
    p.y += trans_hat * sb - strafe_hat * cb;
    p.yaw = wrap_angle(p.yaw + rot_hat);
  }
}

void apply_motion_model(MotionModelType type, const MotionNoise& noise, const Pose2& odom_old, const Pose2& odom_new,
                        std::span<Pose2> poses, Rng& rng) {
  if (type == MotionModelType::Omnidirectional) OmniMotionModel(noise).apply(odom_old, odom_new, poses, rng);
  else DifferentialMotionModel(noise).apply(odom_old, odom_new, poses, rng);
}

}  // namespace starnav
