#include "starnav/slam/relative_pose_error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/text_lines.hpp"

namespace starnav {

namespace {

std::int64_t decimals_unit_us(std::string_view stamp) {
  const std::size_t dot = stamp.find('.');
  const std::size_t decimals = dot == std::string_view::npos ? 0 : stamp.size() - dot - 1;
  std::int64_t unit = 1;
  for (std::size_t d = std::min<std::size_t>(decimals, 6); d < 6; ++d) unit *= 10;
  return unit;
}

// The pose nearest in time to t within `tolerance`, or null.
const TrajectoryPose* nearest(const std::vector<TrajectoryPose>& sorted, std::int64_t t, std::int64_t tolerance) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), t,
                                   [](const TrajectoryPose& p, std::int64_t x) { return p.stamp_us < x; });
  const TrajectoryPose* best = nullptr;
  std::int64_t best_d = tolerance + 1;
  for (auto c = it == sorted.begin() ? it : it - 1; c != sorted.end() && c <= it; ++c) {
    const std::int64_t d = std::abs(c->stamp_us - t);
    if (d < best_d) best_d = d, best = &*c;
  }
  return best_d <= tolerance ? best : nullptr;
}

}  // namespace

std::vector<PoseRelation> parse_relations(std::string_view text, const std::string& path, bool whole) {
  std::vector<PoseRelation> out;
  static const char* kColumns[8] = {"t_i", "t_j", "dx", "dy", "dz", "droll", "dpitch", "dyaw"};
  for_each_line(text, [&](std::string_view line, int line_no) {
    const std::vector<std::string_view> f = split_fields(line);
    if (f.empty() || f[0][0] == '#') return;
    if (f.size() != 8) throw Error("expected 8 columns t_i t_j dx dy dz droll dpitch dyaw, got " + std::to_string(f.size()), path, line_no);
    PoseRelation r;
    r.line = line_no;
    if (!parse_stamp_us(f[0], r.t_i_us)) throw Error("expected a time, got '" + printable(f[0], 40) + "'", path, line_no, "t_i");
    if (!parse_stamp_us(f[1], r.t_j_us)) throw Error("expected a time, got '" + printable(f[1], 40) + "'", path, line_no, "t_j");
    r.tolerance_us = std::max(decimals_unit_us(f[0]), decimals_unit_us(f[1]));
    double v[6];
    for (int k = 0; k < 6; ++k) {
      const std::string_view c = f[static_cast<std::size_t>(k + 2)];
      if (!parse_finite_number(c, v[k]))
        throw Error("expected a finite number, got '" + printable(c, 40) + "'", path, line_no, kColumns[k + 2]);
    }
    r.delta = Pose2(v[0], v[1], wrap_angle(v[5]));
    out.push_back(r);
  });
  if (whole && out.empty()) throw Error("holds no relation", path);
  return out;
}

std::vector<PoseRelation> read_relations(const std::string& path) {
  const std::string text = read_text_lines_file(path, kMaxInputFileBytes, "a relation file (t_i t_j dx dy dz droll dpitch dyaw)",
                                                [&](std::string_view head) { parse_relations(head, path, false); });
  return parse_relations(text, path);
}

RelativePoseError relative_pose_error(const std::vector<TrajectoryPose>& trajectory, const std::vector<PoseRelation>& relations,
                                      const Pose2& offset) {
  std::vector<TrajectoryPose> sorted = trajectory;
  std::sort(sorted.begin(), sorted.end(), [](const TrajectoryPose& a, const TrajectoryPose& b) { return a.stamp_us < b.stamp_us; });
  RelativePoseError e;
  e.relations = relations.size();
  std::vector<double> trans, rot;
  for (const PoseRelation& r : relations) {
    const TrajectoryPose* a = nearest(sorted, r.t_i_us, r.tolerance_us);
    const TrajectoryPose* b = nearest(sorted, r.t_j_us, r.tolerance_us);
    if (!a || !b) {
      ++e.unmatched;
      e.translation_each_m.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const Pose2 xi = a->pose.compose(offset), xj = b->pose.compose(offset);
    const Pose2 delta = xi.inverse().compose(xj);
    const Pose2 err = r.delta.inverse().compose(delta);
    trans.push_back(std::hypot(err.x, err.y));
    e.translation_each_m.push_back(trans.back());
    rot.push_back(rad_to_deg(std::abs(wrap_angle(err.yaw))));
  }
  std::vector<double> sorted_trans = trans;
  std::sort(sorted_trans.begin(), sorted_trans.end());
  e.translation_p95_m = quantile_sorted(sorted_trans, 0.95);
  e.translation_m = sample_stats(std::move(trans));
  e.rotation_deg = sample_stats(std::move(rot));
  return e;
}

std::size_t relations_worse_than(const RelativePoseError& e, const RelativePoseError& reference, double margin_m) {
  if (e.translation_each_m.size() != reference.translation_each_m.size())
    throw Error("the two errors were evaluated on different relations (" + std::to_string(e.translation_each_m.size()) + " and " +
                std::to_string(reference.translation_each_m.size()) + ")");
  std::size_t worse = 0;
  for (std::size_t i = 0; i < e.translation_each_m.size(); ++i)
    if (e.translation_each_m[i] > reference.translation_each_m[i] + margin_m) ++worse;  // NaN on either side: not counted
  return worse;
}

RelationSpans relation_spans(const RelativePoseError& e, const std::vector<PoseRelation>& relations, double max_short_s) {
  if (e.translation_each_m.size() != relations.size())
    throw Error("the error was evaluated on other relations (" + std::to_string(e.translation_each_m.size()) + " against " +
                std::to_string(relations.size()) + ")");
  std::vector<double> short_m, long_m;
  for (std::size_t i = 0; i < relations.size(); ++i) {
    const double t = e.translation_each_m[i];
    if (std::isnan(t)) continue;  // unmatched
    const double span_s = static_cast<double>(std::abs(relations[i].t_j_us - relations[i].t_i_us)) * 1e-6;
    (span_s <= max_short_s ? short_m : long_m).push_back(t);
  }
  RelationSpans out;
  for (auto [values, stats, p95] : {std::tuple{&short_m, &out.short_m, &out.short_p95_m}, std::tuple{&long_m, &out.long_m, &out.long_p95_m}}) {
    std::sort(values->begin(), values->end());
    *p95 = quantile_sorted(*values, 0.95);
    *stats = sample_stats(*values);
  }
  return out;
}

namespace {

std::string stats_text(const SampleStats& s, int precision, const char* unit) {
  return format_fixed(s.mean, precision) + " ± " + format_fixed(s.sd, precision) + " " + unit + " (max " +
         format_fixed(s.max, precision) + ")";
}

nlohmann::ordered_json stats_json(const SampleStats& s) {
  return {{"mean", s.mean}, {"sd", s.sd}, {"max", s.max}, {"count", s.n}};
}

nlohmann::ordered_json error_json(const RelativePoseError& e) {
  nlohmann::ordered_json j;
  j["translation_m"] = stats_json(e.translation_m);
  j["translation_m"]["p95"] = e.translation_p95_m;
  j["rotation_deg"] = stats_json(e.rotation_deg);
  j["relations"] = e.relations;
  j["unmatched"] = e.unmatched;
  return j;
}

}  // namespace

std::string rpe_text(const RelativePoseError& base, const std::optional<RelativePoseError>& laser, const Pose2& offset) {
  std::ostringstream out;
  out << "relations:   " << base.relations << " (" << base.translation_m.n << " evaluated, " << base.unmatched
      << " with an end not in the trajectory)\n";
  out << "base:        translation " << stats_text(base.translation_m, 4, "m") << ", p95 " << format_fixed(base.translation_p95_m, 4)
      << " m, rotation "
      << stats_text(base.rotation_deg, 3, "deg") << "\n";
  if (laser)
    out << "laser:       translation " << stats_text(laser->translation_m, 4, "m") << ", p95 "
        << format_fixed(laser->translation_p95_m, 4) << " m, rotation "
        << stats_text(laser->rotation_deg, 3, "deg") << " (mount " << format_number(offset.x) << ", "
        << format_number(offset.y) << " m, " << format_number(rad_to_deg(offset.yaw)) << " deg)\n";
  return out.str();
}

std::string rpe_json(const RelativePoseError& base, const std::optional<RelativePoseError>& laser, const Pose2& offset) {
  nlohmann::ordered_json j;
  j["base"] = error_json(base);
  j["laser"] = laser ? error_json(*laser) : nlohmann::ordered_json(nullptr);
  j["laser_offset"] = {{"x_m", offset.x}, {"y_m", offset.y}, {"yaw_rad", offset.yaw}};
  return j.dump() + "\n";
}

}  // namespace starnav
