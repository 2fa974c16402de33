// The scan-matcher interface with a test double: a brute-force scan matcher (exhaustive search
// over a pose grid, the reference any real matcher is checked against).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/slam/scan_matcher.hpp"

namespace starnav {
namespace {

Vec2 apply(const Pose2& t, const Vec2& p) {
  return Vec2(t.x + std::cos(t.yaw) * p.x() - std::sin(t.yaw) * p.y(), t.y + std::sin(t.yaw) * p.x() + std::cos(t.yaw) * p.y());
}

// Exhaustive search: every pose on a grid around the guess, scored by the mean squared distance
// of the transformed scan points to their nearest reference points.
class BruteForceMatcher final : public ScanMatcher {
 public:
  std::string_view name() const override { return "brute_force"; }
  ScanMatch match(std::span<const Vec2> reference, std::span<const Vec2> scan, const Pose2& guess) override {
    ScanMatch best;
    best.score = std::numeric_limits<double>::infinity();
    for (int i = -5; i <= 5; ++i)
      for (int j = -5; j <= 5; ++j)
        for (int k = -5; k <= 5; ++k) {
          const Pose2 t(guess.x + 0.01 * i, guess.y + 0.01 * j, guess.yaw + 0.005 * k);
          double sum = 0.0;
          for (const Vec2& p : scan) {
            const Vec2 q = apply(t, p);
            double d = std::numeric_limits<double>::infinity();
            for (const Vec2& r : reference) d = std::min(d, (q - r).squaredNorm());
            sum += d;
          }
          ++best.iterations;
          if (sum / static_cast<double>(scan.size()) < best.score) {
            best.score = sum / static_cast<double>(scan.size());
            best.transform = t;
          }
        }
    best.rms_m = std::sqrt(best.score);
    best.converged = true;
    return best;
  }
};

TEST(ScanMatcherInterface, ABruteForceDoubleRecoversAKnownTransform) {
  std::vector<Vec2> room;  // an L-shaped corner, 8 cm spacing
  for (int i = 0; i <= 25; ++i) room.emplace_back(0.08 * i, 0.0);
  for (int i = 1; i <= 15; ++i) room.emplace_back(0.0, 0.08 * i);
  const Pose2 truth(0.05, -0.03, 0.02);
  // The scan sees the room from a pose `truth` away: scan points = truth^-1 * room.
  std::vector<Vec2> scan;
  for (const Vec2& p : room) {
    const Vec2 d = p - Vec2(truth.x, truth.y);
    scan.emplace_back(std::cos(truth.yaw) * d.x() + std::sin(truth.yaw) * d.y(),
                      -std::sin(truth.yaw) * d.x() + std::cos(truth.yaw) * d.y());
  }
  BruteForceMatcher m;
  ScanMatcher& matcher = m;
  const ScanMatch r = matcher.match(room, scan, Pose2());
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.transform.x, truth.x, 1e-9);
  EXPECT_NEAR(r.transform.y, truth.y, 1e-9);
  EXPECT_NEAR(r.transform.yaw, truth.yaw, 1e-9);
  EXPECT_LT(r.rms_m, 1e-9);
  EXPECT_EQ(r.iterations, 11 * 11 * 11);
  EXPECT_FALSE(matcher.supports_map());
  EXPECT_THROW(matcher.match_to_map(OccupancyGrid(GridGeometry{2, 2, 0.1, {}}, 0), scan, Pose2()), Error);
}

}  // namespace
}  // namespace starnav
