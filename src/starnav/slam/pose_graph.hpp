#pragma once
// Sparse 2D pose-graph optimisation: nodes are poses (x, y, yaw), edges relative-pose
// measurements between two nodes with an information matrix, optionally under a robust loss.
// Levenberg-Marquardt on the normal equations, solved by Eigen's sparse Cholesky (SimplicialLDLT
// with AMD ordering); robust losses by iteratively reweighted least squares. The first node is
// held fixed (the map frame). docs/slam.md says why this is not Ceres.
//
// Edge error (the residual of measurement Z = (t_z, yaw_z) between poses X_i and X_j):
//   e_t   = R(yaw_z)^T (R(yaw_i)^T (t_j - t_i) - t_z)
//   e_yaw = wrap(yaw_j - yaw_i - yaw_z)
// and the cost of an edge is rho(e^T Omega e) with rho the loss (identity, Huber, Cauchy).
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "starnav/core/geometry.hpp"

namespace starnav {

enum class RobustLoss { None, Huber, Cauchy };

struct PoseGraphEdge {
  std::size_t from = 0, to = 0;
  Pose2 measurement;  // `to` in the frame of `from`
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  RobustLoss loss = RobustLoss::None;
  double loss_scale = 1.0;  // the chi (sqrt of e^T Omega e) where the robust loss bends
};

struct PoseGraphOptions {
  int max_iterations = 50;
  double relative_tolerance = 1e-9;  // stop when the cost falls by less than this fraction
};

struct PoseGraphReport {
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;  // sum of the edges' losses
};

// The edge's residual (e_t, e_yaw) at the given poses.
Eigen::Vector3d pose_graph_residual(const Pose2& from, const Pose2& to, const Pose2& measurement);
// rho(s) and its derivative at s = e^T Omega e.
double robust_loss(RobustLoss loss, double scale, double s);
double robust_weight(RobustLoss loss, double scale, double s);
// The total cost of `poses` under `edges`.
double pose_graph_cost(const std::vector<Pose2>& poses, const std::vector<PoseGraphEdge>& edges);

// Optimises `poses` in place (poses[0] fixed). Throws Error on an edge naming a missing node or
// with a non-finite or non-positive-definite information matrix.
PoseGraphReport optimise_pose_graph(std::vector<Pose2>& poses, const std::vector<PoseGraphEdge>& edges,
                                    const PoseGraphOptions& options = {});

RobustLoss parse_robust_loss(const std::string& text);  // none | huber | cauchy
std::string robust_loss_name(RobustLoss loss);

}  // namespace starnav
