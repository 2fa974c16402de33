#pragma once
// The particle filter under AMCL (Nav2 pf.c, after Player's amcl; Fox 2003 for KLD sampling;
// Probabilistic Robotics Table 8.3 for the recovery averages): a weighted set of planar poses,
// KLD-adaptive resampling with low-variance (systematic) or multinomial draws, injection of
// random poses driven by short- and long-term likelihood averages, and clusters of the particles
// in the KLD histogram's bins.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "starnav/core/angle.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"

namespace starnav {

// The histogram bins of KLD sampling and clustering: x, y and yaw cells (Nav2: 0.5 m, 0.5 m,
// 10 deg). Yaw bins cover (-pi, pi] from -pi and wrap (Nav2 does not wrap, so one pose
// hypothesis across +-pi made two clusters there); the last bin is narrower when 2 pi is not a
// multiple of the bin.
struct KldBins {
  double xy_m = 0.5;
  double yaw_rad = deg_to_rad(10.0);
  int yaw_bins() const;
  // Throws Error (field "amcl.kld_bin_xy_m" / "amcl.kld_bin_yaw_rad") for a non-positive or
  // non-finite size, or one too small for the packed bin keys.
  void validate() const;
};

// The KLD sample-count bound for k occupied bins (pf.c pf_resample_limit, Fox 2003 eq. 13):
//   n = ceil((k - 1) / (2 err) * (1 - 2 / (9 (k - 1)) + sqrt(2 / (9 (k - 1))) z)^3),
// clamped to [min, max]; max when k <= 1. `z` is the upper standard normal quantile of the
// bound's confidence 1 - delta. Nav2 passes its parameter pf_z (default 0.99) here as z itself,
// which is the quantile of a confidence of Phi(0.99) = 0.839, not of 0.99 (z = 2.326); starnav
// keeps Nav2's behaviour, so the same pf_z gives the same particle counts.
int kld_limit(int k, double pf_err, double pf_z, int min_particles, int max_particles);

// Resampling draws: `n` indices into `weights` (normalised or not; non-negative, positive sum).
// Systematic (low variance, Probabilistic Robotics Table 4.4): one uniform offset, n evenly
// spaced pointers; each index is drawn floor(n w) or ceil(n w) times (w normalised), in
// increasing order. Multinomial: n independent draws.
std::vector<std::int32_t> systematic_resample(std::span<const double> weights, std::size_t n, Rng& rng);
std::vector<std::int32_t> multinomial_resample(std::span<const double> weights, std::size_t n, Rng& rng);

// sum(w)^2 / sum(w^2): the effective sample size.
double effective_sample_size(std::span<const double> weights);

// What the recovery averages do after a resampling that injected random poses.
//  Zero (pf.c): both go back to 0, so the next update sets both to the same value and the
//    injection stops; after a kidnap this leaves one round of about alpha_fast (1 - w_kidnapped /
//    w_tracking) of the set (a few per cent), and the filter relocalizes only if that round
//    happens to land near the truth.
//  FastToSlow: w_fast := w_slow. The long-term average keeps its memory of how well the filter
//    used to explain the scans, so while it stays lost each update injects about that share
//    again, and the injection cannot compound (without any reset, random particles pull w_fast
//    down further and the set dissolves into noise: Nav2's flat likelihood gives a well placed
//    particle only about 5 times the weight of a random one).
enum class RecoveryReset : std::uint8_t { Zero, FastToSlow };

// The short- and long-term averages of the measurement likelihood (Augmented MCL). The
// injection probability is max(0, 1 - w_fast / w_slow). An average at 0 (start, or after a
// reset to zero) takes the next value as it is (pf.c), so with both alphas 0 the two stay equal
// and nothing is ever injected.
struct RecoveryAverages {
  double alpha_slow = 0.0;
  double alpha_fast = 0.0;
  double w_slow = 0.0;
  double w_fast = 0.0;

  void update(double w_avg);
  double injection_probability() const;
  void reset() { w_slow = w_fast = 0.0; }
  void after_injection(RecoveryReset how);
};

// One cluster: connected occupied bins (26-neighbourhood, yaw bins wrapping). The weight is the
// sum of its particles' (normalised) weights; the mean has the circular mean yaw; the covariance
// has the weighted x-y covariance about the mean and the circular variance -2 ln R of yaw, with
// R the length of the weighted mean unit vector divided by the cluster's weight (Nav2 leaves the
// weight out, which inflates light clusters' yaw variance). Cross terms with yaw are 0, as Nav2.
struct ParticleCluster {
  double weight = 0.0;
  int count = 0;
  Pose2 mean;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// The clusters of a weighted particle set, heaviest first (ties: the cluster met first).
std::vector<ParticleCluster> cluster_particles(std::span<const Pose2> poses, std::span<const double> weights,
                                               const KldBins& bins);

// The number of distinct bins the poses occupy.
int occupied_bins(std::span<const Pose2> poses, const KldBins& bins);

enum class Resampler : std::uint8_t { LowVariance, Multinomial };

struct ParticleFilterConfig {
  int min_particles = 500;
  int max_particles = 2000;
  double pf_err = 0.05;
  double pf_z = 0.99;
  KldBins bins;
  Resampler resampler = Resampler::LowVariance;
  double alpha_slow = 0.0;  // recovery_alpha_slow
  double alpha_fast = 0.0;  // recovery_alpha_fast
  bool selective_resampling = false;  // resample only when N_eff < N / 2 (unless injecting)
  RecoveryReset recovery_reset = RecoveryReset::FastToSlow;
  // Throws Error naming the field ("amcl.min_particles", ...).
  void validate() const;
};

struct ResampleResult {
  bool resampled = false;
  int particles = 0;      // after resampling
  int injected = 0;       // random poses among them
  int bins = 0;           // occupied KLD bins of the new set
  double w_diff = 0.0;    // the injection probability used
};

// A random pose for injection (uniform over free space for AMCL).
using RandomPoseFn = std::function<Pose2(Rng&)>;

class ParticleFilter {
 public:
  explicit ParticleFilter(const ParticleFilterConfig& config);

  const ParticleFilterConfig& config() const { return config_; }
  // Replaces the set (uniform weights) and resets the recovery averages (pf_init).
  void set_particles(std::vector<Pose2> poses);

  std::size_t size() const { return poses_.size(); }
  std::span<Pose2> poses() { return poses_; }
  std::span<const Pose2> poses() const { return poses_; }
  std::span<const double> weights() const { return weights_; }

  // The measurement update: weights times the likelihoods, normalised. The recovery averages
  // take w_avg = sum_i w_i p_i with w the normalised weights before the update: the expected
  // likelihood under the prior, which does not depend on the particle count (Nav2 averages the
  // unnormalised products over the particles, which shrinks as 1/N, so a KLD change of N alone
  // moved its averages). A zero or non-finite total resets the weights to uniform and leaves
  // the averages alone.
  void weigh(std::span<const double> likelihoods);

  double effective_sample_size() const { return starnav::effective_sample_size(weights_); }
  double injection_probability() const { return recovery_.injection_probability(); }
  const RecoveryAverages& recovery() const { return recovery_; }
  // True when the set should be resampled now: always without selective resampling; with it,
  // when N_eff < N / 2; and in any case while the injection probability is positive (with flat
  // weights after a kidnap, N_eff stays near N and selective resampling alone would never let
  // the recovery inject).
  bool wants_resample() const;

  // KLD-adaptive resampling: max_particles draws (systematic or multinomial) visited in a random
  // order (a random subset of an unbiased draw is unbiased; KLD's stopping point depends weakly
  // on what was drawn, as in Nav2), each replaced with probability
  // w_diff by random_pose(rng) (when given), until the count reaches the KLD limit of the bins
  // occupied so far. Weights become uniform; after an injection the averages are reset as
  // recovery_reset says.
  // `at_least` raises the count KLD may stop at (up to max_particles).
  ResampleResult resample(Rng& rng, const RandomPoseFn& random_pose, int at_least = 0);

 private:
  ParticleFilterConfig config_;
  std::vector<Pose2> poses_;
  std::vector<double> weights_;
  RecoveryAverages recovery_;
  std::vector<Pose2> scratch_;
};

}  // namespace starnav
