// The particle filter under AMCL: the KLD bound against its formula and against chi-square
// quantiles (computed here from the regularized incomplete gamma function), resampling counts
// and unbiasedness, the recovery averages and injection, clusters on hand-made sets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/estimate/particle_filter.hpp"

namespace starnav {
namespace {

// Regularized lower incomplete gamma P(a, x): series below a + 1, Lentz's continued fraction
// for Q = 1 - P above (Numerical Recipes 6.2).
double pf_test_gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_front = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_front);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_front) * h;
}

// The p-quantile of chi-square with `dof` degrees of freedom, by bisection.
double pf_test_chi2_quantile(double dof, double p) {
  double lo = 0.0, hi = dof + 20.0 * std::sqrt(2.0 * dof) + 50.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (pf_test_gamma_p(0.5 * dof, 0.5 * mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double pf_test_normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

TEST(KldLimit, MatchesPfFormulaAndClamps) {
  const double err = 0.05, z = 0.99;
  for (const int k : {2, 3, 10, 57, 400, 3000}) {
    const double a = 2.0 / (9.0 * (k - 1));
    const double x = 1.0 - a + std::sqrt(a) * z;
    const int n = static_cast<int>(std::ceil((k - 1) / (2 * err) * x * x * x));
    EXPECT_EQ(kld_limit(k, err, z, 1, 1'000'000), n) << k;
    EXPECT_EQ(kld_limit(k, err, z, n + 5, 1'000'000), n + 5) << k;
    EXPECT_EQ(kld_limit(k, err, z, 1, n - 3), n - 3) << k;
  }
  EXPECT_EQ(kld_limit(1, err, z, 10, 2000), 2000);  // one bin: max (pf.c)
  EXPECT_EQ(kld_limit(0, err, z, 10, 2000), 2000);
  EXPECT_EQ(kld_limit(2'000'000'000, err, z, 10, 2000), 2000);  // no overflow
}

// n = chi^2_{k-1}(1 - delta) / (2 err) (Fox 2003), of which the pf.c formula is the
// Wilson-Hilferty approximation: within 1 % for k >= 10. With Nav2's pf_z = 0.99 used as z, the
// bound is the chi-square quantile at Phi(0.99) = 0.839.
TEST(KldLimit, MatchesChiSquareQuantiles) {
  const double err = 0.05;
  const double z99 = 2.3263478740408408;  // Phi^-1(0.99)
  for (const int k : {10, 20, 50, 100, 500, 2000}) {
    const double exact99 = pf_test_chi2_quantile(k - 1, 0.99) / (2 * err);
    EXPECT_NEAR(kld_limit(k, err, z99, 1, 100'000'000) / exact99, 1.0, 0.01) << k;
    const double exact_nav2 = pf_test_chi2_quantile(k - 1, pf_test_normal_cdf(0.99)) / (2 * err);
    EXPECT_NEAR(kld_limit(k, err, 0.99, 1, 100'000'000) / exact_nav2, 1.0, 0.01) << k;
  }
  // The chi-square quantile itself against a table value: chi^2_10(0.95) = 18.307.
  EXPECT_NEAR(pf_test_chi2_quantile(10, 0.95), 18.307, 1e-3);
}

std::vector<double> pf_test_weights(std::size_t m, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<double> w(m);
  for (double& x : w) x = std::pow(rng.uniform(), 3.0) + 1e-3;
  return w;
}

TEST(ParticleResample, SystematicCountsAreFloorOrCeil) {
  for (const std::size_t n : {50u, 137u, 1000u}) {
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      const std::vector<double> w = pf_test_weights(50, seed);
      double total = 0.0;
      for (const double x : w) total += x;
      Rng rng(seed + 100);
      const std::vector<std::int32_t> idx = systematic_resample(w, n, rng);
      ASSERT_EQ(idx.size(), n);
      std::vector<int> count(w.size(), 0);
      for (const std::int32_t i : idx) ++count[static_cast<std::size_t>(i)];
      for (std::size_t i = 0; i < w.size(); ++i) {
        const double e = static_cast<double>(n) * w[i] / total;
        EXPECT_TRUE(count[i] == std::floor(e) || count[i] == std::ceil(e)) << n << " " << seed << " " << i;
      }
    }
  }
}

// Over many repetitions the counts add up to R n w (chi-square goodness of fit).
double pf_test_chi2_of_counts(bool systematic, std::size_t m, std::size_t n, int repeats, std::uint64_t seed) {
  const std::vector<double> w = pf_test_weights(m, seed);
  double total = 0.0;
  for (const double x : w) total += x;
  std::vector<double> count(m, 0.0);
  Rng rng(seed + 1);
  for (int r = 0; r < repeats; ++r) {
    const std::vector<std::int32_t> idx = systematic ? systematic_resample(w, n, rng) : multinomial_resample(w, n, rng);
    for (const std::int32_t i : idx) count[static_cast<std::size_t>(i)] += 1.0;
  }
  double chi2 = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    const double e = repeats * static_cast<double>(n) * w[i] / total;
    chi2 += (count[i] - e) * (count[i] - e) / e;
  }
  return chi2;
}

TEST(ParticleResample, DrawsAreUnbiased) {
  const std::size_t m = 20;
  const double upper = pf_test_chi2_quantile(m - 1, 0.999), lower = pf_test_chi2_quantile(m - 1, 0.001);
  // Multinomial: the statistic follows chi^2_{m-1}.
  const double multinomial = pf_test_chi2_of_counts(false, m, 100, 2000, 3);
  EXPECT_LT(multinomial, upper);
  EXPECT_GT(multinomial, lower);
  // Systematic draws vary less than multinomial ones, so only the upper bound applies.
  EXPECT_LT(pf_test_chi2_of_counts(true, m, 100, 2000, 4), upper);
}

TEST(ParticleResample, EffectiveSampleSize) {
  EXPECT_DOUBLE_EQ(effective_sample_size(std::vector<double>(8, 0.125)), 8.0);
  EXPECT_DOUBLE_EQ(effective_sample_size(std::vector<double>{0.0, 1.0, 0.0}), 1.0);
  EXPECT_DOUBLE_EQ(effective_sample_size(std::vector<double>{1.0, 1.0, 2.0}), 16.0 / 6.0);
}

// Ten particles in three KLD bins (their x 0.1 ... 1.4 m, bins of 0.5 m): no bound for k <= 3
// exceeds min_particles = 50, so every resampling keeps exactly 50 of the 1000 systematic draws,
// taken in a random order; each particle's mean count must be 50 w.
TEST(ParticleFilter, KldSubsetOfSystematicDrawsIsUnbiased) {
  ParticleFilterConfig c;
  c.min_particles = 50;
  c.max_particles = 1000;
  const std::vector<double> xs = {0.1, 0.2, 0.3, 0.6, 0.7, 0.8, 1.1, 1.2, 1.3, 1.4};
  std::vector<Pose2> poses;
  for (const double x : xs) poses.emplace_back(x, 0.1, 0.05);
  std::vector<double> p = pf_test_weights(xs.size(), 9);
  double total = 0.0;
  for (const double x : p) total += x;
  ASSERT_LT(kld_limit(3, c.pf_err, c.pf_z, 1, 100000), 50);
  const int repeats = 3000;
  std::vector<double> count(xs.size(), 0.0);
  Rng rng(10);
  ParticleFilter f(c);
  for (int r = 0; r < repeats; ++r) {
    f.set_particles(poses);
    f.weigh(p);
    const ResampleResult res = f.resample(rng, {});
    ASSERT_EQ(res.particles, 50);
    for (const Pose2& q : f.poses())
      for (std::size_t i = 0; i < xs.size(); ++i)
        if (q.x == xs[i]) count[i] += 1.0;
  }
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double w = p[i] / total;
    const double sd = std::sqrt(50.0 * w * (1 - w) / repeats);
    EXPECT_NEAR(count[i] / repeats, 50.0 * w, 4.0 * sd + 1e-9) << i;
  }
}

// 5,000 poses uniform over a 1 m square and every heading, for 100-5,000 particles: a set whose
// KLD limit lies strictly between the two.
ParticleFilterConfig pf_test_square_config() {
  ParticleFilterConfig c;
  c.min_particles = 100;
  c.max_particles = 5000;
  return c;
}

std::vector<Pose2> pf_test_square_poses(Rng& rng) {
  std::vector<Pose2> poses(5000);
  for (Pose2& q : poses) q = Pose2(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0), rng.uniform(-kPi, kPi));
  return poses;
}

TEST(ParticleFilter, ResamplingStopsAtTheKldLimit) {
  const ParticleFilterConfig c = pf_test_square_config();
  Rng rng(12);
  const std::vector<Pose2> poses = pf_test_square_poses(rng);
  ParticleFilter f(c);
  f.set_particles(poses);
  const ResampleResult r = f.resample(rng, {});
  EXPECT_EQ(r.bins, occupied_bins(f.poses(), c.bins));
  EXPECT_EQ(r.particles, kld_limit(r.bins, c.pf_err, c.pf_z, c.min_particles, c.max_particles));
  EXPECT_GT(r.particles, c.min_particles);
  EXPECT_LT(r.particles, c.max_particles);
  for (const double w : f.weights()) EXPECT_DOUBLE_EQ(w, 1.0 / r.particles);
  // One bin: the limit is max_particles.
  f.set_particles(std::vector<Pose2>(10, Pose2(0.1, 0.1, 0.0)));
  EXPECT_EQ(f.resample(rng, {}).particles, c.max_particles);
}

// A floor on the count (AMCL's search phase holds max_particles): KLD stops no earlier.
TEST(ParticleFilter, ResamplingHonoursAFloorOnTheCount) {
  const ParticleFilterConfig c = pf_test_square_config();
  Rng rng(13);
  const std::vector<Pose2> poses = pf_test_square_poses(rng);
  ParticleFilter f(c);
  f.set_particles(poses);
  const int kld = f.resample(rng, {}).particles;
  ASSERT_LT(kld, 4000);
  f.set_particles(poses);
  EXPECT_EQ(f.resample(rng, {}, 4000).particles, 4000);
  f.set_particles(poses);
  EXPECT_EQ(f.resample(rng, {}, 1).particles, kld_limit(occupied_bins(f.poses(), c.bins), c.pf_err, c.pf_z, 100, 5000));
}

// -------------------------------------------------------------------------------------------
// Recovery

TEST(ParticleRecovery, AveragesFollowTheRecursion) {
  RecoveryAverages a;
  a.alpha_slow = 0.1;
  a.alpha_fast = 0.5;
  a.update(2.0);  // from 0: taken as is
  EXPECT_EQ(a.w_slow, 2.0);
  EXPECT_EQ(a.w_fast, 2.0);
  EXPECT_EQ(a.injection_probability(), 0.0);
  a.update(1.0);
  EXPECT_DOUBLE_EQ(a.w_slow, 1.9);
  EXPECT_DOUBLE_EQ(a.w_fast, 1.5);
  EXPECT_DOUBLE_EQ(a.injection_probability(), 1.0 - 1.5 / 1.9);
  a.update(4.0);
  EXPECT_DOUBLE_EQ(a.w_slow, 2.11);
  EXPECT_DOUBLE_EQ(a.w_fast, 2.75);
  EXPECT_EQ(a.injection_probability(), 0.0);  // fast above slow
  a.reset();
  EXPECT_EQ(a.injection_probability(), 0.0);
}

ParticleFilterConfig pf_test_recovery_config(double slow, double fast) {
  ParticleFilterConfig c;
  c.min_particles = c.max_particles = 1000;
  c.alpha_slow = slow;
  c.alpha_fast = fast;
  return c;
}

// Scripted likelihoods: 5 then 1 for every particle. w_slow = 5 + 0.01 (1 - 5) = 4.96, w_fast =
// 5 + 0.5 (1 - 5) = 3, so w_diff = 1 - 3 / 4.96; the injected count is binomial.
TEST(ParticleRecovery, InjectsExactlyWhenTheAveragesSaySo) {
  ParticleFilter f(pf_test_recovery_config(0.01, 0.5));
  f.set_particles(std::vector<Pose2>(1000, Pose2(1.0, 1.0, 0.0)));
  const RandomPoseFn marker = [](Rng& r) { return Pose2(100.0 + r.uniform(), 0.0, 0.0); };
  Rng rng(13);
  f.weigh(std::vector<double>(1000, 5.0));
  EXPECT_EQ(f.injection_probability(), 0.0);
  ResampleResult r = f.resample(rng, marker);
  EXPECT_EQ(r.injected, 0);
  f.weigh(std::vector<double>(1000, 1.0));
  const double w_diff = 1.0 - 3.0 / 4.96;
  EXPECT_NEAR(f.recovery().w_slow, 4.96, 1e-12);
  EXPECT_NEAR(f.recovery().w_fast, 3.0, 1e-12);
  EXPECT_NEAR(f.injection_probability(), w_diff, 1e-12);
  r = f.resample(rng, marker);
  EXPECT_NEAR(r.w_diff, w_diff, 1e-12);
  int markers = 0;
  for (const Pose2& p : f.poses()) markers += p.x >= 100.0;
  EXPECT_EQ(markers, r.injected);
  EXPECT_NEAR(r.injected, 1000 * w_diff, 4.0 * std::sqrt(1000 * w_diff * (1 - w_diff)));
  // Default reset after injecting: w_fast := w_slow; the slow average remembers, so a second
  // update that explains as little injects again: 1 - (4.96 + 0.5 (1 - 4.96)) / (4.96 + 0.01 (1 - 4.96)).
  EXPECT_NEAR(f.recovery().w_slow, 4.96, 1e-12);
  EXPECT_NEAR(f.recovery().w_fast, 4.96, 1e-12);
  f.weigh(std::vector<double>(1000, 1.0));
  EXPECT_NEAR(f.injection_probability(), 1.0 - 2.98 / 4.9204, 1e-12);
}

// Nav2's reset: both averages to 0, the next update starts them afresh and nothing is injected.
TEST(ParticleRecovery, Nav2ResetZeroesBothAverages) {
  ParticleFilterConfig c = pf_test_recovery_config(0.01, 0.5);
  c.recovery_reset = RecoveryReset::Zero;
  ParticleFilter f(c);
  f.set_particles(std::vector<Pose2>(1000, Pose2(1.0, 1.0, 0.0)));
  Rng rng(15);
  f.weigh(std::vector<double>(1000, 5.0));
  f.weigh(std::vector<double>(1000, 1.0));
  EXPECT_GT(f.resample(rng, [](Rng&) { return Pose2(100.0, 0.0, 0.0); }).injected, 0);
  EXPECT_EQ(f.recovery().w_slow, 0.0);
  EXPECT_EQ(f.recovery().w_fast, 0.0);
  f.weigh(std::vector<double>(1000, 1.0));
  EXPECT_EQ(f.injection_probability(), 0.0);
}

TEST(ParticleRecovery, NoInjectionWithZeroAlphasOrRisingLikelihood) {
  const RandomPoseFn marker = [](Rng&) { return Pose2(100.0, 0.0, 0.0); };
  Rng rng(14);
  {
    ParticleFilter f(pf_test_recovery_config(0.0, 0.0));
    f.set_particles(std::vector<Pose2>(1000, Pose2()));
    for (const double p : {5.0, 1.0, 0.2, 3.0}) {
      f.weigh(std::vector<double>(1000, p));
      EXPECT_EQ(f.injection_probability(), 0.0);
      EXPECT_EQ(f.resample(rng, marker).injected, 0);
    }
  }
  {
    ParticleFilter f(pf_test_recovery_config(0.001, 0.1));
    f.set_particles(std::vector<Pose2>(1000, Pose2()));
    for (const double p : {1.0, 2.0, 3.0, 4.0}) {
      f.weigh(std::vector<double>(1000, p));
      EXPECT_EQ(f.injection_probability(), 0.0);
      EXPECT_EQ(f.resample(rng, marker).injected, 0);
    }
  }
}

// The average likelihood is sum_i w_i p_i: the same for 100 and for 5000 particles with the
// same likelihoods (alphas 1, so the averages show the latest value).
TEST(ParticleRecovery, AverageDoesNotDependOnParticleCount) {
  for (const int n : {100, 5000}) {
    ParticleFilterConfig c;
    c.min_particles = 1;
    c.max_particles = n;
    c.alpha_slow = c.alpha_fast = 1.0;
    ParticleFilter f(c);
    f.set_particles(std::vector<Pose2>(static_cast<std::size_t>(n), Pose2()));
    std::vector<double> p(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) p[static_cast<std::size_t>(i)] = i % 4 == 0 ? 9.0 : 1.0;  // mean 3
    f.weigh(p);
    EXPECT_NEAR(f.recovery().w_slow, 3.0, 1e-12) << n;
    // Now the prior weights are 3/n and 1/(3n): sum w p = (n/4)(3/n)9 + (3n/4)(1/(3n)) = 7.
    f.weigh(p);
    EXPECT_NEAR(f.recovery().w_fast, 7.0, 1e-12) << n;
    EXPECT_NEAR(f.recovery().w_slow, 7.0, 1e-12) << n;
  }
}

// Selective resampling waits for N_eff < N / 2, except while recovery wants to inject: after a
// kidnap the weights are flat and N_eff stays near N.
TEST(ParticleRecovery, SelectiveResamplingStillInjects) {
  ParticleFilterConfig c = pf_test_recovery_config(0.01, 0.5);
  c.selective_resampling = true;
  ParticleFilter f(c);
  f.set_particles(std::vector<Pose2>(1000, Pose2()));
  f.weigh(std::vector<double>(1000, 5.0));
  EXPECT_FALSE(f.wants_resample());  // flat weights, nothing to inject
  f.weigh(std::vector<double>(1000, 1.0));
  EXPECT_GT(f.injection_probability(), 0.0);
  EXPECT_TRUE(f.wants_resample());
  // Without selective resampling it always resamples; with it, an uneven set is resampled.
  ParticleFilter g(pf_test_recovery_config(0.0, 0.0));
  g.set_particles(std::vector<Pose2>(1000, Pose2()));
  EXPECT_TRUE(g.wants_resample());
  c.alpha_slow = c.alpha_fast = 0.0;
  ParticleFilter h(c);
  h.set_particles(std::vector<Pose2>(1000, Pose2()));
  std::vector<double> p(1000, 1e-6);
  p[0] = 1.0;
  h.weigh(p);
  EXPECT_TRUE(h.wants_resample());
}

// -------------------------------------------------------------------------------------------
// Clusters

TEST(ParticleCluster, TwoGroupsByHand) {
  // Group A: three particles in one bin; group B: two particles far away.
  const std::vector<Pose2> poses = {Pose2(0.1, 0.1, 0.1), Pose2(0.3, 0.2, 0.0), Pose2(0.2, 0.4, 0.05),
                                    Pose2(5.1, 5.1, 1.0), Pose2(5.2, 5.3, 1.02)};
  const std::vector<double> w = {0.2, 0.3, 0.1, 0.25, 0.15};
  const std::vector<ParticleCluster> c = cluster_particles(poses, w, KldBins{});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].weight, 0.6, 1e-15);
  EXPECT_EQ(c[0].count, 3);
  EXPECT_NEAR(c[1].weight, 0.4, 1e-15);
  const double mx = (0.2 * 0.1 + 0.3 * 0.3 + 0.1 * 0.2) / 0.6, my = (0.2 * 0.1 + 0.3 * 0.2 + 0.1 * 0.4) / 0.6;
  EXPECT_NEAR(c[0].mean.x, mx, 1e-15);
  EXPECT_NEAR(c[0].mean.y, my, 1e-15);
  const double cxx = (0.2 * (0.1 - mx) * (0.1 - mx) + 0.3 * (0.3 - mx) * (0.3 - mx) + 0.1 * (0.2 - mx) * (0.2 - mx)) / 0.6;
  const double cxy = (0.2 * (0.1 - mx) * (0.1 - my) + 0.3 * (0.3 - mx) * (0.2 - my) + 0.1 * (0.2 - mx) * (0.4 - my)) / 0.6;
  EXPECT_NEAR(c[0].covariance(0, 0), cxx, 1e-15);
  EXPECT_NEAR(c[0].covariance(0, 1), cxy, 1e-15);
  EXPECT_NEAR(c[0].covariance(1, 0), cxy, 1e-15);
  const double s = 0.2 * std::sin(0.1) + 0.1 * std::sin(0.05), co = 0.2 * std::cos(0.1) + 0.3 + 0.1 * std::cos(0.05);
  EXPECT_NEAR(c[0].mean.yaw, std::atan2(s, co), 1e-15);
  EXPECT_NEAR(c[0].covariance(2, 2), -2.0 * std::log(std::hypot(s, co) / 0.6), 1e-12);
  EXPECT_EQ(c[0].covariance(0, 2), 0.0);
  EXPECT_NEAR(c[1].mean.x, (0.25 * 5.1 + 0.15 * 5.2) / 0.4, 1e-14);
}

// One hypothesis across +-pi is one cluster (the yaw bins wrap) with mean pi, and its yaw
// variance is the circular one of the cluster alone (divided by its weight).
TEST(ParticleCluster, YawAcrossPi) {
  const std::vector<Pose2> poses = {Pose2(1.1, 1.1, kPi - 0.05), Pose2(1.2, 1.1, -kPi + 0.05),
                                    Pose2(-3.0, 2.0, 0.0)};
  const std::vector<double> w = {0.35, 0.35, 0.3};
  const std::vector<ParticleCluster> c = cluster_particles(poses, w, KldBins{});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].weight, 0.7, 1e-15);
  EXPECT_EQ(c[0].count, 2);
  EXPECT_NEAR(angle_diff(c[0].mean.yaw, kPi), 0.0, 1e-12);
  EXPECT_NEAR(c[0].covariance(2, 2), -2.0 * std::log(std::cos(0.05)), 1e-12);
  EXPECT_NEAR(c[0].mean.x, 1.15, 1e-15);
}

TEST(ParticleCluster, DiagonalNeighboursJoinAndGapsSplit) {
  const KldBins b;
  const double a = b.yaw_rad;
  // Bins (0,0,k) and (1,1,k+1): neighbours on all three axes at once.
  std::vector<Pose2> poses = {Pose2(0.25, 0.25, -kPi + 0.5 * a), Pose2(0.75, 0.75, -kPi + 1.5 * a)};
  std::vector<double> w = {0.5, 0.5};
  EXPECT_EQ(cluster_particles(poses, w, b).size(), 1u);
  // Two x bins apart: separate.
  poses[1].x = 1.25;
  EXPECT_EQ(cluster_particles(poses, w, b).size(), 2u);
  // Two yaw bins apart: separate.
  poses[1] = Pose2(0.25, 0.25, -kPi + 2.5 * a);
  EXPECT_EQ(cluster_particles(poses, w, b).size(), 2u);
  // Negative coordinates: bins -1 and 0 touch.
  poses = {Pose2(-0.1, -0.1, 0.0), Pose2(0.1, 0.1, 0.0)};
  EXPECT_EQ(cluster_particles(poses, w, b).size(), 1u);
  EXPECT_EQ(occupied_bins(poses, b), 2);
  EXPECT_EQ(b.yaw_bins(), 36);
}

TEST(ParticleFilter, RejectsImpossibleConfigurations) {
  const auto field_of = [](ParticleFilterConfig c) {
    try {
      ParticleFilter f(c);
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("accepted");
  };
  ParticleFilterConfig c;
  c.min_particles = 0;
  EXPECT_EQ(field_of(c), "amcl.min_particles");
  c = {};
  c.max_particles = 10;
  EXPECT_EQ(field_of(c), "amcl.max_particles");
  c = {};
  c.pf_err = 0.0;
  EXPECT_EQ(field_of(c), "amcl.pf_err");
  c = {};
  c.bins.yaw_rad = -1.0;
  EXPECT_EQ(field_of(c), "amcl.kld_bin_yaw_rad");
  c = {};
  c.alpha_fast = 1.5;
  EXPECT_EQ(field_of(c), "amcl.recovery_alpha_fast");
}

}  // namespace
}  // namespace starnav
