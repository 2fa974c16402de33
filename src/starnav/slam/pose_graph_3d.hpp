#pragma once
// Sparse 3D pose-graph optimisation for 3D graph SLAM (hdl_graph_slam, Ou et al. 2022 section 2):
// nodes are poses in SE(3), edges relative-pose measurements between two nodes and plane
// measurements tying one node to a fixed global plane (the floor), each with an information matrix
// and optionally a robust loss. The 3D twin of optimise_pose_graph (pose_graph.hpp): Levenberg-
// Marquardt on the normal equations (6 unknowns per free node), Eigen's sparse Cholesky
// (SimplicialLDLT, AMD ordering), robust losses by iteratively reweighted least squares with the
// same RobustLoss, and by default the first node held fixed (the map frame).
//
// Poses: a node's pose T = (R, t) maps points of the node's frame into the map frame,
// p_map = R p_node + t.
//
// Relative-pose edge with measurement Z (`to` in the frame of `from`) between T_from and T_to:
//   E = Z^-1 (T_from^-1 T_to),  e = (translation of E, rotation vector of E)   (6: translation FIRST)
// The rotation vector is the angle-axis vector (angle in [0, pi]) of E's rotation.
//
// Plane edge (hdl_graph_slam's EdgeSE3Plane against a fixed plane): the global plane
// (n_w, d_w), n_w . p + d_w = 0, expressed in the node's frame is
//   n_l = R^T n_w,  d_l = d_w + n_w . t
// (Ou 2022's n' = R n, with its R the map-to-node rotation, our R^T).
// The measured plane (n_m, d_m) (the floor as RANSAC fits it in the node's frame) is first
// oriented like n_l: when n_m . n_l < 0 both n_m and d_m change sign (they describe the same
// plane; a fitter may return either orientation). Then, as in the paper's e_rr (Ou 2022 Eqs.
// 15-20): R_x is the shortest-arc rotation taking n_l onto the x axis, q = R_x n_m, and
//   e = (alpha, beta, d_l - d_m),  alpha = atan2(q_y, q_x),  beta = atan2(q_z, sqrt(q_x^2 + q_y^2)).
// The shortest arc is smooth everywhere except at n_l = -x; g2o's azimuth/elevation choice of R_x
// is singular at n_l = +-z, which is where the floor is seen from a level robot. The error is zero
// exactly when the node lies on the plane as measured; the angle between the normals is
// acos(cos alpha cos beta), about sqrt(alpha^2 + beta^2) for small tilts.
//
// The cost of an edge is rho(e^T Omega e) with rho the loss (identity, Huber, Cauchy); the total
// cost is the sum over both kinds of edges.
//
// Update: the left perturbation T <- exp(xi) T per free node, xi = (omega, v) as se3_exp takes it
// (rotation first, both in the map frame); rotations are re-orthonormalised after every update.
// Jacobians: analytic for relative edges, central differences for plane edges.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/cloud/ransac_plane.hpp"
#include "starnav/slam/pose_graph.hpp"

namespace starnav {

struct PoseGraph3Edge {
  std::size_t from = 0, to = 0;
  Rigid3 measurement = Rigid3::Identity();  // `to` in the frame of `from`
  // On the residual (translation, rotation vector).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();
  RobustLoss loss = RobustLoss::None;
  double loss_scale = 1.0;  // the chi (sqrt of e^T Omega e) where the robust loss bends
};

struct PlaneEdge3 {
  std::size_t node = 0;
  Plane3 measured = Plane3{};  // the global plane as observed in the node's frame (unit normal)
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  // on (alpha, beta, d_l - d_m)
  RobustLoss loss = RobustLoss::None;
  double loss_scale = 1.0;
};

struct PoseGraph3Options {
  int max_iterations = 50;
  double relative_tolerance = 1e-9;  // stop when the cost falls by less than this fraction
  // Nodes held where they are. With none, only the damping holds the gauge (the graph may drift
  // as a whole); with all, there is nothing to do.
  std::vector<std::size_t> fixed_nodes = {0};
  Plane3 floor = Plane3{};  // the fixed global plane of the plane edges; default z = 0, normal up
};

struct PoseGraph3Report {
  int iterations = 0;                           // accepted steps
  double initial_cost = 0.0, final_cost = 0.0;  // sum of the edges' losses
};

// The relative edge's residual (translation, rotation vector) of E = Z^-1 T_from^-1 T_to.
Eigen::Matrix<double, 6, 1> pose_graph_3d_residual(const Rigid3& from, const Rigid3& to, const Rigid3& measurement);

// The derivatives of that residual under the left perturbations T <- exp(xi) T of each node,
// columns in se3_exp's order (omega, v).
struct PoseGraph3Jacobians {
  Eigen::Matrix<double, 6, 6> from, to;
};
PoseGraph3Jacobians pose_graph_3d_jacobians(const Rigid3& from, const Rigid3& to, const Rigid3& measurement);

// The plane edge's residual (alpha, beta, d_l - d_m) of `node` observing `global` as `measured`.
Eigen::Vector3d plane_edge_3d_residual(const Rigid3& node, const Plane3& global, const Plane3& measured);

// The total cost of `poses` under both kinds of edges, `floor` the plane edges' global plane.
double pose_graph_3d_cost(const std::vector<Rigid3>& poses, const std::vector<PoseGraph3Edge>& edges,
                          const std::vector<PlaneEdge3>& plane_edges, const Plane3& floor = {});

// Optimises `poses` in place; fixed nodes are left bit for bit as they were. Throws Error (field
// `poses[i]`, `edges[k]`, `plane_edges[k]`, `fixed_nodes`, `floor`) on a non-finite or
// non-orthonormal pose, an edge naming a missing node (or a relative edge joining a node to
// itself), a non-finite or non-positive-definite information matrix, a non-finite or
// non-orthonormal measurement, a non-finite or non-unit plane normal, or a non-positive loss scale.
PoseGraph3Report optimise_pose_graph_3d(std::vector<Rigid3>& poses, const std::vector<PoseGraph3Edge>& edges,
                                        const std::vector<PlaneEdge3>& plane_edges,
                                        const PoseGraph3Options& options = {});

}  // namespace starnav
