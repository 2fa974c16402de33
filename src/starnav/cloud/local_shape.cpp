#include "starnav/cloud/local_shape.hpp"

#include <Eigen/Eigenvalues>

namespace starnav {

std::vector<LocalShape> local_shapes(const KdTree3& tree, std::size_t k) {
  const std::vector<Vec3>& pts = tree.points();
  std::vector<LocalShape> out(pts.size());
  std::vector<Neighbour> nn;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    tree.k_nearest(pts[i], k, nn);
    if (nn.size() < 3) continue;
    Vec3 mean = Vec3::Zero();
    for (const Neighbour& n : nn) mean += pts[n.index];
    mean /= static_cast<double>(nn.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Neighbour& n : nn) {
      const Vec3 d = pts[n.index] - mean;
      cov += d * d.transpose();
    }
    cov /= static_cast<double>(nn.size());
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(cov);
    const Eigen::Vector3d ev = eig.eigenvalues();
    LocalShape& s = out[i];
    s.covariance = cov;
    // Collinear (or coincident) neighbours: the second eigenvalue vanishes and no plane is defined.
    s.valid = ev(1) > 1e-12 * std::max(ev(2), 1e-300);
    Vec3 n = eig.eigenvectors().col(0);
    if (n.dot(pts[i]) > 0) n = -n;  // towards the sensor at the origin
    s.normal = n.normalized();
  }
  return out;
}

Eigen::Matrix3d plane_regularised(const Eigen::Matrix3d& covariance, double epsilon) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(covariance);
  const Eigen::Matrix3d& v = eig.eigenvectors();
  return v * Eigen::Vector3d(epsilon, 1.0, 1.0).asDiagonal() * v.transpose();
}

}  // namespace starnav
