// Liu 2024 cost functions against hand-computed values (Table 1 defaults).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "starnav/core/error.hpp"
#include "starnav/terrain/liu_cost.hpp"

namespace {

using starnav::LiuCostParams;

TEST(LiuCost, Table1Defaults) {
  const LiuCostParams p;
  EXPECT_EQ(p.h_y, 0.05);
  EXPECT_EQ(p.a_y, 0.5);
  EXPECT_EQ(p.s_y, 0.02);
  EXPECT_EQ(p.w_s, 0.33);
  EXPECT_EQ(p.w_e, 0.33);
  EXPECT_EQ(p.w_r, 0.34);
  EXPECT_EQ(p.w1, 0.5);
  EXPECT_EQ(p.w2, 0.5);
  EXPECT_FALSE(p.cost_per_metre);
  EXPECT_NO_THROW(p.validate());
}

TEST(LiuCost, TanShapedCostsAtKnownPoints) {
  const LiuCostParams p;
  // Half of each threshold: tan(pi/4) = 1; a third: tan(pi/6) = 1/sqrt(3); zero: 0.
  EXPECT_NEAR(starnav::liu_f_slope(0.25, p), 1.0, 1e-15);
  EXPECT_NEAR(starnav::liu_f_step(0.025, p), 1.0, 1e-15);
  EXPECT_NEAR(starnav::liu_f_rugged(0.01, p), 1.0, 1e-15);
  EXPECT_NEAR(starnav::liu_f_step(0.05 / 3.0, p), 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_EQ(starnav::liu_f_slope(0.0, p), 0.0);
  // At and beyond the threshold: impassable; just below: finite and large.
  EXPECT_TRUE(std::isinf(starnav::liu_f_slope(0.5, p)));
  EXPECT_TRUE(std::isinf(starnav::liu_f_step(0.05, p)));
  EXPECT_TRUE(std::isinf(starnav::liu_f_rugged(0.03, p)));
  EXPECT_GT(starnav::liu_f_step(0.0499999, p), 1e5);
  EXPECT_TRUE(std::isfinite(starnav::liu_f_step(0.0499999, p)));
  // Magnitudes: stepping down costs as stepping up.
  EXPECT_EQ(starnav::liu_f_step(-0.02, p), starnav::liu_f_step(0.02, p));
}

TEST(LiuCost, GIsTheWeightedSum) {
  const LiuCostParams p;
  EXPECT_NEAR(starnav::liu_g(0.25, 0.025, 0.01, p), 0.33 + 0.33 + 0.34, 1e-15);
  EXPECT_TRUE(std::isinf(starnav::liu_g(0.1, 0.05, 0.0, p)));
  // Passability does not depend on the weights.
  LiuCostParams q = p;
  q.w_s = 0.0;
  q.w_e = 0.0;
  q.w_r = 1.0;
  EXPECT_TRUE(std::isinf(starnav::liu_g(0.6, 0.0, 0.0, q)));
}

TEST(LiuCost, MoveCostHandComputed) {
  const LiuCostParams p;
  // Straight move of 0.1 m up 0.02 m into a cell with S = 0.005 m^2:
  // a = atan(0.2) = 0.19739555984988075, f_s = tan(pi a / 1) = 0.7141150065847313,
  // f_e = tan(pi 0.02 / 0.1) = 0.7265425280053609, f_r = tan(pi 0.005 / 0.04) = 0.41421356237309503,
  // g = 0.33 f_s + 0.33 f_e + 0.34 f_r = 0.6162495976215827, cost = 0.5 g + 0.5 * 0.1.
  EXPECT_NEAR(starnav::liu_slope(0.02, 0.1), 0.19739555984988075, 1e-15);
  EXPECT_NEAR(starnav::liu_g(0.19739555984988075, 0.02, 0.005, p), 0.6162495976215827, 1e-14);
  EXPECT_NEAR(starnav::liu_move_cost_from_heights(1.0, 1.02, 0.005, 0.1, 0.1, p), 0.35812479881079134, 1e-14);
  EXPECT_NEAR(starnav::liu_move_cost_from_heights(1.02, 1.0, 0.005, 0.1, 0.1, p), 0.35812479881079134, 1e-14);
  // Diagonal, d = 0.1 sqrt 2: a = atan(0.02 / 0.14142) = 0.14048970175352032,
  // g = 0.5364984116735189; per move: 0.5 g + 0.5 d = 0.3389598839554142;
  // per metre (g scaled by d / res = sqrt 2): 0.450072343108812.
  const double d = 0.1 * std::numbers::sqrt2;
  EXPECT_NEAR(starnav::liu_move_cost_from_heights(0.0, 0.02, 0.005, d, 0.1, p), 0.3389598839554142, 1e-14);
  LiuCostParams per_metre = p;
  per_metre.cost_per_metre = true;
  EXPECT_NEAR(starnav::liu_move_cost_from_heights(0.0, 0.02, 0.005, d, 0.1, per_metre), 0.450072343108812, 1e-14);
  // Straight moves are unchanged by the scaling (d / res = 1).
  EXPECT_NEAR(starnav::liu_move_cost_from_heights(1.0, 1.02, 0.005, 0.1, 0.1, per_metre), 0.35812479881079134, 1e-14);
  // Flat ground: only distance.
  EXPECT_NEAR(starnav::liu_move_cost(0.0, 0.0, 0.0, 0.1, 0.1, p), 0.05, 1e-16);
  EXPECT_TRUE(std::isinf(starnav::liu_move_cost(0.0, 0.0, 0.02, 0.1, 0.1, p)));
}

TEST(LiuCost, Heuristics) {
  const LiuCostParams p;
  EXPECT_EQ(starnav::liu_heuristic(3.0, starnav::LiuHeuristic::Paper, p), 3.0);
  EXPECT_EQ(starnav::liu_heuristic(3.0, starnav::LiuHeuristic::Admissible, p), 1.5);
  EXPECT_EQ(starnav::parse_liu_heuristic("paper"), starnav::LiuHeuristic::Paper);
  EXPECT_EQ(starnav::parse_liu_heuristic("admissible"), starnav::LiuHeuristic::Admissible);
  try {
    starnav::parse_liu_heuristic("octile", "--heuristic");
    FAIL();
  } catch (const starnav::Error& e) {
    EXPECT_EQ(e.field(), "--heuristic");
  }
}

TEST(LiuCost, ValidateNamesTheField) {
  auto field_of = [](LiuCostParams p) -> std::string {
    try {
      p.validate();
    } catch (const starnav::Error& e) {
      return e.field();
    }
    return "";
  };
  LiuCostParams p;
  p.h_y = 0.0;
  EXPECT_EQ(field_of(p), "h_y");
  p = {};
  p.a_y = 2.0;
  EXPECT_EQ(field_of(p), "a_y");
  p = {};
  p.s_y = NAN;
  EXPECT_EQ(field_of(p), "s_y");
  p = {};
  p.w_s = 0.5;
  EXPECT_EQ(field_of(p), "weights");
  p = {};
  p.w1 = -1.0;
  EXPECT_EQ(field_of(p), "w1");
  p = {};
  p.unobserved_g = INFINITY;
  EXPECT_EQ(field_of(p), "unobserved_g");
}

}  // namespace
