// Pose-graph optimisation against independent answers: measurements taken from known poses are
// reproduced exactly from a perturbed start; with translation-only edges the problem is linear and
// the optimum is the dense normal equations' solution; a robust loss keeps one false edge from
// pulling the graph; bad edges are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/slam/pose_graph.hpp"

namespace starnav {
namespace {

std::vector<Pose2> square_loop(int per_side) {
  std::vector<Pose2> poses;
  Pose2 p;
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < per_side; ++k) {
      poses.push_back(p);
      p = p.compose(Pose2(1.0, 0.0, k == per_side - 1 ? kPi / 2 : 0.0));
    }
  return poses;
}

TEST(PoseGraph, ResidualIsZeroForTheTrueMeasurementAndWrapsTheAngle) {
  const Pose2 a(1, 2, 3.0), b(-1, 0.5, -3.0);
  EXPECT_LT(pose_graph_residual(a, b, a.inverse().compose(b)).norm(), 1e-12);
  // A measurement 2 pi off in yaw is the same measurement.
  Pose2 z = a.inverse().compose(b);
  z.yaw += 2 * kPi;
  EXPECT_LT(std::abs(pose_graph_residual(a, b, z)(2)), 1e-12);
}

TEST(PoseGraph, RecoversConsistentMeasurementsFromAPerturbedStart) {
  const std::vector<Pose2> truth = square_loop(5);
  std::vector<PoseGraphEdge> edges;
  for (std::size_t i = 0; i + 1 < truth.size(); ++i) edges.push_back({i, i + 1, truth[i].inverse().compose(truth[i + 1])});
  edges.push_back({truth.size() - 1, 0, truth.back().inverse().compose(truth[0])});  // the loop
  edges.push_back({3, 13, truth[3].inverse().compose(truth[13])});
  Rng rng(7);
  std::vector<Pose2> poses = truth;
  for (std::size_t i = 1; i < poses.size(); ++i)
    poses[i] = Pose2(poses[i].x + 0.3 * rng.normal(), poses[i].y + 0.3 * rng.normal(), wrap_angle(poses[i].yaw + 0.2 * rng.normal()));
  const PoseGraphReport r = optimise_pose_graph(poses, edges);
  EXPECT_GT(r.initial_cost, 1.0);
  EXPECT_LT(r.final_cost, 1e-12);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(poses[i].x, truth[i].x, 1e-6) << i;
    EXPECT_NEAR(poses[i].y, truth[i].y, 1e-6) << i;
    EXPECT_NEAR(wrap_angle(poses[i].yaw - truth[i].yaw), 0.0, 1e-6) << i;
  }
}

TEST(PoseGraph, TranslationOnlyGraphsMatchTheDenseLeastSquaresSolution) {
  // Every measurement's yaw 0 and the yaws held at 0 by a huge information: the residuals are
  // then linear in the positions, and the optimum solves a dense linear least-squares problem.
  Rng rng(11);
  const std::size_t n = 12;
  std::vector<PoseGraphEdge> edges;
  for (std::size_t i = 0; i + 1 < n; ++i) edges.push_back({i, i + 1, Pose2(1.0 + 0.1 * rng.normal(), 0.1 * rng.normal(), 0.0)});
  for (auto [i, j] : {std::pair<std::size_t, std::size_t>{0, 6}, {2, 11}, {4, 9}})
    edges.push_back({i, j, Pose2(static_cast<double>(j - i) + 0.2 * rng.normal(), 0.2 * rng.normal(), 0.0)});
  for (std::size_t k = 0; k < edges.size(); ++k)
    edges[k].information = Eigen::Vector3d(1.0 + static_cast<double>(k % 3), 2.0, 1e12).asDiagonal();
  // Dense: unknowns x_1..x_{n-1}, y_1..y_{n-1}; x_0 = y_0 = 0.
  const Eigen::Index m = static_cast<Eigen::Index>(n - 1);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(2 * edges.size()), 2 * m);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(2 * edges.size()));
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    for (int axis = 0; axis < 2; ++axis) {
      const Eigen::Index row = static_cast<Eigen::Index>(2 * k) + axis;
      const double w = std::sqrt(e.information(axis, axis));
      if (e.to > 0) A(row, axis * m + static_cast<Eigen::Index>(e.to) - 1) += w;
      if (e.from > 0) A(row, axis * m + static_cast<Eigen::Index>(e.from) - 1) -= w;
      b(row) = w * (axis == 0 ? e.measurement.x : e.measurement.y);
    }
  }
  const Eigen::VectorXd solution = A.colPivHouseholderQr().solve(b);
  std::vector<Pose2> poses(n);
  for (std::size_t i = 0; i < n; ++i) poses[i] = Pose2(static_cast<double>(i) * 0.5, 0.0, 0.0);
  optimise_pose_graph(poses, edges);
  for (std::size_t i = 1; i < n; ++i) {
    EXPECT_NEAR(poses[i].x, solution(static_cast<Eigen::Index>(i) - 1), 1e-6) << i;
    EXPECT_NEAR(poses[i].y, solution(m + static_cast<Eigen::Index>(i) - 1), 1e-6) << i;
    EXPECT_NEAR(poses[i].yaw, 0.0, 1e-8);
  }
}

TEST(PoseGraph, ARobustLossKeepsOneFalseClosureFromBendingTheGraph) {
  const std::vector<Pose2> truth = square_loop(6);
  const auto build = [&](RobustLoss loss) {
    std::vector<PoseGraphEdge> edges;
    for (std::size_t i = 0; i + 1 < truth.size(); ++i) {
      edges.push_back({i, i + 1, truth[i].inverse().compose(truth[i + 1])});
      edges.back().information = Eigen::Vector3d(100, 100, 1000).asDiagonal();
    }
    // True closures between the sides, and one false one that says node 20 sits on node 2.
    for (auto [i, j] : {std::pair<std::size_t, std::size_t>{0, 23}, {5, 18}, {1, 22}, {8, 15}}) {
      edges.push_back({i, j, truth[i].inverse().compose(truth[j]), Eigen::Vector3d(100, 100, 1000).asDiagonal(), loss, 1.0});
    }
    edges.push_back({2, 20, Pose2(0.0, 0.0, 0.0), Eigen::Vector3d(100, 100, 1000).asDiagonal(), loss, 1.0});
    std::vector<Pose2> poses = truth;
    optimise_pose_graph(poses, edges, {.max_iterations = 200});
    double worst = 0.0;
    for (std::size_t i = 0; i < truth.size(); ++i) worst = std::max(worst, (poses[i].translation() - truth[i].translation()).norm());
    return worst;
  };
  const double plain = build(RobustLoss::None), cauchy = build(RobustLoss::Cauchy), huber = build(RobustLoss::Huber);
  EXPECT_GT(plain, 0.5);
  EXPECT_LT(cauchy, 0.05) << "plain " << plain;
  EXPECT_LT(huber, plain / 2);
}

TEST(PoseGraph, RobustLossesHaveTheirClosedForms) {
  EXPECT_DOUBLE_EQ(robust_loss(RobustLoss::None, 1.0, 9.0), 9.0);
  EXPECT_DOUBLE_EQ(robust_loss(RobustLoss::Huber, 2.0, 1.0), 1.0);       // quadratic inside
  EXPECT_DOUBLE_EQ(robust_loss(RobustLoss::Huber, 2.0, 16.0), 12.0);     // 2 k sqrt(s) - k^2
  EXPECT_DOUBLE_EQ(robust_loss(RobustLoss::Cauchy, 2.0, 4.0), 4.0 * std::log(2.0));
  EXPECT_DOUBLE_EQ(robust_weight(RobustLoss::Cauchy, 2.0, 4.0), 0.5);
  EXPECT_DOUBLE_EQ(robust_weight(RobustLoss::Huber, 2.0, 16.0), 0.5);
  EXPECT_EQ(parse_robust_loss("cauchy"), RobustLoss::Cauchy);
  EXPECT_THROW(parse_robust_loss("tukey"), Error);
}

TEST(PoseGraph, RefusesEdgesToMissingNodesAndBadInformation) {
  std::vector<Pose2> poses(3);
  EXPECT_THROW(optimise_pose_graph(poses, {{0, 3, Pose2()}}), Error);
  EXPECT_THROW(optimise_pose_graph(poses, {{1, 1, Pose2()}}), Error);
  EXPECT_THROW(optimise_pose_graph(poses, {{0, 1, Pose2(), Eigen::Vector3d(1, -1, 1).asDiagonal()}}), Error);
  EXPECT_THROW(optimise_pose_graph(poses, {{0, 1, Pose2(std::nan(""), 0, 0)}}), Error);
  EXPECT_NO_THROW(optimise_pose_graph(poses, {}));
}

}  // namespace
}  // namespace starnav
