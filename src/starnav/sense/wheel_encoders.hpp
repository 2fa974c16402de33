#pragma once
// Incremental wheel encoders (docs/papers/ren2022.md). Each wheel's sensed angle is its true
// travel since the first sample plus a slip error that accumulates N(0, slip_sigma^2) times each
// increment of the true angle between samples (multiplicative slip noise on the increments; one
// normal per wheel per sample, wheels in order, from the encoders' own Rng, only when
// slip_sigma > 0). The reported count is floor(sensed_angle * ticks_per_rev / (2 pi)), cumulative
// since the first sample (whose angles are the zero). Without slip, 2 pi ticks / ticks_per_rev lies
// within one tick of the true travel (at or below it). A systematic error per wheel (scale_error
// e_i) makes wheel i count (1 + e_i) times its true travel, slip included: a wheel whose real
// radius is not the one the odometry assumes (a worn or under-inflated tyre, a calibration error),
// the odometry error that grows with distance and that no seed averages away.
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/core/rng.hpp"

namespace starnav {

struct EncoderConfig {
  int ticks_per_rev = 1024;
  double slip_sigma = 0.0;
  // One fraction per wheel, in the drive's wheel order (empty: none); each in [-0.5, 0.5].
  std::vector<double> scale_error;
  // Throws Error naming the field (prefix "encoders.").
  void validate() const;
};

class WheelEncoders {
 public:
  // Validates the configuration; `wheels` >= 1, and scale_error empty or one per wheel.
  WheelEncoders(int wheels, const EncoderConfig& config, Rng rng);
  // Cumulative ticks of every wheel for the true wheel angles (rad) now.
  std::vector<std::int64_t> sample(std::span<const double> wheel_angle_rad);
  // Ticks -> angle (rad).
  double ticks_to_rad(std::int64_t ticks) const;
  int wheels() const { return static_cast<int>(sensed_.size()); }
  const EncoderConfig& config() const { return config_; }

 private:
  EncoderConfig config_;
  Rng rng_;
  bool started_ = false;
  std::vector<double> last_true_;  // true angles at the previous sample
  std::vector<double> first_;      // true angles at the first sample (the zero)
  std::vector<double> sensed_;     // accumulated slip error (rad)
};

}  // namespace starnav
