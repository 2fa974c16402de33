#include "starnav/sense/imu.hpp"

#include <cmath>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

void ImuConfig::validate() const {
  if (!(std::isfinite(rate_hz) && rate_hz > 0.0)) throw Error("must be finite and > 0", {}, 0, "imu.rate_hz");
  if (!(std::isfinite(yaw_rate_noise_sigma_radps) && yaw_rate_noise_sigma_radps >= 0.0))
    throw Error("must be finite and >= 0", {}, 0, "imu.yaw_rate_noise_sigma_radps");
  if (!std::isfinite(yaw_rate_bias_radps)) throw Error("must be finite", {}, 0, "imu.yaw_rate_bias_radps");
  if (!(std::isfinite(yaw_noise_sigma_rad) && yaw_noise_sigma_rad >= 0.0))
    throw Error("must be finite and >= 0", {}, 0, "imu.yaw_noise_sigma_rad");
}

ImuModel::ImuModel(const ImuConfig& config, Rng rng, double initial_yaw_rad)
    : config_(config), rng_(rng), yaw_(initial_yaw_rad) {
  config_.validate();
}

ImuModel::ImuReading ImuModel::sample(double t_s, double true_yaw_rate, double dt) {
  if (!(std::isfinite(dt) && dt >= 0.0)) throw Error("must be finite and >= 0", {}, 0, "dt");
  double rate = true_yaw_rate + config_.yaw_rate_bias_radps;
  if (config_.yaw_rate_noise_sigma_radps > 0.0) rate += config_.yaw_rate_noise_sigma_radps * rng_.normal();
  yaw_ += rate * dt;
  double yaw = yaw_;
  if (config_.yaw_noise_sigma_rad > 0.0) yaw += config_.yaw_noise_sigma_rad * rng_.normal();
  return {t_s, rate, wrap_angle(yaw)};
}

ImuMessage imu_message(const ImuModel::ImuReading& reading, const std::string& stream) {
  ImuMessage m;
  m.header = {reading.t_s, stream};
  m.angular_velocity_radps = Vec3(0.0, 0.0, reading.yaw_rate_radps);
  m.yaw_rad = reading.yaw_rad;
  return m;
}

}  // namespace starnav
