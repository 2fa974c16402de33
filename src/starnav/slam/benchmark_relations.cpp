#include "starnav/slam/benchmark_relations.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {

PoseRelation relation_between(const TrajectoryPose& a, const TrajectoryPose& b) {
  PoseRelation r;
  r.t_i_us = a.stamp_us;
  r.t_j_us = b.stamp_us;
  r.tolerance_us = 1;
  r.delta = a.pose.inverse().compose(b.pose);
  return r;
}

}  // namespace

BenchmarkRelations make_benchmark_relations(const std::vector<TrajectoryPose>& poses, const RelationRule& rule) {
  if (!(rule.key_distance_m > 0.0) || !std::isfinite(rule.key_distance_m)) throw Error("must be > 0", {}, 0, "key_distance_m");
  if (!(rule.key_angle_deg > 0.0) || !std::isfinite(rule.key_angle_deg)) throw Error("must be > 0", {}, 0, "key_angle_deg");
  if (!(rule.loop_max_distance_m > 0.0) || !std::isfinite(rule.loop_max_distance_m))
    throw Error("must be > 0", {}, 0, "loop_max_distance_m");
  if (!(rule.loop_min_travel_m >= 0.0) || !std::isfinite(rule.loop_min_travel_m)) throw Error("must be >= 0", {}, 0, "loop_min_travel_m");
  if (rule.loop_every < 1) throw Error("must be >= 1", {}, 0, "loop_every");
  for (std::size_t i = 1; i < poses.size(); ++i)
    if (poses[i].stamp_us <= poses[i - 1].stamp_us)
      throw Error("stamps must increase (" + format_stamp_us(poses[i].stamp_us) + " after " + format_stamp_us(poses[i - 1].stamp_us) + ")",
                  {}, 0, "poses");
  BenchmarkRelations out;
  if (poses.empty()) return out;
  // Key poses and the travel up to each.
  std::vector<std::size_t> keys = {0};
  std::vector<double> travel = {0.0};
  double total = 0.0, since_distance = 0.0, since_angle = 0.0;
  const double key_angle = deg_to_rad(rule.key_angle_deg);
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const Pose2& a = poses[i - 1].pose;
    const Pose2& b = poses[i].pose;
    const double step = std::hypot(b.x - a.x, b.y - a.y);
    total += step;
    since_distance += step;
    since_angle += std::abs(wrap_angle(b.yaw - a.yaw));
    if (since_distance >= rule.key_distance_m || since_angle >= key_angle) {
      keys.push_back(i);
      travel.push_back(total);
      since_distance = since_angle = 0.0;
    }
  }
  out.key_poses = keys.size();
  for (std::size_t k = 0; k + 1 < keys.size(); ++k) out.relations.push_back(relation_between(poses[keys[k]], poses[keys[k + 1]]));
  out.local = out.relations.size();
  // Loops: key poses hashed into cells as wide as the distance limit; a query looks at 3 x 3.
  const double cell = rule.loop_max_distance_m;
  const auto cell_of = [&](const Pose2& p) {
    return std::pair<long long, long long>{static_cast<long long>(std::floor(p.x / cell)), static_cast<long long>(std::floor(p.y / cell))};
  };
  const auto hash = [](const std::pair<long long, long long>& c) {
    return static_cast<std::size_t>(c.first) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::size_t>(c.second);
  };
  std::unordered_map<std::pair<long long, long long>, std::vector<std::size_t>, decltype(hash)> cells(16, hash);
  for (std::size_t k = 0; k < keys.size(); ++k) cells[cell_of(poses[keys[k]].pose)].push_back(k);
  std::vector<std::size_t> near;
  for (std::size_t k = 0; k < keys.size(); k += static_cast<std::size_t>(rule.loop_every)) {
    const Pose2& p = poses[keys[k]].pose;
    const auto [cx, cy] = cell_of(p);
    near.clear();
    for (long long dy = -1; dy <= 1; ++dy)
      for (long long dx = -1; dx <= 1; ++dx) {
        const auto it = cells.find({cx + dx, cy + dy});
        if (it == cells.end()) continue;
        for (std::size_t m : it->second) {
          const Pose2& q = poses[keys[m]].pose;
          if (m > k && travel[m] - travel[k] >= rule.loop_min_travel_m && std::hypot(q.x - p.x, q.y - p.y) <= rule.loop_max_distance_m)
            near.push_back(m);
        }
      }
    std::sort(near.begin(), near.end());
    for (std::size_t s = 0; s < near.size();) {
      std::size_t e = s, best = near[s];
      double best_d = std::hypot(poses[keys[best]].pose.x - p.x, poses[keys[best]].pose.y - p.y);
      while (e + 1 < near.size() && near[e + 1] == near[e] + 1) {
        ++e;
        const Pose2& q = poses[keys[near[e]]].pose;
        const double d = std::hypot(q.x - p.x, q.y - p.y);
        if (d < best_d) best_d = d, best = near[e];
      }
      out.relations.push_back(relation_between(poses[keys[k]], poses[keys[best]]));
      ++out.loops;
      s = e + 1;
    }
  }
  return out;
}

std::string relations_text(const std::vector<PoseRelation>& relations) {
  std::ostringstream o;
  for (const PoseRelation& r : relations)
    o << format_stamp_us(r.t_i_us) << ' ' << format_stamp_us(r.t_j_us) << ' ' << format_fixed(r.delta.x, 6) << ' '
      << format_fixed(r.delta.y, 6) << " 0.000000 0.000000 0.000000 " << format_fixed(r.delta.yaw, 6) << '\n';
  return o.str();
}

std::vector<TrajectoryPose> log_truth_at_scans(const RobotLog& log) {
  if (log.truth.empty()) throw Error("holds no ground truth (TRUEPOS lines: a simulated log)", log.path, 0, "TRUEPOS");
  const std::vector<LogOdometry> truth = truth_readings(log);
  std::vector<TrajectoryPose> out;
  out.reserve(log.scans.size());
  for (const LogScan& s : log.scans) {
    if (s.stamp_us < truth.front().stamp_us || s.stamp_us > truth.back().stamp_us) continue;
    out.push_back({s.stamp_us, laser_pose(log, *odometry_at(truth, s.stamp_us))});
  }
  std::sort(out.begin(), out.end(), [](const TrajectoryPose& a, const TrajectoryPose& b) { return a.stamp_us < b.stamp_us; });
  out.erase(std::unique(out.begin(), out.end(), [](const TrajectoryPose& a, const TrajectoryPose& b) { return a.stamp_us == b.stamp_us; }),
            out.end());
  return out;
}

}  // namespace starnav
