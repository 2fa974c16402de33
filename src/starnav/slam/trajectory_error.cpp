#include "starnav/slam/trajectory_error.hpp"

#include <cmath>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

namespace {

// map_server's thresholds; values between them are neither wall nor free run.
constexpr OccupancyThresholds kThresholds{};

bool occupied(std::int8_t v) { return v >= kThresholds.occupied_percent; }
bool free_cell(std::int8_t v) { return v >= 0 && v <= kThresholds.free_percent; }

}  // namespace

AbsoluteTrajectoryError absolute_trajectory_error(const std::vector<TrajectoryPose>& trajectory, const RobotLog& log) {
  if (log.truth.empty()) throw Error("holds no ground truth", log.path, 0, "TRUEPOS");
  const std::vector<LogOdometry> truth = truth_readings(log);
  std::vector<double> d, a;
  AbsoluteTrajectoryError e;
  double sum2 = 0.0;
  for (const TrajectoryPose& p : trajectory) {
    if (p.stamp_us < truth.front().stamp_us || p.stamp_us > truth.back().stamp_us) {
      ++e.unmatched;
      continue;
    }
    const Pose2 t = *odometry_at(truth, p.stamp_us);
    const double dist = (p.pose.translation() - t.translation()).norm();
    d.push_back(dist);
    a.push_back(std::abs(rad_to_deg(wrap_angle(p.pose.yaw - t.yaw))));
    sum2 += dist * dist;
  }
  e.rmse_m = d.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(d.size()));
  e.translation_m = sample_stats(std::move(d));
  e.rotation_deg = sample_stats(std::move(a));
  return e;
}

namespace {

// The built map's distance along `w`'s line, or nullopt when not seen.
std::optional<double> measure(const OccupancyGrid& built, const WallDistance& w) {
  const double rb = built.resolution();
  const Vec2 ob = built.origin().translation();
  const int cx = static_cast<int>(std::floor((w.midpoint.x() - ob.x()) / rb)), cy = static_cast<int>(std::floor((w.midpoint.y() - ob.y()) / rb));
  if (!built.contains(cx, cy) || !free_cell(built(cx, cy))) return std::nullopt;
  const int limit = static_cast<int>(std::ceil(w.true_m / rb)) + 20;
  double faces[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    const int step = side == 0 ? -1 : 1;
    bool found = false;
    for (int k = 1; k <= limit && !found; ++k) {
      const int x = w.along_x ? cx + step * k : cx, y = w.along_x ? cy : cy + step * k;
      if (!built.contains(x, y) || built(x, y) < 0) return std::nullopt;
      if (occupied(built(x, y))) {
        // The face: the centre of the first occupied cell, where the hits that made it lie (its
        // near edge would count every cell a hit fell into as wall, a cell's bias per side).
        const int c = w.along_x ? x : y;
        faces[side] = (w.along_x ? ob.x() : ob.y()) + (c + 0.5) * rb;
        found = true;
      }
    }
    if (!found) return std::nullopt;
  }
  return faces[1] - faces[0];
}

}  // namespace

std::vector<WallDistance> wall_distances(const OccupancyGrid& truth, const std::vector<const OccupancyGrid*>& built,
                                         const WallDistanceOptions& o) {
  if (truth.origin().yaw != 0.0) throw Error("the true map's origin has a yaw; wall distances need an unrotated map", {}, 0, "truth");
  for (const OccupancyGrid* b : built)
    if (b->origin().yaw != 0.0) throw Error("a built map's origin has a yaw; wall distances need an unrotated map", {}, 0, "built");
  if (built.empty() || o.stride_cells < 1 || o.count < 1 || !(o.min_length_m > 0) || !(o.max_length_m >= o.min_length_m))
    throw Error("needs a built map, count >= 1, stride >= 1 and 0 < min_length <= max_length", {}, 0, "options");
  const double r = truth.resolution();
  const Vec2 origin = truth.origin().translation();
  // Candidates: free runs bounded by occupied cells on both sides, along rows, then columns,
  // kept when every built map saw them.
  std::vector<WallDistance> candidates;
  for (int axis = 0; axis < 2; ++axis) {
    const int lines = axis == 0 ? truth.height() : truth.width(), length = axis == 0 ? truth.width() : truth.height();
    const auto at = [&](int line, int k) { return axis == 0 ? truth(k, line) : truth(line, k); };
    for (int line = o.stride_cells / 2; line < lines; line += o.stride_cells)
      for (int k = 0; k + 1 < length; ++k) {
        if (!occupied(at(line, k)) || !free_cell(at(line, k + 1))) continue;
        int end = k + 1;
        while (end < length && free_cell(at(line, end))) ++end;
        if (end < length && occupied(at(line, end))) {
          const double span = (end - k - 1) * r;
          if (span >= o.min_length_m && span <= o.max_length_m) {
            WallDistance w;
            w.along_x = axis == 0;
            const double mid = ((k + 1) + end) * 0.5 * r, across = (line + 0.5) * r;
            w.midpoint = axis == 0 ? origin + Vec2(mid, across) : origin + Vec2(across, mid);
            w.true_m = span;
            bool seen = true;
            for (const OccupancyGrid* b : built) {
              const std::optional<double> d = measure(*b, w);
              seen = seen && d.has_value();
              if (d) w.built_m.push_back(*d);
            }
            if (seen) candidates.push_back(w);
          }
        }
        k = end - 1;
      }
  }
  std::vector<WallDistance> out;
  const std::size_t n = std::min(o.count, candidates.size());
  for (std::size_t i = 0; i < n; ++i) out.push_back(candidates[i * candidates.size() / n]);
  return out;
}

double wall_distance_mean_abs_error(const std::vector<WallDistance>& probes, std::size_t map) {
  double sum = 0.0;
  for (const WallDistance& w : probes) sum += std::abs(w.error_m(map));
  return probes.empty() ? 0.0 : sum / static_cast<double>(probes.size());
}

std::string wall_distances_text(const std::vector<WallDistance>& probes, const std::vector<std::string>& names) {
  std::ostringstream o;
  o << "| # | along | midpoint (m) | true (m) |";
  for (const std::string& n : names) o << " " << n << " (m) | " << n << " error (m) |";
  o << "\n|---:|---|---|---:|";
  for (std::size_t i = 0; i < names.size(); ++i) o << "---:|---:|";
  o << "\n";
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const WallDistance& w = probes[i];
    o << "| " << i + 1 << " | " << (w.along_x ? "x" : "y") << " | (" << format_fixed(w.midpoint.x(), 2) << ", " << format_fixed(w.midpoint.y(), 2)
      << ") | " << format_fixed(w.true_m, 3) << " |";
    for (std::size_t m = 0; m < names.size(); ++m) o << " " << format_fixed(w.built_m[m], 3) << " | " << format_fixed(w.error_m(m), 3) << " |";
    o << "\n";
  }
  o << "\n";
  for (std::size_t m = 0; m < names.size(); ++m)
    o << names[m] << ": mean absolute error " << format_fixed(wall_distance_mean_abs_error(probes, m), 4) << " m over " << probes.size()
      << " distances\n";
  return o.str();
}

std::string wall_distances_json(const std::vector<WallDistance>& probes, const std::vector<std::string>& names) {
  nlohmann::ordered_json j;
  j["maps"] = names;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const WallDistance& w : probes)
    rows.push_back({{"along", w.along_x ? "x" : "y"}, {"midpoint", {w.midpoint.x(), w.midpoint.y()}}, {"true_m", w.true_m}, {"built_m", w.built_m}});
  j["distances"] = std::move(rows);
  nlohmann::ordered_json errors = nlohmann::ordered_json::array();
  for (std::size_t m = 0; m < names.size(); ++m) errors.push_back(wall_distance_mean_abs_error(probes, m));
  j["mean_abs_error_m"] = std::move(errors);
  return j.dump(1) + "\n";
}

}  // namespace starnav
