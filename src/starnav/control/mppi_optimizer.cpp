#include "starnav/control/mppi_optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace starnav {

const char* mppi_motion_model_name(MppiMotionModel m) {
  switch (m) {
    case MppiMotionModel::DiffDrive: return "diff_drive";
    case MppiMotionModel::Omni: return "omni";
    case MppiMotionModel::Ackermann: return "ackermann";
  }
  return "diff_drive";
}

namespace {

// One axis: the speed bounds, then step by step the acceleration bounds from `v0` (a rising
// magnitude limited by a_max, a falling one by -a_min, as Nav2's motion models).
void limit_axis(Eigen::ArrayXXf& v, double lo, double hi, double v0, double a_max, double a_min, double dt) {
  const float up = static_cast<float>(a_max * dt), down = static_cast<float>(-a_min * dt);  // both >= 0
  const float flo = static_cast<float>(lo), fhi = static_cast<float>(hi);
  const Eigen::Index n = v.rows();
  // One pass per step over the batch, branch-free on distinct columns (the compiler vectorises
  // it): the previous step's velocity is the column before, the current one's before step 0.
  const auto step = [&](float* __restrict col, const float* __restrict prev, float first) {
    for (Eigen::Index k = 0; k < n; ++k) {
      const float last = prev ? prev[k] : first;
      const bool forward = last > 0.0f;
      const float lower = last - (forward ? down : up), upper = last + (forward ? up : down);
      const float x = std::min(std::max(col[k], flo), fhi);
      col[k] = std::min(std::max(x, lower), upper);
    }
  };
  if (v.cols() == 0) return;
  step(v.col(0).data(), nullptr, static_cast<float>(v0));
  for (Eigen::Index t = 1; t < v.cols(); ++t) {
    float* __restrict col = v.col(t).data();
    const float* __restrict prev = v.col(t - 1).data();
    for (Eigen::Index k = 0; k < n; ++k) {
      const float last = prev[k];
      const float forward = static_cast<float>(last > 0.0f);  // 1 or 0, no branch
      const float lower = last - up + forward * (up - down), upper = last + down + forward * (up - down);
      const float x = std::min(std::max(col[k], flo), fhi);
      col[k] = std::min(std::max(x, lower), upper);
    }
  }
}

}  // namespace

void mppi_apply_limits(const MppiLimits& l, const BodyTwist& current, double dt, MppiControls& c) {
  limit_axis(c.vx, l.vx_min, l.vx_max, current.vx, l.ax_max, l.ax_min, dt);
  if (l.holonomic()) limit_axis(c.vy, -l.vy_max, l.vy_max, current.vy, l.ay_max, l.ay_min, dt);
  else c.vy.setZero();
  if (l.model == MppiMotionModel::Ackermann && c.curvature.size() == c.vx.size() && c.vx.size() > 0) {
    // Sampled in curvature: the radius is kept by construction, the yaw rate follows the speed.
    const float k_max = static_cast<float>(1.0 / l.min_turning_r);
    c.curvature = c.curvature.cwiseMax(-k_max).cwiseMin(k_max);
    c.wz = c.vx * c.curvature;
    return;
  }
  limit_axis(c.wz, -l.wz_max, l.wz_max, current.wz, l.az_max, -l.az_max, dt);
  if (l.model == MppiMotionModel::Ackermann) {
    // The radius has the last word: |vx / wz| >= R_min for every sample and step.
    const float inv_r = static_cast<float>(1.0 / l.min_turning_r);
    const Eigen::ArrayXXf bound = c.vx.abs() * inv_r;
    c.wz = c.wz.cwiseMax(-bound).cwiseMin(bound);
  }
}

void mppi_integrate(const Pose2& start, double dt, const MppiControls& c, MppiTrajectories& out) {
  const Eigen::Index n = c.vx.rows(), steps = c.vx.cols();
  out.x.resize(n, steps);
  out.y.resize(n, steps);
  out.yaw.resize(n, steps);
  const float fdt = static_cast<float>(dt);
  Eigen::ArrayXf x = Eigen::ArrayXf::Constant(n, static_cast<float>(start.x));
  Eigen::ArrayXf y = Eigen::ArrayXf::Constant(n, static_cast<float>(start.y));
  Eigen::ArrayXf yaw = Eigen::ArrayXf::Constant(n, static_cast<float>(start.yaw));
  Eigen::ArrayXf half(n), mid(n), cs(n), sn(n), chord(n);
  for (Eigen::Index t = 0; t < steps; ++t) {
    half = c.wz.col(t) * (0.5f * fdt);
    mid = yaw + half;
    cs = mid.cos();
    sn = mid.sin();
    // sinc(h) = 1 - h^2/6 + h^4/120 - ...: |h| <= wz_max dt / 2 is small; the next term is below
    // float precision for |h| < 0.3.
    const Eigen::ArrayXf h2 = half.square();
    chord = fdt * (1.0f - h2 * (1.0f / 6.0f) + h2.square() * (1.0f / 120.0f));
    x += (c.vx.col(t) * cs - c.vy.col(t) * sn) * chord;
    y += (c.vx.col(t) * sn + c.vy.col(t) * cs) * chord;
    yaw = mid + half;
    out.x.col(t) = x;
    out.y.col(t) = y;
    out.yaw.col(t) = yaw;
  }
}

void mppi_softmax_weights(const Eigen::ArrayXf& costs, double temperature, Eigen::ArrayXf& weights) {
  const float lo = costs.minCoeff();
  weights = (-(costs - lo) * static_cast<float>(1.0 / temperature)).exp();
  weights /= weights.sum();
}

void mppi_weighted_mean(const MppiControls& c, const Eigen::ArrayXf& w, MppiSequence& out) {
  out.vx = (c.vx.colwise() * w).colwise().sum().transpose();
  out.vy = (c.vy.colwise() * w).colwise().sum().transpose();
  out.wz = (c.wz.colwise() * w).colwise().sum().transpose();
  if (c.curvature.size() == c.vx.size() && c.vx.size() > 0) out.curvature = (c.curvature.colwise() * w).colwise().sum().transpose();
}

void mppi_savitzky_golay(Eigen::ArrayXf& seq, const std::array<float, 4>& history) {
  // Quadratic (and cubic) least squares over 9 points: (-21, 14, 39, 54, 59, 54, 39, 14, -21) / 231.
  static constexpr std::array<float, 9> kCoefficients = {-21.0f, 14.0f, 39.0f, 54.0f, 59.0f, 54.0f, 39.0f, 14.0f, -21.0f};
  const Eigen::Index n = seq.size();
  if (n < 21) return;
  const Eigen::ArrayXf original = seq;
  const auto at = [&](Eigen::Index j) {
    if (j < 0) return history[static_cast<std::size_t>(4 + j)];
    return original(std::min(j, n - 1));
  };
  // The last value is left as it is (Nav2 filters all but the last).
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    float sum = 0.0f;
    for (int k = 0; k < 9; ++k) sum += kCoefficients[static_cast<std::size_t>(k)] * at(i + k - 4);
    seq(i) = sum / 231.0f;
  }
}

}  // namespace starnav
