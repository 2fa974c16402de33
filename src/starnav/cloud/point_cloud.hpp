#pragma once
// Point clouds and rigid transforms in 3D. A cloud is a plain vector of points (metres, in the
// frame its producer states); registration works on `std::span<const Vec3>` so any contiguous
// storage serves. Rigid transforms are Eigen::Isometry3d: `T * p` maps a point of the source
// frame into the target frame.
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "starnav/core/geometry.hpp"

namespace starnav {

using PointCloud = std::vector<Vec3>;
using Rigid3 = Eigen::Isometry3d;

// `transform * p` for every point.
PointCloud transform_cloud(std::span<const Vec3> points, const Rigid3& transform);

// The rigid transform exp(xi) for xi = (omega, v) in se(3): rotation by the axis-angle omega and
// the translation V(omega) v (Rodrigues' formula and its left Jacobian).
Rigid3 se3_exp(const Eigen::Matrix<double, 6, 1>& xi);

// The rotation angle of `transform` (rad, in [0, pi]) and its translation's length (m): the two
// numbers every registration error is reported in.
double rotation_angle(const Rigid3& transform);
double translation_norm(const Rigid3& transform);

// Pose3 <-> Rigid3.
Rigid3 to_rigid(const Pose3& pose);
Pose3 to_pose3(const Rigid3& transform);

// The axis-aligned bounds of a cloud (min, max); both zero for an empty cloud.
struct CloudBounds {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();
};
CloudBounds cloud_bounds(std::span<const Vec3> points);

}  // namespace starnav
