#include "starnav/slam/pose_graph_3d.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/Sparse>

#include "starnav/core/error.hpp"
#include "starnav/slam/sparse_levenberg_marquardt.hpp"

namespace starnav {

namespace {

using Pg3Matrix6 = Eigen::Matrix<double, 6, 6>;
using Pg3Vector6 = Eigen::Matrix<double, 6, 1>;
using Pg3PlaneJacobian = Eigen::Matrix<double, 3, 6>;

// Central-difference step of the plane edges' Jacobian: truncation ~h^2 and round-off ~1e-16/h
// balance near 1e-5; the residual's entries are O(1), so this gives about 10 correct digits.
constexpr double kPg3PlaneStep = 1e-6;

Eigen::Matrix3d pg3_hat(const Vec3& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// The rotation vector (angle in [0, pi]) of a rotation matrix, through the unit quaternion with
// w >= 0; the small-angle branch avoids 0/0.
Vec3 pg3_rotation_vector(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double n = q.vec().norm();
  const double factor = n < 1e-8 ? 2.0 / q.w() : 2.0 * std::atan2(n, q.w()) / n;
  return factor * q.vec();
}

// Inverse of SO(3)'s right Jacobian: log(R exp(d)) = phi + J_r^-1(phi) d + O(d^2), phi = log R.
// Written with cot(theta/2) so that it stays finite at theta = pi.
Eigen::Matrix3d pg3_inverse_right_jacobian(const Vec3& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d w = pg3_hat(phi);
  double c;
  if (theta < 1e-4) {
    c = 1.0 / 12.0 + theta * theta / 720.0;
  } else {
    const double half = 0.5 * theta;
    c = 1.0 / (theta * theta) - std::cos(half) / (2.0 * theta * std::sin(half));
  }
  return Eigen::Matrix3d::Identity() + 0.5 * w + c * w * w;
}

bool pg3_is_rotation(const Eigen::Matrix3d& r) {
  return r.allFinite() && (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6 &&
         r.determinant() > 0;
}

bool pg3_is_rigid(const Rigid3& t) { return t.translation().allFinite() && pg3_is_rotation(t.linear()); }

// Rounding drifts a rotation off SO(3) over many updates; the nearest unit quaternion puts it back.
Rigid3 pg3_orthonormalised(Rigid3 t) {
  t.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
  return t;
}

template <int N>
void pg3_check_information(const Eigen::Matrix<double, N, N>& information, const std::string& field) {
  require(information.allFinite() && information.isApprox(information.transpose()), field,
          "information must be finite and symmetric");
  require(Eigen::LLT<Eigen::Matrix<double, N, N>>(information).info() == Eigen::Success, field,
          "information must be positive definite");
}

void pg3_check_plane(const Plane3& plane, const std::string& field, const std::string& what) {
  require(plane.normal.allFinite() && std::abs(plane.normal.norm() - 1.0) < 1e-6 && std::isfinite(plane.d), field,
          what + " must have a finite unit normal and a finite d");
}

void pg3_check_loss(RobustLoss loss, double scale, const std::string& field) {
  require(loss == RobustLoss::None || (std::isfinite(scale) && scale > 0), field, "loss_scale must be > 0");
}

void pg3_check_inputs(const std::vector<Rigid3>& poses, const std::vector<PoseGraph3Edge>& edges,
                      const std::vector<PlaneEdge3>& plane_edges, const PoseGraph3Options& options) {
  const std::size_t nodes = poses.size();
  for (std::size_t i = 0; i < nodes; ++i)
    require(pg3_is_rigid(poses[i]), "poses[" + std::to_string(i) + "]", "must be finite with an orthonormal rotation");
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraph3Edge& e = edges[k];
    const std::string field = "edges[" + std::to_string(k) + "]";
    require(e.from < nodes && e.to < nodes && e.from != e.to, field, "must join two different existing nodes");
    pg3_check_information(e.information, field);
    require(pg3_is_rigid(e.measurement), field, "measurement must be finite with an orthonormal rotation");
    pg3_check_loss(e.loss, e.loss_scale, field);
  }
  for (std::size_t k = 0; k < plane_edges.size(); ++k) {
    const PlaneEdge3& e = plane_edges[k];
    const std::string field = "plane_edges[" + std::to_string(k) + "]";
    require(e.node < nodes, field, "must name an existing node");
    pg3_check_information(e.information, field);
    pg3_check_plane(e.measured, field, "measured plane");
    pg3_check_loss(e.loss, e.loss_scale, field);
  }
  pg3_check_plane(options.floor, "floor", "the floor plane");
  if (nodes > 0)  // an empty graph has nothing to fix, whatever the (default) list says
    for (std::size_t f : options.fixed_nodes) require(f < nodes, "fixed_nodes", "must name existing nodes");
}

Pg3PlaneJacobian pg3_plane_jacobian(const Rigid3& node, const Plane3& global, const Plane3& measured) {
  Pg3PlaneJacobian j;
  for (int k = 0; k < 6; ++k) {
    Pg3Vector6 xi = Pg3Vector6::Zero();
    xi(k) = kPg3PlaneStep;
    const Eigen::Vector3d plus = plane_edge_3d_residual(se3_exp(xi) * node, global, measured);
    const Eigen::Vector3d minus = plane_edge_3d_residual(se3_exp(-xi) * node, global, measured);
    j.col(k) = (plus - minus) / (2.0 * kPg3PlaneStep);
  }
  return j;
}

}  // namespace

Eigen::Matrix<double, 6, 1> pose_graph_3d_residual(const Rigid3& from, const Rigid3& to, const Rigid3& measurement) {
  const Rigid3 e = measurement.inverse() * (from.inverse() * to);
  Pg3Vector6 r;
  r << e.translation(), pg3_rotation_vector(e.linear());
  return r;
}

PoseGraph3Jacobians pose_graph_3d_jacobians(const Rigid3& from, const Rigid3& to, const Rigid3& measurement) {
  // exp(xi) T_to = T_to exp(Ad(T_to^-1) xi), so E(xi_to) = E exp(Ad(T_to^-1) xi_to), and
  // exp(-xi) T_to likewise for the perturbation of `from` (which enters E through T_from^-1).
  // With E exp(d), d = (dw, dv): the translation moves by R_E dv, the rotation vector by
  // J_r^-1(phi) dw. Ad(T^-1) = [[R^T, 0], [-R^T t^, R^T]] in the (omega, v) order.
  const Rigid3 e = measurement.inverse() * (from.inverse() * to);
  const Vec3 phi = pg3_rotation_vector(e.linear());
  const Eigen::Matrix3d rt = to.linear().transpose();
  Pg3Matrix6 j;
  j.block<3, 3>(0, 0) = -e.linear() * rt * pg3_hat(to.translation());
  j.block<3, 3>(0, 3) = e.linear() * rt;
  j.block<3, 3>(3, 0) = pg3_inverse_right_jacobian(phi) * rt;
  j.block<3, 3>(3, 3).setZero();
  return {-j, j};
}

Eigen::Vector3d plane_edge_3d_residual(const Rigid3& node, const Plane3& global, const Plane3& measured) {
  const Vec3 n_l = node.linear().transpose() * global.normal;
  const double d_l = global.d + global.normal.dot(node.translation());
  Vec3 n_m = measured.normal;
  double d_m = measured.d;
  if (n_m.dot(n_l) < 0) {  // the same plane, oriented like the expected one
    n_m = -n_m;
    d_m = -d_m;
  }
  const Vec3 q = Eigen::Quaterniond::FromTwoVectors(n_l, Vec3::UnitX()) * n_m;
  return {std::atan2(q.y(), q.x()), std::atan2(q.z(), std::hypot(q.x(), q.y())), d_l - d_m};
}

double pose_graph_3d_cost(const std::vector<Rigid3>& poses, const std::vector<PoseGraph3Edge>& edges,
                          const std::vector<PlaneEdge3>& plane_edges, const Plane3& floor) {
  double cost = 0.0;
  for (const PoseGraph3Edge& e : edges) {
    const Pg3Vector6 r = pose_graph_3d_residual(poses[e.from], poses[e.to], e.measurement);
    cost += robust_loss(e.loss, e.loss_scale, r.dot(e.information * r));
  }
  for (const PlaneEdge3& e : plane_edges) {
    const Eigen::Vector3d r = plane_edge_3d_residual(poses[e.node], floor, e.measured);
    cost += robust_loss(e.loss, e.loss_scale, r.dot(e.information * r));
  }
  return cost;
}

PoseGraph3Report optimise_pose_graph_3d(std::vector<Rigid3>& poses, const std::vector<PoseGraph3Edge>& edges,
                                        const std::vector<PlaneEdge3>& plane_edges, const PoseGraph3Options& options) {
  pg3_check_inputs(poses, edges, plane_edges, options);
  PoseGraph3Report report;
  report.initial_cost = report.final_cost = pose_graph_3d_cost(poses, edges, plane_edges, options.floor);
  if (poses.empty()) return report;

  // The first of each free node's 6 unknowns; -1 for a fixed node.
  std::vector<bool> fixed(poses.size(), false);
  for (std::size_t f : options.fixed_nodes) fixed[f] = true;
  std::vector<Eigen::Index> column(poses.size(), -1);
  Eigen::Index n = 0;
  for (std::size_t k = 0; k < poses.size(); ++k)
    if (!fixed[k]) column[k] = n, n += 6;
  if (n == 0 || (edges.empty() && plane_edges.empty())) return report;

  SparseLevenbergMarquardt lm;
  double cost = report.initial_cost;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(edges.size() * 78 + plane_edges.size() * 21);
  Eigen::VectorXd b(n), diagonal(n);
  // Adds a 6 x 6 block at (row0, col0), only its part in H's lower triangle, and its diagonal.
  const auto add_block = [&](Eigen::Index row0, Eigen::Index col0, const Pg3Matrix6& h) {
    for (int v = 0; v < 6; ++v)
      for (int u = 0; u < 6; ++u) {
        const Eigen::Index row = row0 + u, col = col0 + v;
        if (row >= col) triplets.emplace_back(row, col, h(u, v));
        if (row == col) diagonal(row) += h(u, v);
      }
  };
  for (int it = 0; it < options.max_iterations; ++it) {
    triplets.clear();
    b.setZero();
    diagonal.setZero();
    for (const PoseGraph3Edge& e : edges) {
      const Eigen::Index cols[2] = {column[e.from], column[e.to]};
      if (cols[0] < 0 && cols[1] < 0) continue;
      const Rigid3& from = poses[e.from];
      const Rigid3& to = poses[e.to];
      const Pg3Vector6 r = pose_graph_3d_residual(from, to, e.measurement);
      const double w = robust_weight(e.loss, e.loss_scale, r.dot(e.information * r));
      const Pg3Matrix6 omega = w * e.information;
      const PoseGraph3Jacobians jac = pose_graph_3d_jacobians(from, to, e.measurement);
      const Pg3Matrix6* j[2] = {&jac.from, &jac.to};
      for (int p = 0; p < 2; ++p) {
        if (cols[p] < 0) continue;
        const Pg3Matrix6 jt_omega = j[p]->transpose() * omega;
        b.segment<6>(cols[p]) += jt_omega * r;
        for (int q = 0; q < 2; ++q)
          if (cols[q] >= 0) add_block(cols[p], cols[q], jt_omega * *j[q]);
      }
    }
    for (const PlaneEdge3& e : plane_edges) {
      const Eigen::Index c = column[e.node];
      if (c < 0) continue;
      const Eigen::Vector3d r = plane_edge_3d_residual(poses[e.node], options.floor, e.measured);
      const double w = robust_weight(e.loss, e.loss_scale, r.dot(e.information * r));
      const Pg3PlaneJacobian j = pg3_plane_jacobian(poses[e.node], options.floor, e.measured);
      const Eigen::Matrix<double, 6, 3> jt_omega = w * j.transpose() * e.information;
      b.segment<6>(c) += jt_omega * r;
      add_block(c, c, jt_omega * j);
    }
    const auto step = lm.step(
        triplets, diagonal, b, poses, cost, options.relative_tolerance,
        [&](const Eigen::VectorXd& delta) {
          std::vector<Rigid3> moved = poses;
          for (std::size_t k = 0; k < poses.size(); ++k)
            if (column[k] >= 0) moved[k] = pg3_orthonormalised(se3_exp(delta.segment<6>(column[k])) * poses[k]);
          return moved;
        },
        [&](const std::vector<Rigid3>& candidate) { return pose_graph_3d_cost(candidate, edges, plane_edges, options.floor); });
    if (step == SparseLevenbergMarquardt::Step::Failed) break;
    ++report.iterations;
    if (step == SparseLevenbergMarquardt::Step::Converged) break;
  }
  report.final_cost = cost;
  return report;
}

}  // namespace starnav
