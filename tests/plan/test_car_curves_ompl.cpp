// Dubins and Reeds-Shepp lengths against OMPL's DubinsStateSpace and ReedsSheppStateSpace, an
// independent implementation, on random pose pairs. Built only with -DSTARNAV_TEST_WITH_OMPL=ON
// (Debian's libompl-dev); docs/planning.md records the result.
#include <gtest/gtest.h>

#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/DubinsStateSpace.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "starnav/core/angle.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/plan/car_curves.hpp"

namespace starnav {
namespace {

namespace ob = ompl::base;

template <class Space>
double ompl_length(const std::shared_ptr<Space>& space, const Pose2& a, const Pose2& b) {
  ob::ScopedState<ob::SE2StateSpace> sa(space), sb(space);
  sa->setXY(a.x, a.y);
  sa->setYaw(a.yaw);
  sb->setXY(b.x, b.y);
  sb->setYaw(b.yaw);
  return space->distance(sa.get(), sb.get());
}

TEST(CarCurvesOmpl, LengthsMatchOmplOnRandomPairs) {
  Rng rng(2024);
  int rs_worse = 0, rs_better = 0, dubins_differ = 0;
  double rs_max_diff = 0.0, dubins_max_diff = 0.0;
  const int pairs = 20000;
  for (int i = 0; i < pairs; ++i) {
    const double radius = rng.uniform(0.3, 3.0);
    const Pose2 a{rng.uniform(-8.0, 8.0), rng.uniform(-8.0, 8.0), rng.uniform(-kPi, kPi)};
    const Pose2 b{rng.uniform(-8.0, 8.0), rng.uniform(-8.0, 8.0), rng.uniform(-kPi, kPi)};
    const auto rs_space = std::make_shared<ob::ReedsSheppStateSpace>(radius);
    const auto dubins_space = std::make_shared<ob::DubinsStateSpace>(radius, false);
    const double rs = shortest_reeds_shepp_path(a, b, radius).length;
    const double rs_ompl = ompl_length(rs_space, a, b);
    const double du = shortest_dubins_path(a, b, radius).length;
    const double du_ompl = ompl_length(dubins_space, a, b);
    const double tol = 1e-9 * (1.0 + rs_ompl);
    if (rs > rs_ompl + tol) ++rs_worse;
    if (rs < rs_ompl - tol) ++rs_better;
    if (std::abs(du - du_ompl) > 1e-9 * (1.0 + du_ompl)) ++dubins_differ;
    rs_max_diff = std::max(rs_max_diff, std::abs(rs - rs_ompl));
    dubins_max_diff = std::max(dubins_max_diff, std::abs(du - du_ompl));
  }
  std::printf("OMPL comparison over %d pairs: Reeds-Shepp longer %d, shorter %d, max |diff| %.3g m; Dubins "
              "differing %d, max |diff| %.3g m\n",
              pairs, rs_worse, rs_better, rs_max_diff, dubins_differ, dubins_max_diff);
  // Never longer than OMPL's shortest: both search the same 48 words. (Shorter is allowed where OMPL's
  // round-off tolerance rejects a word this implementation accepts; the count is printed.)
  EXPECT_EQ(rs_worse, 0);
  EXPECT_LE(rs_better, pairs / 1000);
  EXPECT_EQ(dubins_differ, 0);
}

}  // namespace
}  // namespace starnav
