#pragma once
// Vectors and poses (REP-103: x forward, y left, z up; yaw counter-clockwise from +x).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "starnav/core/angle.hpp"

namespace starnav {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The farthest a position read from a file (a pose, a point) may lie from its frame's origin: a
// million kilometres, beyond any site a robot maps and well inside what grids and pictures can
// index. A farther value is corrupt and is refused where it is read.
inline constexpr double kMaxCoordinateM = 1e9;
inline bool plausible_coordinate(double v) { return std::abs(v) <= kMaxCoordinateM; }  // false for NaN

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

// A pose in the plane: position and heading.
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;

  Pose2() = default;
  Pose2(double x_, double y_, double yaw_) : x(x_), y(y_), yaw(yaw_) {}

  Vec2 translation() const { return {x, y}; }
  Eigen::Matrix2d rotation() const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    Eigen::Matrix2d r;
    r << c, -s, s, c;
    return r;
  }
  // Maps a point given in this pose's frame into the parent frame.
  Vec2 transform(const Vec2& p) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
  // Maps a point given in the parent frame into this pose's frame.
  Vec2 inverse_transform(const Vec2& p) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    const double dx = p.x() - x, dy = p.y() - y;
    return {c * dx + s * dy, -s * dx + c * dy};
  }
  // this * other: `other` expressed in this pose's frame, returned in the parent frame.
  Pose2 compose(const Pose2& other) const {
    const Vec2 t = transform(other.translation());
    return {t.x(), t.y(), wrap_angle(yaw + other.yaw)};
  }
  Pose2 inverse() const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {-(c * x + s * y), -(-s * x + c * y), wrap_angle(-yaw)};
  }
};

// A pose in space; attitude as R = Rz(yaw) * Ry(pitch) * Rx(roll) (conventions.md).
// A planar body velocity in base_link (geometry_msgs/Twist's x, y and angular z).
struct BodyTwist {
  double vx = 0.0;  // m/s forward
  double vy = 0.0;  // m/s left
  double wz = 0.0;  // rad/s counter-clockwise
};

struct Pose3 {
  Vec3 position = Vec3::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();

  static Pose3 from_rpy(const Vec3& position, double roll, double pitch, double yaw) {
    Pose3 p;
    p.position = position;
    p.orientation = Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                    Eigen::AngleAxisd(roll, Vec3::UnitX());
    return p;
  }
  Eigen::Matrix3d rotation() const { return orientation.toRotationMatrix(); }
  Vec3 transform(const Vec3& p) const { return position + orientation * p; }
  Vec3 inverse_transform(const Vec3& p) const { return orientation.conjugate() * (p - position); }
  Pose3 compose(const Pose3& other) const {
    Pose3 r;
    r.position = transform(other.position);
    r.orientation = (orientation * other.orientation).normalized();
    return r;
  }
  Pose3 inverse() const {
    Pose3 r;
    r.orientation = orientation.conjugate();
    r.position = -(r.orientation * position);
    return r;
  }
  // Roll, pitch, yaw of R = Rz(yaw) Ry(pitch) Rx(roll); pitch in [-pi/2, pi/2]. Accurate to
  // rounding everywhere, also at and near gimbal lock (pitch = +-pi/2), where roll is set to 0
  // and the whole rotation about z goes into yaw.
  Vec3 rpy() const {
    const Eigen::Matrix3d r = rotation();
    // R's last row is (-sin p, cos p sin r, cos p cos r).
    double roll = 0.0;
    if (std::hypot(r(2, 1), r(2, 2)) > 1e-12) roll = std::atan2(r(2, 1), r(2, 2));
    // Undo the roll: N = R Rx(roll)^T = Rz(yaw) Ry(pitch) = [cy cp, -sy, cy sp; sy cp, cy, sy sp; -sp, 0, cp].
    // Pitch from (N20, N22) and yaw from N's middle column stay well conditioned near the lock
    // (unlike asin(-R20) or atan2(R10, R00)).
    const double cr = std::cos(roll), sr = std::sin(roll);
    const double n22 = sr * r(2, 1) + cr * r(2, 2);
    const double n01 = cr * r(0, 1) - sr * r(0, 2);
    const double n11 = cr * r(1, 1) - sr * r(1, 2);
    const double pitch = std::atan2(-r(2, 0), n22);
    const double yaw = std::atan2(-n01, n11);
    return {roll, pitch, yaw};
  }
  Pose2 to_pose2() const { return {position.x(), position.y(), rpy().z()}; }
};

}  // namespace starnav
