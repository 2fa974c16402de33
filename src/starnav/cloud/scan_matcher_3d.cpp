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
                     ThreadPool* pool, std::span<const std::uint32_t> order) {
  if (reference.size() == 0) return kInfinity;
  if (!order.empty() && order.size() != scan.size()) throw Error("fitness_score: the order does not cover the scan");
  constexpr std::size_t kChunk = 512;
  const double max_sq = max_range_m * max_range_m;
  const std::size_t chunks = (scan.size() + kChunk - 1) / kChunk;
  std::vector<double> sums(chunks, 0.0);
  std::vector<std::size_t> counts(chunks, 0);
  auto task = [&](std::size_t c) {
    // The previous point's nearest distance plus the step between the two bounds this one's.
    Vec3 previous = Vec3::Zero();
    double previous_distance = kInfinity;
    const std::size_t end = std::min(scan.size(), (c + 1) * kChunk);
    for (std::size_t j = c * kChunk; j < end; ++j) {
      const Vec3 p = transform * scan[order.empty() ? j : order[j]];
      const double reach = previous_distance + (p - previous).norm();
      const double bound = reach * reach * (1.0 + 1e-9) + 1e-12;
      Neighbour nn;
      bool found = bound < max_sq && reference.nearest_within(p, bound, nn);
      if (!found) found = reference.nearest_within(p, max_sq, nn);  // the bound was not needed or too tight
      previous = p;
      previous_distance = found ? std::sqrt(nn.squared_distance) : kInfinity;
      if (found) {
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
