#include "starnav/cloud/point_cloud.hpp"

#include <algorithm>
#include <cmath>

namespace starnav {

PointCloud transform_cloud(std::span<const Vec3> points, const Rigid3& transform) {
  PointCloud out;
  out.reserve(points.size());
  const Eigen::Matrix3d r = transform.linear();
  const Vec3 t = transform.translation();
  for (const Vec3& p : points) out.push_back(r * p + t);
  return out;
}

Rigid3 se3_exp(const Eigen::Matrix<double, 6, 1>& xi) {
  const Vec3 omega = xi.head<3>(), v = xi.tail<3>();
  const double theta = omega.norm();
  Eigen::Matrix3d w;
  w << 0, -omega.z(), omega.y(), omega.z(), 0, -omega.x(), -omega.y(), omega.x(), 0;
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity(), left = Eigen::Matrix3d::Identity();
  if (theta < 1e-10) {
    r += w;
    left += 0.5 * w;
  } else {
    const double a = std::sin(theta) / theta, b = (1 - std::cos(theta)) / (theta * theta);
    const double c = (theta - std::sin(theta)) / (theta * theta * theta);
    r += a * w + b * w * w;
    left += b * w + c * w * w;
  }
  Rigid3 t = Rigid3::Identity();
  t.linear() = r;
  t.translation() = left * v;
  return t;
}

double rotation_angle(const Rigid3& transform) {
  const double c = std::clamp((transform.linear().trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c);
}

double translation_norm(const Rigid3& transform) { return transform.translation().norm(); }

Rigid3 to_rigid(const Pose3& pose) {
  Rigid3 t = Rigid3::Identity();
  t.linear() = pose.rotation();
  t.translation() = pose.position;
  return t;
}

Pose3 to_pose3(const Rigid3& transform) {
  Pose3 p;
  p.position = transform.translation();
  p.orientation = Eigen::Quaterniond(transform.linear()).normalized();
  return p;
}

CloudBounds cloud_bounds(std::span<const Vec3> points) {
  CloudBounds b;
  if (points.empty()) return b;
  b.min = b.max = points.front();
  for (const Vec3& p : points) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  return b;
}

}  // namespace starnav
