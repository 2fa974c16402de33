#include "starnav/slam/pose_graph.hpp"

#include <cmath>

#include <Eigen/Sparse>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/slam/sparse_levenberg_marquardt.hpp"

namespace starnav {

namespace {

Eigen::Matrix2d rotation(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

void check_edges(std::size_t nodes, const std::vector<PoseGraphEdge>& edges) {
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    const std::string field = "edges[" + std::to_string(k) + "]";
    require(e.from < nodes && e.to < nodes && e.from != e.to, field, "must join two different existing nodes");
    require(e.information.allFinite() && e.information.isApprox(e.information.transpose()), field,
            "information must be finite and symmetric");
    require(Eigen::LDLT<Eigen::Matrix3d>(e.information).isPositive() && e.information.determinant() > 0, field,
            "information must be positive definite");
    require(std::isfinite(e.measurement.x) && std::isfinite(e.measurement.y) && std::isfinite(e.measurement.yaw), field,
            "measurement must be finite");
    require(e.loss == RobustLoss::None || (std::isfinite(e.loss_scale) && e.loss_scale > 0), field, "loss_scale must be > 0");
  }
}

}  // namespace

Eigen::Vector3d pose_graph_residual(const Pose2& from, const Pose2& to, const Pose2& z) {
  const Eigen::Vector2d d(to.x - from.x, to.y - from.y);
  const Eigen::Vector2d t = rotation(z.yaw).transpose() * (rotation(from.yaw).transpose() * d - Eigen::Vector2d(z.x, z.y));
  return {t.x(), t.y(), wrap_angle(to.yaw - from.yaw - z.yaw)};
}

double robust_loss(RobustLoss loss, double scale, double s) {
  const double k2 = scale * scale;
  switch (loss) {
    case RobustLoss::None:
      return s;
    case RobustLoss::Huber:
      return s <= k2 ? s : 2.0 * scale * std::sqrt(s) - k2;
    case RobustLoss::Cauchy:
      return k2 * std::log1p(s / k2);
  }
  return s;
}

double robust_weight(RobustLoss loss, double scale, double s) {
  const double k2 = scale * scale;
  switch (loss) {
    case RobustLoss::None:
      return 1.0;
    case RobustLoss::Huber:
      return s <= k2 ? 1.0 : scale / std::sqrt(s);
    case RobustLoss::Cauchy:
      return 1.0 / (1.0 + s / k2);
  }
  return 1.0;
}

double pose_graph_cost(const std::vector<Pose2>& poses, const std::vector<PoseGraphEdge>& edges) {
  double cost = 0.0;
  for (const PoseGraphEdge& e : edges) {
    const Eigen::Vector3d r = pose_graph_residual(poses[e.from], poses[e.to], e.measurement);
    cost += robust_loss(e.loss, e.loss_scale, r.dot(e.information * r));
  }
  return cost;
}

PoseGraphReport optimise_pose_graph(std::vector<Pose2>& poses, const std::vector<PoseGraphEdge>& edges,
                                    const PoseGraphOptions& options) {
  check_edges(poses.size(), edges);
  PoseGraphReport report;
  report.initial_cost = report.final_cost = pose_graph_cost(poses, edges);
  if (poses.size() < 2 || edges.empty()) return report;
  const Eigen::Index n = static_cast<Eigen::Index>(3 * (poses.size() - 1));  // node 0 is fixed
  auto column = [](std::size_t node) { return static_cast<Eigen::Index>(3 * (node - 1)); };
  SparseLevenbergMarquardt lm;
  double cost = report.initial_cost;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(edges.size() * 36);
  for (int it = 0; it < options.max_iterations; ++it) {
    triplets.clear();
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
    for (const PoseGraphEdge& e : edges) {
      const Pose2& pi = poses[e.from];
      const Pose2& pj = poses[e.to];
      const Eigen::Vector3d r = pose_graph_residual(pi, pj, e.measurement);
      const double w = robust_weight(e.loss, e.loss_scale, r.dot(e.information * r));
      const Eigen::Matrix2d rz_t = rotation(e.measurement.yaw).transpose();
      const Eigen::Matrix2d a = rz_t * rotation(pi.yaw).transpose();
      const double c = std::cos(pi.yaw), s = std::sin(pi.yaw);
      const Eigen::Vector2d d(pj.x - pi.x, pj.y - pi.y);
      const Eigen::Vector2d dyaw = rz_t * (Eigen::Matrix2d() << -s, c, -c, -s).finished() * d;
      Eigen::Matrix3d ji = Eigen::Matrix3d::Zero(), jj = Eigen::Matrix3d::Zero();
      ji.block<2, 2>(0, 0) = -a;
      ji.block<2, 1>(0, 2) = dyaw;
      ji(2, 2) = -1.0;
      jj.block<2, 2>(0, 0) = a;
      jj(2, 2) = 1.0;
      const Eigen::Matrix3d omega = w * e.information;
      const std::size_t nodes[2] = {e.from, e.to};
      const Eigen::Matrix3d* jac[2] = {&ji, &jj};
      for (int p = 0; p < 2; ++p) {
        if (nodes[p] == 0) continue;
        b.segment<3>(column(nodes[p])) += jac[p]->transpose() * omega * r;
        for (int q = 0; q < 2; ++q) {
          if (nodes[q] == 0) continue;
          const Eigen::Matrix3d h = jac[p]->transpose() * omega * *jac[q];
          for (int u = 0; u < 3; ++u)
            for (int v = 0; v < 3; ++v) {
              const Eigen::Index row = column(nodes[p]) + u, col = column(nodes[q]) + v;
              if (row >= col) triplets.emplace_back(row, col, h(u, v));  // the lower triangle
              if (row == col) diagonal(row) += h(u, v);
            }
        }
      }
    }
    const auto step = lm.step(
        triplets, diagonal, b, poses, cost, options.relative_tolerance,
        [&](const Eigen::VectorXd& delta) {
          std::vector<Pose2> moved = poses;
          for (std::size_t k = 1; k < poses.size(); ++k) {
            const Eigen::Index c0 = column(k);
            moved[k] = Pose2(poses[k].x + delta(c0), poses[k].y + delta(c0 + 1), wrap_angle(poses[k].yaw + delta(c0 + 2)));
          }
          return moved;
        },
        [&](const std::vector<Pose2>& candidate) { return pose_graph_cost(candidate, edges); });
    if (step == SparseLevenbergMarquardt::Step::Failed) break;
    ++report.iterations;
    if (step == SparseLevenbergMarquardt::Step::Converged) break;
  }
  report.final_cost = cost;
  return report;
}

RobustLoss parse_robust_loss(const std::string& text) {
  if (text == "none") return RobustLoss::None;
  if (text == "huber") return RobustLoss::Huber;
  if (text == "cauchy") return RobustLoss::Cauchy;
  throw Error("unknown robust loss '" + text + "' (none, huber, cauchy)", {}, 0, "loss");
}

std::string robust_loss_name(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::None:
      return "none";
    case RobustLoss::Huber:
      return "huber";
    case RobustLoss::Cauchy:
      return "cauchy";
  }
  return "none";
}

}  // namespace starnav
