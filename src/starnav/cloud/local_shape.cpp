#include "starnav/cloud/local_shape.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace starnav {

namespace {

// The covariance of the neighbours about their mean and its eigen decomposition; false with fewer
// than 3 neighbours or collinear (or coincident) ones, where no plane is defined.
bool fit_neighbourhood(const std::vector<Vec3>& pts, const std::vector<Neighbour>& nn, Eigen::Matrix3d& cov,
                       Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& eig) {
  if (nn.size() < 3) return false;
  Vec3 mean = Vec3::Zero();
  for (const Neighbour& n : nn) mean += pts[n.index];
  mean /= static_cast<double>(nn.size());
  cov.setZero();
  for (const Neighbour& n : nn) {
    const Vec3 d = pts[n.index] - mean;
    cov += d * d.transpose();
  }
  cov /= static_cast<double>(nn.size());
  eig.computeDirect(cov);
  const Eigen::Vector3d ev = eig.eigenvalues();
  return ev(1) > 1e-12 * std::max(ev(2), 1e-300);
}

// The same covariance in one pass over the neighbours: sums of d and d d^T with d taken from the
// first neighbour (the query itself, so the sums stay small and cancel nothing), the upper
// triangle only.
bool fit_neighbourhood_one_pass(const std::vector<Vec3>& pts, const std::uint32_t* nn, std::size_t n,
                                Eigen::Matrix3d& cov, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& eig) {
  if (n < 3) return false;
  const Vec3 o = pts[nn[0]];
  double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3& p = pts[nn[j]];
    const double x = p.x() - o.x(), y = p.y() - o.y(), z = p.z() - o.z();
    sx += x;
    sy += y;
    sz += z;
    sxx += x * x;
    sxy += x * y;
    sxz += x * z;
    syy += y * y;
    syz += y * z;
    szz += z * z;
  }
  const double inv = 1.0 / static_cast<double>(n);
  const double mx = sx * inv, my = sy * inv, mz = sz * inv;
  cov(0, 0) = sxx * inv - mx * mx;
  cov(1, 1) = syy * inv - my * my;
  cov(2, 2) = szz * inv - mz * mz;
  cov(0, 1) = cov(1, 0) = sxy * inv - mx * my;
  cov(0, 2) = cov(2, 0) = sxz * inv - mx * mz;
  cov(1, 2) = cov(2, 1) = syz * inv - my * mz;
  eig.computeDirect(cov);
  const Eigen::Vector3d ev = eig.eigenvalues();
  return ev(1) > 1e-12 * std::max(ev(2), 1e-300);
}

Eigen::Matrix3d disc(const Eigen::Matrix3d& eigenvectors, double epsilon) {
  return eigenvectors * Eigen::Vector3d(epsilon, 1.0, 1.0).asDiagonal() * eigenvectors.transpose();
}

constexpr std::size_t kShapeChunk = 512;

}  // namespace

std::vector<LocalShape> local_shapes(const KdTree3& tree, std::size_t k) {
  const std::vector<Vec3>& pts = tree.points();
  std::vector<LocalShape> out(pts.size());
  std::vector<Neighbour> nn;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    tree.k_nearest(pts[i], k, nn);
    LocalShape& s = out[i];
    if (nn.size() < 3) continue;
    s.valid = fit_neighbourhood(pts, nn, s.covariance, eig);
    Vec3 n = eig.eigenvectors().col(0);
    if (n.dot(pts[i]) > 0) n = -n;  // towards the sensor at the origin
    s.normal = n.normalized();
  }
  return out;
}

std::vector<Eigen::Matrix3d> disc_covariances(const KdTree3& tree, std::size_t k, double epsilon, ThreadPool* pool) {
  const std::vector<Vec3>& pts = tree.points();
  std::vector<Eigen::Matrix3d> out(pts.size());
  const std::size_t chunks = (pts.size() + kShapeChunk - 1) / kShapeChunk;
  // Every point's covariance is its own, so any split over threads gives the same bytes.
  // Points are taken in the tree's leaf order, so consecutive searches share their memory.
  const std::vector<std::uint32_t>& order = tree.leaf_order();
  k = std::min(k, pts.size());
  auto task = [&](std::size_t c) {
    std::vector<std::uint32_t> nn(k);
    std::vector<double> dist(k);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    Eigen::Matrix3d cov;
    // The previous point's k-th neighbour distance plus the step to this point bounds this
    // point's (triangle inequality), with a margin for rounding.
    Vec3 previous = Vec3::Zero();
    double previous_kth = kInfinity;
    const std::size_t end = std::min(pts.size(), (c + 1) * kShapeChunk);
    for (std::size_t j = c * kShapeChunk; j < end; ++j) {
      const std::uint32_t i = order[j];
      const double reach = std::sqrt(previous_kth) + (pts[i] - previous).norm();
      const double bound = previous_kth < kInfinity ? reach * reach * (1.0 + 1e-9) + 1e-12 : kInfinity;
      const std::size_t n = tree.k_nearest(pts[i], k, nn.data(), dist.data(), bound);
      previous = pts[i];
      previous_kth = n == k ? dist[k - 1] : kInfinity;
      // A point without a surface around it counts as a small isotropic blob.
      out[i] = fit_neighbourhood_one_pass(pts, nn.data(), n, cov, eig) ? disc(eig.eigenvectors(), epsilon)
                                                                        : Eigen::Matrix3d::Identity();
    }
  };
  if (pool && pool->size() > 1) {
    pool->run(chunks, task);
  } else {
    for (std::size_t c = 0; c < chunks; ++c) task(c);
  }
  return out;
}

Eigen::Matrix3d plane_regularised(const Eigen::Matrix3d& covariance, double epsilon) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(covariance);
  return disc(eig.eigenvectors(), epsilon);
}

}  // namespace starnav
