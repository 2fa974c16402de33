#include "starnav/estimate/particle_filter.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

// Bin keys packed into 64 bits: x and y bin indices offset by 2^23 in 24 bits each (positions
// beyond +-2^23 bins clamp to the outermost bin), the yaw bin in 16 bits. The all-ones word is
// never a key (the yaw field stays below 2^16 - 1), so it marks empty slots.
constexpr int kAmclBinCoordBits = 24;
constexpr std::int64_t kAmclBinCoordOffset = std::int64_t{1} << (kAmclBinCoordBits - 1);
constexpr std::int64_t kAmclBinCoordMax = (std::int64_t{1} << kAmclBinCoordBits) - 1;
constexpr int kAmclMaxYawBins = (1 << 16) - 2;
constexpr std::uint64_t kAmclEmptyBin = ~std::uint64_t{0};

struct AmclBin {
  std::int64_t x = 0;  // offset, in [0, kAmclBinCoordMax]
  std::int64_t y = 0;
  int yaw = 0;
};

std::uint64_t amcl_pack_bin(const AmclBin& b) {
  return (static_cast<std::uint64_t>(b.x) << 40) | (static_cast<std::uint64_t>(b.y) << 16) |
         static_cast<std::uint64_t>(b.yaw);
}

AmclBin amcl_unpack_bin(std::uint64_t key) {
  return {static_cast<std::int64_t>(key >> 40), static_cast<std::int64_t>((key >> 16) & 0xFFFFFFu),
          static_cast<int>(key & 0xFFFFu)};
}

std::int64_t amcl_coord_bin(double v, double size) {
  double f = std::floor(v / size) + static_cast<double>(kAmclBinCoordOffset);
  if (!(f >= 0.0)) f = 0.0;  // also NaN
  if (f > static_cast<double>(kAmclBinCoordMax)) f = static_cast<double>(kAmclBinCoordMax);
  return static_cast<std::int64_t>(f);
}

AmclBin amcl_bin_of(const Pose2& p, const KldBins& bins, int yaw_bins) {
  AmclBin b;
  b.x = amcl_coord_bin(p.x, bins.xy_m);
  b.y = amcl_coord_bin(p.y, bins.xy_m);
  const double a = std::floor((wrap_angle(p.yaw) + kPi) / bins.yaw_rad);
  b.yaw = a >= 0.0 && a < yaw_bins ? static_cast<int>(a) : (a >= yaw_bins ? yaw_bins - 1 : 0);
  return b;
}

// An open-addressing map from bin keys to dense indices 0, 1, ... in order of insertion.
class AmclBinTable {
 public:
  // Room for `expected` distinct keys (at most half full, so probes stay short).
  void clear(std::size_t expected) {
    const std::size_t capacity = std::bit_ceil(std::max<std::size_t>(16, 2 * expected));
    shift_ = 64 - std::countr_zero(capacity);
    keys_.assign(capacity, kAmclEmptyBin);
    values_.resize(capacity);
    count_ = 0;
  }
  int insert(std::uint64_t key) {
    const std::size_t mask = keys_.size() - 1;
    for (std::size_t h = slot(key);; h = (h + 1) & mask) {
      if (keys_[h] == key) return values_[h];
      if (keys_[h] == kAmclEmptyBin) {
        keys_[h] = key;
        values_[h] = count_;
        return count_++;
      }
    }
  }
  int find(std::uint64_t key) const {
    const std::size_t mask = keys_.size() - 1;
    for (std::size_t h = slot(key);; h = (h + 1) & mask) {
      if (keys_[h] == key) return values_[h];
      if (keys_[h] == kAmclEmptyBin) return -1;
    }
  }
  int size() const { return count_; }

 private:
  std::size_t slot(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> values_;
  int shift_ = 60;
  int count_ = 0;
};

double amcl_weight_total(std::span<const double> weights) {
  double total = 0.0;
  for (const double w : weights) total += w;
  return total;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

int KldBins::yaw_bins() const {
  const double n = std::ceil(2.0 * kPi / yaw_rad - 1e-9);
  return n < 1.0 ? 1 : (n > kAmclMaxYawBins ? kAmclMaxYawBins : static_cast<int>(n));
}

void KldBins::validate() const {
  require_positive(xy_m, "amcl.kld_bin_xy_m");
  require_positive(yaw_rad, "amcl.kld_bin_yaw_rad");
  require(2.0 * kPi / yaw_rad <= kAmclMaxYawBins, "amcl.kld_bin_yaw_rad", "is too small (at most 65534 yaw bins)");
}

int kld_limit(int k, double pf_err, double pf_z, int min_particles, int max_particles) {
  if (k <= 1) return max_particles;
  const double a = 2.0 / (9.0 * (k - 1.0));
  const double x = 1.0 - a + std::sqrt(a) * pf_z;
  const double n = std::ceil((k - 1.0) / (2.0 * pf_err) * x * x * x);
  if (!(n >= min_particles)) return min_particles;  // also NaN
  if (n > max_particles) return max_particles;
  return static_cast<int>(n);
}

std::vector<std::int32_t> systematic_resample(std::span<const double> weights, std::size_t n, Rng& rng) {
  require(!weights.empty(), "weights", "cannot resample an empty set");
  const double total = amcl_weight_total(weights);
  require(total > 0.0 && std::isfinite(total), "weights", "must have a finite positive sum");
  std::vector<std::int32_t> out(n);
  const double step = total / static_cast<double>(n);
  const double u = rng.uniform() * step;
  const std::size_t last = weights.size() - 1;
  std::size_t i = 0;
  double c = weights[0];  // cumulative weight up to and including i
  for (std::size_t m = 0; m < n; ++m) {
    const double target = u + static_cast<double>(m) * step;
    while (target >= c && i < last) c += weights[++i];
    out[m] = static_cast<std::int32_t>(i);
  }
  return out;
}

std::vector<std::int32_t> multinomial_resample(std::span<const double> weights, std::size_t n, Rng& rng) {
  require(!weights.empty(), "weights", "cannot resample an empty set");
  std::vector<double> cumulative(weights.size());
  std::partial_sum(weights.begin(), weights.end(), cumulative.begin());
  const double total = cumulative.back();
  require(total > 0.0 && std::isfinite(total), "weights", "must have a finite positive sum");
  std::vector<std::int32_t> out(n);
  for (std::size_t m = 0; m < n; ++m) {
    const double r = rng.uniform() * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), r);
    out[m] = static_cast<std::int32_t>(std::min<std::ptrdiff_t>(it - cumulative.begin(),
                                                                 static_cast<std::ptrdiff_t>(weights.size()) - 1));
  }
  return out;
}

double effective_sample_size(std::span<const double> weights) {
  double s = 0.0, s2 = 0.0;
  for (const double w : weights) {
    s += w;
    s2 += w * w;
  }
  return s2 > 0.0 ? s * s / s2 : 0.0;
}

void RecoveryAverages::update(double w_avg) {
  w_slow = w_slow == 0.0 ? w_avg : w_slow + alpha_slow * (w_avg - w_slow);
  w_fast = w_fast == 0.0 ? w_avg : w_fast + alpha_fast * (w_avg - w_fast);
}

void RecoveryAverages::after_injection(RecoveryReset how) {
  if (how == RecoveryReset::Zero) reset();
  else w_fast = w_slow;
}

double RecoveryAverages::injection_probability() const {
  if (!(w_slow > 0.0)) return 0.0;
  return std::max(0.0, 1.0 - w_fast / w_slow);
}

int occupied_bins(std::span<const Pose2> poses, const KldBins& bins) {
  AmclBinTable table;
  table.clear(poses.size());
  const int nb = bins.yaw_bins();
  for (const Pose2& p : poses) table.insert(amcl_pack_bin(amcl_bin_of(p, bins, nb)));
  return table.size();
}

std::vector<ParticleCluster> cluster_particles(std::span<const Pose2> poses, std::span<const double> weights,
                                               const KldBins& bins) {
  require(poses.size() == weights.size(), "weights", "differ in size from the particles");
  std::vector<ParticleCluster> clusters;
  if (poses.empty()) return clusters;
  const int nb = bins.yaw_bins();
  AmclBinTable table;
  table.clear(poses.size());
  std::vector<std::int32_t> bin_of(poses.size());
  std::vector<std::uint64_t> keys;  // per dense bin index
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::uint64_t key = amcl_pack_bin(amcl_bin_of(poses[i], bins, nb));
    const int b = table.insert(key);
    if (b == static_cast<int>(keys.size())) keys.push_back(key);
    bin_of[i] = b;
  }

  // Connected components of the occupied bins.
  std::vector<std::int32_t> label(keys.size(), -1);
  std::vector<std::int32_t> stack;
  int cluster_count = 0;
  for (std::size_t start = 0; start < keys.size(); ++start) {
    if (label[start] >= 0) continue;
    label[start] = cluster_count;
    stack.assign(1, static_cast<std::int32_t>(start));
    while (!stack.empty()) {
      const AmclBin b = amcl_unpack_bin(keys[static_cast<std::size_t>(stack.back())]);
      stack.pop_back();
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int da = -1; da <= 1; ++da) {
            if (dx == 0 && dy == 0 && da == 0) continue;
            AmclBin n{b.x + dx, b.y + dy, ((b.yaw + da) % nb + nb) % nb};
            if (n.x < 0 || n.y < 0 || n.x > kAmclBinCoordMax || n.y > kAmclBinCoordMax) continue;
            const int j = table.find(amcl_pack_bin(n));
            if (j < 0 || label[static_cast<std::size_t>(j)] >= 0) continue;
            label[static_cast<std::size_t>(j)] = cluster_count;
            stack.push_back(j);
          }
    }
    ++cluster_count;
  }

  const double total = amcl_weight_total(weights);
  // A set without weight (all zero) is treated as uniform.
  const bool uniform = !(total > 0.0) || !std::isfinite(total);
  struct Sums {
    double w = 0.0, x = 0.0, y = 0.0, c = 0.0, s = 0.0;
    double xx = 0.0, xy = 0.0, yy = 0.0;
    int count = 0;
  };
  std::vector<Sums> sums(static_cast<std::size_t>(cluster_count));
  const auto weight_of = [&](std::size_t i) {
    return uniform ? 1.0 / static_cast<double>(poses.size()) : weights[i] / total;
  };
  std::vector<std::int32_t> cluster_of(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::int32_t k = label[static_cast<std::size_t>(bin_of[i])];
    cluster_of[i] = k;
    Sums& s = sums[static_cast<std::size_t>(k)];
    const double w = weight_of(i);
    s.w += w;
    s.x += w * poses[i].x;
    s.y += w * poses[i].y;
    s.c += w * std::cos(poses[i].yaw);
    s.s += w * std::sin(poses[i].yaw);
    ++s.count;
  }
  // The covariance about the mean in a second pass (no cancellation far from the map origin).
  std::vector<Vec2> mean(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k)
    mean[k] = sums[k].w > 0.0 ? Vec2(sums[k].x / sums[k].w, sums[k].y / sums[k].w) : Vec2(0.0, 0.0);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::size_t k = static_cast<std::size_t>(cluster_of[i]);
    const double w = weight_of(i);
    const double ex = poses[i].x - mean[k].x(), ey = poses[i].y - mean[k].y();
    sums[k].xx += w * ex * ex;
    sums[k].xy += w * ex * ey;
    sums[k].yy += w * ey * ey;
  }
  clusters.resize(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) {
    const Sums& s = sums[k];
    ParticleCluster& c = clusters[k];
    c.weight = s.w;
    c.count = s.count;
    if (s.w > 0.0) {
      c.mean = Pose2(mean[k].x(), mean[k].y(), std::atan2(s.s, s.c));
      c.covariance(0, 0) = s.xx / s.w;
      c.covariance(0, 1) = c.covariance(1, 0) = s.xy / s.w;
      c.covariance(1, 1) = s.yy / s.w;
      // Circular variance; R is floored so that uniformly spread headings give a large finite value.
      const double r = std::min(1.0, std::hypot(s.s, s.c) / s.w);
      c.covariance(2, 2) = -2.0 * std::log(std::max(r, 1e-12));
    }
  }
  std::stable_sort(clusters.begin(), clusters.end(),
                   [](const ParticleCluster& a, const ParticleCluster& b) { return a.weight > b.weight; });
  return clusters;
}

// ---------------------------------------------------------------------------------------------

void ParticleFilterConfig::validate() const {
  require(min_particles >= 1, "amcl.min_particles", "must be >= 1");
  require(max_particles >= min_particles, "amcl.max_particles", "must be >= min_particles");
  require(max_particles <= 10'000'000, "amcl.max_particles", "must be <= 10000000");
  require(std::isfinite(pf_err) && pf_err > 0.0 && pf_err < 1.0, "amcl.pf_err", "must be in (0, 1)");
  require(std::isfinite(pf_z) && pf_z > 0.0, "amcl.pf_z", "must be finite and > 0");
  bins.validate();
  require(std::isfinite(alpha_slow) && alpha_slow >= 0.0 && alpha_slow <= 1.0, "amcl.recovery_alpha_slow",
          "must be in [0, 1]");
  require(std::isfinite(alpha_fast) && alpha_fast >= 0.0 && alpha_fast <= 1.0, "amcl.recovery_alpha_fast",
          "must be in [0, 1]");
}

ParticleFilter::ParticleFilter(const ParticleFilterConfig& config) : config_(config) {
  config_.validate();
  recovery_.alpha_slow = config_.alpha_slow;
  recovery_.alpha_fast = config_.alpha_fast;
}

void ParticleFilter::set_particles(std::vector<Pose2> poses) {
  require(!poses.empty(), "amcl", "a particle set needs at least one particle");
  poses_ = std::move(poses);
  for (Pose2& p : poses_) p.yaw = wrap_angle(p.yaw);
  weights_.assign(poses_.size(), 1.0 / static_cast<double>(poses_.size()));
  recovery_.reset();
}

void ParticleFilter::weigh(std::span<const double> likelihoods) {
  require(likelihoods.size() == poses_.size(), "amcl", "likelihood count differs from the particle count");
  double total = 0.0;
  for (std::size_t i = 0; i < weights_.size(); ++i) {
    weights_[i] *= likelihoods[i];
    total += weights_[i];
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    std::fill(weights_.begin(), weights_.end(), 1.0 / static_cast<double>(weights_.size()));
    return;
  }
  // The weights were normalised, so the total is sum_i w_i p_i.
  for (double& w : weights_) w /= total;
  recovery_.update(total);
}

bool ParticleFilter::wants_resample() const {
  if (!config_.selective_resampling) return true;
  if (injection_probability() > 0.0) return true;
  return effective_sample_size() < 0.5 * static_cast<double>(weights_.size());
}

ResampleResult ParticleFilter::resample(Rng& rng, const RandomPoseFn& random_pose, int at_least) {
  ResampleResult r;
  if (poses_.empty()) return r;
  r.w_diff = injection_probability();
  const bool inject = r.w_diff > 0.0 && static_cast<bool>(random_pose);
  const std::size_t draws_n = static_cast<std::size_t>(config_.max_particles);
  std::vector<std::int32_t> draws = config_.resampler == Resampler::Multinomial
                                        ? multinomial_resample(weights_, draws_n, rng)
                                        : systematic_resample(weights_, draws_n, rng);
  const int nb = config_.bins.yaw_bins();
  AmclBinTable table;
  table.clear(draws_n);
  scratch_.clear();
  scratch_.reserve(draws_n);
  int limit = config_.max_particles;  // the KLD limit of the bins so far (k = 0: max)
  for (std::size_t m = 0; m < draws_n; ++m) {
    // One step of Fisher-Yates: the systematic draws come sorted, so they are visited in a
    // random order and stopping early leaves an unbiased subset.
    const std::size_t j = m + static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(draws_n - 1 - m)));
    std::swap(draws[m], draws[j]);
    Pose2 p;
    if (inject && rng.uniform() < r.w_diff) {
      p = random_pose(rng);
      p.yaw = wrap_angle(p.yaw);
      ++r.injected;
    } else {
      p = poses_[static_cast<std::size_t>(draws[m])];
    }
    scratch_.push_back(p);
    const int bins_before = table.size();
    table.insert(amcl_pack_bin(amcl_bin_of(p, config_.bins, nb)));
    if (table.size() != bins_before)
      limit = std::max(at_least, kld_limit(table.size(), config_.pf_err, config_.pf_z, config_.min_particles,
                                           config_.max_particles));
    if (static_cast<int>(scratch_.size()) >= limit) break;
  }
  poses_.swap(scratch_);
  weights_.assign(poses_.size(), 1.0 / static_cast<double>(poses_.size()));
  // Averages back to zero after an injection round, so that recovery does not spiral (pf.c).
  if (r.w_diff > 0.0) recovery_.after_injection(config_.recovery_reset);
  r.resampled = true;
  r.particles = static_cast<int>(poses_.size());
  r.bins = table.size();
  return r;
}

}  // namespace starnav
