#pragma once
// The local shape of a cloud around each point, from its k nearest neighbours (the point itself
// included): the neighbourhood's covariance and its surface normal (the eigenvector of the
// smallest eigenvalue, oriented towards the sensor's origin). Point-to-plane ICP uses the
// normals, GICP the covariances regularised as Segal et al. 2009 do (the eigenvalues replaced by
// (epsilon, 1, 1) so every point is a small disc on its surface).
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "starnav/cloud/kd_tree.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav {

struct LocalShape {
  Vec3 normal = Vec3::UnitZ();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  bool valid = false;  // false with fewer than 3 neighbours or collinear ones
};

// One LocalShape per point of `tree` from its `k` nearest neighbours (k >= 3).
std::vector<LocalShape> local_shapes(const KdTree3& tree, std::size_t k);

// Each point's covariance from its k nearest neighbours, regularised as plane_regularised does
// (the identity where no plane is defined): GICP's and VGICP's per-point covariances. One
// eigen decomposition per point; the same bytes on any pool.
std::vector<Eigen::Matrix3d> disc_covariances(const KdTree3& tree, std::size_t k, double epsilon,
                                              ThreadPool* pool = nullptr);

// The covariance with eigenvalues (epsilon, 1, 1) along its eigenvectors (smallest first).
Eigen::Matrix3d plane_regularised(const Eigen::Matrix3d& covariance, double epsilon);

}  // namespace starnav
