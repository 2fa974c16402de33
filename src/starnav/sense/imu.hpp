#pragma once
// A yaw-rate gyro (docs/papers/ren2022.md): each sample measures the true yaw rate plus a
// constant bias and Gaussian white noise,
//   rate_meas = rate_true + bias + N(0, yaw_rate_noise_sigma^2),
// and the reported yaw is integrated from the measured rate (so it drifts by bias * t plus a
// random walk), optionally with extra Gaussian noise on the reported yaw:
//   yaw_int += rate_meas * dt;   yaw = wrap(yaw_int + N(0, yaw_noise_sigma^2)).
// Every draw comes from the model's own Rng: one normal per sample for the rate (when its sigma
// is > 0), then one for the yaw (when its sigma is > 0).
#include <string>

#include "starnav/core/rng.hpp"
#include "starnav/sense/sensor_messages.hpp"

namespace starnav {

struct ImuConfig {
  double rate_hz = 100.0;  // how often the simulator samples it (the model itself takes any dt)
  double yaw_rate_noise_sigma_radps = 0.002;
  double yaw_rate_bias_radps = 0.0005;
  double yaw_noise_sigma_rad = 0.0;
  // Throws Error naming the field (prefix "imu.").
  void validate() const;
};

class ImuModel {
 public:
  struct ImuReading {
    double t_s = 0.0;
    double yaw_rate_radps = 0.0;
    double yaw_rad = 0.0;
  };
  // Validates the configuration.
  ImuModel(const ImuConfig& config, Rng rng, double initial_yaw_rad = 0.0);
  // One reading at time t_s for the true yaw rate over the last dt seconds.
  ImuReading sample(double t_s, double true_yaw_rate, double dt);
  const ImuConfig& config() const { return config_; }
  // Yaw integrated from the measured rates so far (unwrapped, without the yaw noise).
  double integrated_yaw() const { return yaw_; }

 private:
  ImuConfig config_;
  Rng rng_;
  double yaw_ = 0.0;
};

// The reading as the unit's driver publishes it on `stream`: the measured rate about the sensor's z
// (mounted level at the base's origin) and the integrated heading.
ImuMessage imu_message(const ImuModel::ImuReading& reading, const std::string& stream);

}  // namespace starnav
