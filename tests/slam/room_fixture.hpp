#pragma once
// A furnished room for the SLAM tests, and exact scans of it by ray casting.
#include <algorithm>
#include <cmath>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/geometry.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/logs/robot_log.hpp"

namespace starnav::test {

// A 6 m x 4 m room with a 1 m x 0.5 m box and a pillar: segments in the world frame.
struct Segment {
  Vec2 a, b;
};
inline const std::vector<Segment> kRoom = {
    {{0, 0}, {6, 0}}, {{6, 0}, {6, 4}}, {{6, 4}, {0, 4}}, {{0, 4}, {0, 0}},
    {{4, 1}, {5, 1}}, {{5, 1}, {5, 1.5}}, {{5, 1.5}, {4, 1.5}}, {{4, 1.5}, {4, 1}},
    {{1.5, 3.0}, {1.8, 3.0}}, {{1.8, 3.0}, {1.8, 3.3}}, {{1.8, 3.3}, {1.5, 3.3}}, {{1.5, 3.3}, {1.5, 3.0}},
};

// Ray-casts `beams` beams from `pose`: beam i at -pi + 2 pi i / beams in the sensor frame, `no_return` where
// nothing is hit.
inline std::vector<float> ranges_from(const Pose2& pose, int beams, float no_return, const std::vector<Segment>& world = kRoom) {
  std::vector<float> out(static_cast<std::size_t>(beams), no_return);
  for (int i = 0; i < beams; ++i) {
    const double a = pose.yaw - kPi + 2 * kPi * i / beams;
    const Vec2 d(std::cos(a), std::sin(a));
    double best = 1e9;
    for (const Segment& s : world) {
      const Vec2 e = s.b - s.a;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const Vec2 w = s.a - pose.translation();
      const double t = (w.x() * e.y() - w.y() * e.x()) / den;
      const double u = (w.x() * d.y() - w.y() * d.x()) / den;
      if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
    }
    if (best < 30) out[static_cast<std::size_t>(i)] = static_cast<float>(best);
  }
  return out;
}

// A square ring corridor 3 m wide between a 20 m x 14 m outer wall and a 14 m x 8 m inner block,
// with 0.3 m posts along both walls at uneven spacing (so no stretch of it is a featureless
// corridor).
inline std::vector<Segment> ring_world() {
  std::vector<Segment> w = {{{0, 0}, {20, 0}}, {{20, 0}, {20, 14}}, {{20, 14}, {0, 14}}, {{0, 14}, {0, 0}},
                            {{3, 3}, {17, 3}}, {{17, 3}, {17, 11}}, {{17, 11}, {3, 11}}, {{3, 11}, {3, 3}}};
  const auto post = [&w](double x, double y) {
    const double h = 0.15;
    w.push_back({{x - h, y - h}, {x + h, y - h}});
    w.push_back({{x + h, y - h}, {x + h, y + h}});
    w.push_back({{x + h, y + h}, {x - h, y + h}});
    w.push_back({{x - h, y + h}, {x - h, y - h}});
  };
  for (double x : {2.1, 4.9, 6.3, 9.8, 12.2, 13.1, 16.4, 18.7}) post(x, 0.15), post(x + 0.7, 3.0 - 0.15 + 0.3 * (x > 10));
  for (double x : {1.4, 3.8, 7.7, 8.6, 11.9, 15.2, 17.9}) post(x, 13.85), post(x + 0.5, 11.15);
  for (double y : {1.7, 4.4, 6.1, 9.3, 12.6}) post(0.15, y), post(19.85, y + 0.4);
  for (double y : {4.2, 5.9, 8.8}) post(2.85, y), post(17.15, y - 0.6);
  return w;
}

// The hit points of `beams` beams from `pose` in `world` out to `max_range_m`, in the sensor frame
// and beam order.
inline std::vector<Vec2> scan_from(const Pose2& pose, int beams = 360, const std::vector<Segment>& world = kRoom, double max_range_m = 30.0) {
  const std::vector<float> r = ranges_from(pose, beams, 100.0f, world);
  std::vector<Vec2> out;
  for (int i = 0; i < beams; ++i) {
    const double a = -kPi + 2 * kPi * i / beams;
    if (r[static_cast<std::size_t>(i)] <= max_range_m) out.push_back(static_cast<double>(r[static_cast<std::size_t>(i)]) * Vec2(std::cos(a), std::sin(a)));
  }
  return out;
}

// A drive around the ring corridor and 8 m past the start, odometry over-reading turns by 3 %.
inline RobotLog ring_drive(std::vector<Pose2>& truth) {
  const std::vector<Segment> world = ring_world();
  // The corridor's centre line: a rounded rectangle from (1.5, 1.5) to (18.5, 12.5).
  std::vector<Pose2> path;
  const double x0 = 1.5, y0 = 1.5, x1 = 18.5, y1 = 12.5, step = 0.1;
  const auto leg = [&](Vec2 a, Vec2 b) {
    const double yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
    const int n = static_cast<int>(std::round((b - a).norm() / step));
    for (int k = 0; k < n; ++k) path.emplace_back(a.x() + (b.x() - a.x()) * k / n, a.y() + (b.y() - a.y()) * k / n, yaw);
  };
  leg({x0, y0}, {x1, y0});
  leg({x1, y0}, {x1, y1});
  leg({x1, y1}, {x0, y1});
  leg({x0, y1}, {x0, y0});
  leg({x0, y0}, {x0 + 8.0, y0});
  RobotLog log;
  Rng rng(9);
  Pose2 odom = path.front();
  for (std::size_t k = 0; k < path.size(); ++k) {
    if (k > 0) {
      const Pose2 d = path[k - 1].inverse().compose(path[k]);
      odom = odom.compose(Pose2(d.x * 1.01, d.y, d.yaw * 1.03));
    }
    LogScan scan;
    scan.stamp_us = static_cast<std::int64_t>(k) * 200'000;
    scan.angle_min_rad = -kPi;
    scan.angle_increment_rad = 2 * kPi / 360;
    scan.range_max_m = 30.0;
    scan.ranges_m = ranges_from(path[k], 360, 40.0f, world);
    for (float& r : scan.ranges_m)
      if (r < 30) r += static_cast<float>(0.01 * rng.normal());
    scan.odometry = odom;
    scan.source_index = k + 1;
    log.scans.push_back(std::move(scan));
  }
  truth = path;
  return log;
}

}  // namespace starnav::test
