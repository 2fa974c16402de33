// IMU and wheel encoders: sample statistics against the configured bias and noise, yaw drift
// bias * t, quantisation within one tick, determinism by seed, bad configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/sense/bumper.hpp"
#include "starnav/sense/imu.hpp"
#include "starnav/sense/wheel_encoders.hpp"

using namespace starnav;

TEST(Imu, RateMeanAndVarianceMatchBiasAndSigma) {
  ImuConfig c;
  c.yaw_rate_bias_radps = 0.01;
  c.yaw_rate_noise_sigma_radps = 0.05;
  ImuModel imu(c, Rng(42));
  const int n = 200000;
  const double true_rate = 0.3;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double e = imu.sample(i * 0.01, true_rate, 0.01).yaw_rate_radps - true_rate;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  // Standard errors: sigma / sqrt(n) = 1.1e-4 for the mean, sigma^2 sqrt(2/n) = 7.9e-6 for the variance.
  EXPECT_NEAR(mean, c.yaw_rate_bias_radps, 5e-4);
  EXPECT_NEAR(var, c.yaw_rate_noise_sigma_radps * c.yaw_rate_noise_sigma_radps, 4e-5);
}

TEST(Imu, YawIntegratesTheMeasuredRateAndDriftsByBiasTimesT) {
  ImuConfig c;
  c.yaw_rate_noise_sigma_radps = 0.0;
  c.yaw_rate_bias_radps = 0.002;
  ImuModel imu(c, Rng(1), 0.5);
  const double dt = 0.01, rate = 0.1;
  ImuModel::ImuReading r;
  for (int i = 1; i <= 1000; ++i) r = imu.sample(i * dt, rate, dt);
  const double t = 10.0;
  EXPECT_NEAR(imu.integrated_yaw(), 0.5 + (rate + c.yaw_rate_bias_radps) * t, 1e-12);
  EXPECT_NEAR(r.yaw_rad, wrap_angle(0.5 + rate * t + c.yaw_rate_bias_radps * t), 1e-12);
  EXPECT_NEAR(r.t_s, t, 1e-12);

  // With noise the drift is a random walk around bias * t: over many runs the mean end yaw error
  // is bias * t and its variance sigma^2 dt t.
  c.yaw_rate_noise_sigma_radps = 0.01;
  const int runs = 400;
  double sum = 0.0, sum2 = 0.0;
  Rng seeds(9);
  for (int k = 0; k < runs; ++k) {
    ImuModel m(c, Rng(seeds.next()));
    for (int i = 1; i <= 1000; ++i) m.sample(i * dt, 0.0, dt);
    sum += m.integrated_yaw();
    sum2 += m.integrated_yaw() * m.integrated_yaw();
  }
  const double mean = sum / runs, var = sum2 / runs - mean * mean;
  const double expected_var = 0.01 * 0.01 * dt * t;  // 1e-5, std 3.2e-3
  EXPECT_NEAR(mean, c.yaw_rate_bias_radps * t, 4.0 * std::sqrt(expected_var / runs));
  EXPECT_NEAR(var, expected_var, 0.3 * expected_var);
}

TEST(Imu, DeterministicBySeedAndValidates) {
  ImuConfig c;
  c.yaw_noise_sigma_rad = 0.01;
  ImuModel a(c, Rng(5)), b(c, Rng(5)), other(c, Rng(6));
  bool differs = false;
  for (int i = 0; i < 100; ++i) {
    const auto ra = a.sample(i * 0.01, 0.2, 0.01), rb = b.sample(i * 0.01, 0.2, 0.01);
    const auto ro = other.sample(i * 0.01, 0.2, 0.01);
    EXPECT_EQ(ra.yaw_rate_radps, rb.yaw_rate_radps);
    EXPECT_EQ(ra.yaw_rad, rb.yaw_rad);
    differs = differs || ro.yaw_rad != ra.yaw_rad;
  }
  EXPECT_TRUE(differs);
  c.yaw_rate_noise_sigma_radps = -1.0;
  try {
    ImuModel bad(c, Rng(1));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "imu.yaw_rate_noise_sigma_radps");
  }
}

TEST(WheelEncoders, QuantisedCumulativeTicksWithinOneTick) {
  EncoderConfig c;
  c.ticks_per_rev = 360;
  WheelEncoders enc(4, c, Rng(3));
  Rng rng(17);
  std::vector<double> angles(4, 0.0);
  enc.sample(angles);  // the zero
  for (int i = 0; i < 2000; ++i) {
    for (double& a : angles) a += rng.uniform(-0.3, 0.5);
    const auto ticks = enc.sample(angles);
    for (std::size_t w = 0; w < 4; ++w) {
      // floor: the tick angle lies in (true - one tick, true].
      const double tick_angle = enc.ticks_to_rad(ticks[w]);
      EXPECT_LE(tick_angle, angles[w] + 1e-9);
      EXPECT_GT(tick_angle, angles[w] - 2.0 * kPi / c.ticks_per_rev - 1e-9);
      EXPECT_EQ(ticks[w], static_cast<std::int64_t>(std::floor(angles[w] * (c.ticks_per_rev / (2.0 * kPi)))))
          << "wheel " << w;
    }
  }
}

TEST(WheelEncoders, StartIsZeroAndOneRevolutionIsTicksPerRev) {
  EncoderConfig c;
  WheelEncoders enc(2, c, Rng(0));
  const double start[2] = {10.0, -3.0};
  const auto t0 = enc.sample(start);
  EXPECT_EQ(t0[0], 0);
  EXPECT_EQ(t0[1], 0);
  const double one_rev[2] = {10.0 + 2.0 * kPi + 1e-9, -3.0 - 2.0 * kPi - 1e-9};
  const auto t1 = enc.sample(one_rev);
  EXPECT_EQ(t1[0], c.ticks_per_rev);
  EXPECT_EQ(t1[1], -c.ticks_per_rev - 1);  // floor of a hair below -1024
}

TEST(WheelEncoders, SlipNoiseIsDeterministicBySeedAndUnbiased) {
  EncoderConfig c;
  c.slip_sigma = 0.05;
  c.ticks_per_rev = 100000;
  auto run = [&](std::uint64_t seed) {
    WheelEncoders enc(1, c, Rng(seed));
    double a = 0.0;
    std::vector<std::int64_t> out;
    enc.sample(std::span<const double>(&a, 1));
    for (int i = 0; i < 1000; ++i) {
      a += 0.1;
      out.push_back(enc.sample(std::span<const double>(&a, 1))[0]);
    }
    return out;
  };
  const auto a = run(8), b = run(8), d = run(9);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, d);
  // 1000 increments of 0.1 rad with 5 % slip each: total 100 rad, std 0.1 * 0.05 * sqrt(1000) = 0.16 rad.
  const double total = 2.0 * kPi * static_cast<double>(a.back()) / c.ticks_per_rev;
  EXPECT_NEAR(total, 100.0, 0.8);
  EXPECT_GT(std::abs(total - 100.0), 1e-4);  // slip did something
}

// A systematic error scales each wheel's count: floor((1 + e_i) * travel * ticks_per_rev / 2 pi)
// exactly, without slip; the other wheels unchanged.
TEST(WheelEncoders, ScaleErrorScalesEachWheelsCount) {
  EncoderConfig c;
  c.ticks_per_rev = 1000;
  c.scale_error = {0.02, -0.03, 0.0, 0.5};
  WheelEncoders e(4, c, Rng(2));
  const double zero[4] = {0.3, -0.2, 1.0, 0.0};
  (void)e.sample(zero);
  const double travel[4] = {10.0, -7.0, 3.0, 2.0};
  const double now[4] = {0.3 + travel[0], -0.2 + travel[1], 1.0 + travel[2], travel[3]};
  const std::vector<std::int64_t> ticks = e.sample(now);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto expected = static_cast<std::int64_t>(std::floor((1.0 + c.scale_error[i]) * travel[i] * 1000.0 / (2.0 * kPi)));
    EXPECT_NEAR(static_cast<double>(ticks[i]), static_cast<double>(expected), 1.0) << i;
    EXPECT_NEAR(e.ticks_to_rad(ticks[i]), (1.0 + c.scale_error[i]) * travel[i], 2.0 * kPi / 1000.0) << i;
  }
  // One value per wheel, each in [-0.5, 0.5].
  for (const std::vector<double>& bad : {std::vector<double>{0.1, 0.1}, std::vector<double>{0.0, 0.0, 0.0, 0.6}}) {
    EncoderConfig b;
    b.scale_error = bad;
    try {
      WheelEncoders w(4, b, Rng(1));
      FAIL();
    } catch (const Error& err) {
      EXPECT_EQ(err.field(), "encoders.scale_error");
    }
  }
}

TEST(WheelEncoders, BadInputNamesTheField) {
  EncoderConfig c;
  c.ticks_per_rev = 0;
  try {
    WheelEncoders e(4, c, Rng(1));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "encoders.ticks_per_rev");
  }
  WheelEncoders e(4, EncoderConfig{}, Rng(1));
  const double two[2] = {0.0, 0.0};
  EXPECT_THROW(e.sample(two), Error);
  const BumperReading bumper{1.5, true};
  EXPECT_TRUE(bumper.contact);
}
