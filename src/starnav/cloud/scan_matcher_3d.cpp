#include "starnav/cloud/scan_matcher_3d.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <vector>

#include "starnav/core/error.hpp"

namespace starnav {

void RegistrationLimits::validate() const {
  require(max_iterations >= 1 && max_iterations <= 10000, "max_iterations", "must be in [1, 10000]");
  require_positive(translation_tolerance_m, "translation_tolerance_m");
  require_positive(rotation_tolerance_rad, "rotation_tolerance_deg");
  require_positive(fitness_max_range_m, "fitness_max_range_m");
}

CloudMatch register_clouds(ScanMatcher3d& matcher, std::span<const Vec3> reference, std::span<const Vec3> scan,
                           const Rigid3& guess) {
  const auto start = std::chrono::steady_clock::now();
  matcher.set_reference(reference);
  CloudMatch m = matcher.match(scan, guess);
  m.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return m;
}

double fitness_score(const KdTree3& reference, std::span<const Vec3> scan, const Rigid3& transform, double max_range_m) {
  const double max_sq = max_range_m * max_range_m;
  double sum = 0.0;
  std::size_t n = 0;
  Neighbour nn;
  for (const Vec3& a : scan) {
    if (!reference.nearest(transform * a, nn)) break;
    if (nn.squared_distance <= max_sq) {
      sum += nn.squared_distance;
      ++n;
    }
  }
  return n > 0 ? sum / static_cast<double>(n) : kInfinity;
}

double fitness_score(const KdTree3& reference, std::span<const Vec3> scan, const Rigid3& transform, double max_range_m,
                     ThreadPool* pool) {
  if (reference.size() == 0) return kInfinity;
  constexpr std::size_t kChunk = 512;
  const double max_sq = max_range_m * max_range_m;
  const std::size_t chunks = (scan.size() + kChunk - 1) / kChunk;
  std::vector<double> sums(chunks, 0.0);
  std::vector<std::size_t> counts(chunks, 0);
  auto task = [&](std::size_t c) {
    Neighbour nn;
    const std::size_t end = std::min(scan.size(), (c + 1) * kChunk);
    for (std::size_t i = c * kChunk; i < end; ++i) {
      reference.nearest(transform * scan[i], nn);
      if (nn.squared_distance <= max_sq) {
        sums[c] += nn.squared_distance;
        ++counts[c];
      }
    }
  };
  if (pool && pool->size() > 1) {
    pool->run(chunks, task);
  } else {
    for (std::size_t c = 0; c < chunks; ++c) task(c);
  }
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    sum += sums[c];
    n += counts[c];
  }
  return n > 0 ? sum / static_cast<double>(n) : kInfinity;
}

}  // namespace starnav
