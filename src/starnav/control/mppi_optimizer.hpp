#pragma once
// The batch arithmetic of the MPPI controller (mppi_controller.hpp, docs/local_planning.md "MPPI"):
// the sampled control sequences and the poses they reach, laid out as Eigen arrays of
// batch x time_steps (one column per time step, so each step's update of every sample is one
// contiguous vector operation the compiler vectorises), in single precision as Nav2's.
//
//   limits      each sample's velocities within the motion model's limits: speed bounds, then the
//               acceleration bounds step by step from the robot's current velocity (ax_max raises
//               the speed's magnitude, ax_min lowers it), then for Ackermann |wz| <= |vx| / R_min
//               (the turning radius never below R_min, whatever the noise); an Ackermann batch
//               sampled in curvature has its curvature cut to 1 / R_min and wz = vx x curvature
//   integrate   the poses after each step, each step an exact arc of its constant twist
//   softmax     weights exp(-(c - c_min) / temperature), normalised
//   smoothing   Nav2's 9-point quadratic Savitzky-Golay filter of the sequence, the four last
//               commands standing before it and its last value repeated after it
#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "starnav/core/geometry.hpp"

namespace starnav {

enum class MppiMotionModel : std::uint8_t { DiffDrive, Omni, Ackermann };
// "diff_drive", "omni", "ackermann"
const char* mppi_motion_model_name(MppiMotionModel m);

// A step's limits (SI units; ax_min and ay_min <= 0).
struct MppiLimits {
  MppiMotionModel model = MppiMotionModel::DiffDrive;
  double vx_max = 0.5, vx_min = -0.35, vy_max = 0.5, wz_max = 1.9;
  double ax_max = 3.0, ax_min = -3.0, ay_max = 3.0, ay_min = -3.0, az_max = 3.5;
  double min_turning_r = 0.2;  // Ackermann only
  bool holonomic() const { return model == MppiMotionModel::Omni; }
};

// Controls of a batch: row = sample, column = time step (the velocity held over that step).
// `curvature` (1/m) is used by an Ackermann batch sampled in curvature (empty otherwise): it
// decides wz = vx x curvature, so that a sample keeps its steering whatever its speed, through
// zero and in reverse, as a car's steering does.
struct MppiControls {
  Eigen::ArrayXXf vx, vy, wz, curvature;
  void resize(int batch, int steps) {
    vx.setZero(batch, steps);
    vy.setZero(batch, steps);
    wz.setZero(batch, steps);
  }
};

// The poses after each step (row = sample, column = step).
struct MppiTrajectories {
  Eigen::ArrayXXf x, y, yaw;
};

// One control sequence (the optimiser's mean).
struct MppiSequence {
  Eigen::ArrayXf vx, vy, wz, curvature;  // curvature: as MppiControls'
  void reset(int steps) {
    vx.setZero(steps);
    vy.setZero(steps);
    wz.setZero(steps);
    curvature.setZero(steps);
  }
};

// `c` within `limits` from the current body velocity `current` (the limits' list above); vy is
// zeroed for a robot that is not holonomic. An Ackermann batch with curvatures: |curvature| <=
// 1 / R_min, then wz = vx x curvature (wz's own limits do not apply: the steering decides it).
void mppi_apply_limits(const MppiLimits& limits, const BodyTwist& current, double dt, MppiControls& c);

// The poses after each step of `c` from `start`, every step an exact arc (its chord through the
// mid-step heading, of length |v| dt sinc(wz dt / 2)).
void mppi_integrate(const Pose2& start, double dt, const MppiControls& c, MppiTrajectories& out);

// Softmax weights of `costs` at `temperature` (> 0): exp(-(c - min c) / temperature) / sum; the
// finite minimum keeps the exponent <= 0, so no overflow.
void mppi_softmax_weights(const Eigen::ArrayXf& costs, double temperature, Eigen::ArrayXf& weights);

// The weighted mean over the samples of each step's controls (weights summing to 1), the
// curvature's too when the batch has one.
void mppi_weighted_mean(const MppiControls& c, const Eigen::ArrayXf& weights, MppiSequence& out);

// Nav2's Savitzky-Golay smoothing of one axis of a sequence (left unchanged below 21 steps);
// `history` holds the last four commands, oldest first.
void mppi_savitzky_golay(Eigen::ArrayXf& sequence, const std::array<float, 4>& history);

}  // namespace starnav
