#pragma once
// The one seeded random number generator of starnav. Its output depends only on the seed (no
// std:: distributions, whose results differ between standard libraries), so runs are
// reproducible byte for byte. xoshiro256** seeded through splitmix64.
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace starnav {

__extension__ using uint128_t = unsigned __int128;  // for Lemire's multiply-shift

class Rng {
 public:
  using result_type = std::uint64_t;

  explicit Rng(std::uint64_t seed = 0) { reseed(seed); }

  void reseed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& s : state_) s = splitmix64(x);
    has_spare_normal_ = false;
  }

  // An independent generator for a named sub-stream (e.g. one per sensor), derived from this
  // one's seed material without advancing it.
  Rng fork(std::uint64_t stream) const {
    std::uint64_t x = state_[0] ^ (stream * 0x9E3779B97F4A7C15ull) ^ rotl(state_[2], 17);
    return Rng(splitmix64(x));
  }

  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }

  result_type operator()() { return next(); }

  result_type next() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }

  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [lo, hi] (inclusive), unbiased (Lemire's method with rejection).
  // Requires lo <= hi (swapped otherwise). The span is computed in unsigned arithmetic, so the
  // full int64 range works without signed overflow.
  std::int64_t uniform_int(std::int64_t lo, std::int64_t hi) {
    if (hi < lo) std::swap(lo, hi);
    const std::uint64_t range = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo) + 1u;
    if (range == 0) return static_cast<std::int64_t>(next());  // full 64-bit range
    uint128_t m = static_cast<uint128_t>(next()) * range;
    std::uint64_t low = static_cast<std::uint64_t>(m);
    if (low < range) {
      const std::uint64_t threshold = (0 - range) % range;
      while (low < threshold) {
        m = static_cast<uint128_t>(next()) * range;
        low = static_cast<std::uint64_t>(m);
      }
    }
    // lo + offset in unsigned arithmetic (offset may exceed INT64_MAX); the result is in [lo, hi].
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(lo) + static_cast<std::uint64_t>(m >> 64));
  }
  // Standard normal (Marsaglia polar method).
  double normal() {
    if (has_spare_normal_) {
      has_spare_normal_ = false;
      return spare_normal_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    spare_normal_ = v * f;
    has_spare_normal_ = true;
    return u * f;
  }
  double normal(double mean, double stddev) { return mean + stddev * normal(); }
  bool bernoulli(double p) { return uniform() < p; }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  std::uint64_t state_[4]{};
  double spare_normal_ = 0.0;
  bool has_spare_normal_ = false;
};

}  // namespace starnav
