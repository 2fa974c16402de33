#include "starnav/sense/wheel_encoders.hpp"

#include <cmath>
#include <string>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

void EncoderConfig::validate() const {
  if (ticks_per_rev < 1) throw Error("must be >= 1", {}, 0, "encoders.ticks_per_rev");
  if (!(std::isfinite(slip_sigma) && slip_sigma >= 0.0))
    throw Error("must be finite and >= 0", {}, 0, "encoders.slip_sigma");
  for (const double e : scale_error)
    if (!(std::isfinite(e) && e >= -0.5 && e <= 0.5)) throw Error("each must be in [-0.5, 0.5]", {}, 0, "encoders.scale_error");
}

WheelEncoders::WheelEncoders(int wheels, const EncoderConfig& config, Rng rng) : config_(config), rng_(rng) {
  config_.validate();
  if (wheels < 1) throw Error("must be >= 1 (got " + std::to_string(wheels) + ")", {}, 0, "encoders.wheels");
  if (!config_.scale_error.empty() && config_.scale_error.size() != static_cast<std::size_t>(wheels))
    throw Error("has " + std::to_string(config_.scale_error.size()) + " values; the drive has " + std::to_string(wheels) +
                    " wheels (one each, in its wheel order)",
                {}, 0, "encoders.scale_error");
  last_true_.assign(static_cast<std::size_t>(wheels), 0.0);
  sensed_.assign(static_cast<std::size_t>(wheels), 0.0);
  first_.assign(static_cast<std::size_t>(wheels), 0.0);
}

double WheelEncoders::ticks_to_rad(std::int64_t ticks) const {
  return 2.0 * kPi * static_cast<double>(ticks) / static_cast<double>(config_.ticks_per_rev);
}

std::vector<std::int64_t> WheelEncoders::sample(std::span<const double> wheel_angle_rad) {
  if (wheel_angle_rad.size() != sensed_.size())
    throw Error("expected " + std::to_string(sensed_.size()) + " wheel angles, got " +
                    std::to_string(wheel_angle_rad.size()),
                {}, 0, "encoders.wheels");
  std::vector<std::int64_t> ticks(sensed_.size());
  const double per_rad = static_cast<double>(config_.ticks_per_rev) / (2.0 * kPi);
  for (std::size_t i = 0; i < sensed_.size(); ++i) {
    if (!started_) first_[i] = wheel_angle_rad[i];
    // The slip error accumulates apart from the true travel so that, without slip, the count is
    // exactly floor((angle - first) ticks_per_rev / 2 pi).
    if (started_ && config_.slip_sigma > 0.0)
      sensed_[i] += (wheel_angle_rad[i] - last_true_[i]) * config_.slip_sigma * rng_.normal();
    last_true_[i] = wheel_angle_rad[i];
    const double scale = config_.scale_error.empty() ? 1.0 : 1.0 + config_.scale_error[i];
    ticks[i] = static_cast<std::int64_t>(std::floor((wheel_angle_rad[i] - first_[i] + sensed_[i]) * scale * per_rad));
  }
  started_ = true;
  return ticks;
}

}  // namespace starnav
