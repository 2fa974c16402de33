#include "starnav/cloud/icp.hpp"

#include <chrono>
#include <cmath>

#include <Eigen/Geometry>

#include "starnav/cloud/registration_solver.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

using namespace registration_detail;

const ParamTable<IcpConfig>& icp_params() {
  static const ParamTable<IcpConfig> table = [] {
    using C = IcpConfig;
    ParamTable<C> t;
    declare_registration_limits(t);
    t.choice(
        "metric", {"point_to_point", "point_to_plane"},
        [](C& c, const std::string& v) { c.metric = v == "point_to_plane" ? IcpMetric::PointToPlane : IcpMetric::PointToPoint; },
        [](const C& c) { return std::string(c.metric == IcpMetric::PointToPlane ? "point_to_plane" : "point_to_point"); },
        "distance minimised: to the nearest point, or along the reference's normal there");
    t.real("max_correspondence_distance_m", &C::max_correspondence_distance_m, closed(1e-3, 100.0), "m",
           "pairs further apart than this are left out");
    t.integer("normal_neighbours", &C::normal_neighbours, closed(3, 100), "", "point_to_plane: neighbours a normal is fitted to");
    t.real("robust_scale_m", &C::robust_scale_m, closed(0.0, 100.0), "m", "point_to_plane: Cauchy loss scale (0: none)");
    t.integer("threads", &C::threads, closed(0, 256), "", "point_to_plane: threads (0: one per hardware thread); results do not depend on it");
    return t;
  }();
  return table;
}

void IcpConfig::validate() const {
  limits.validate();
  require(std::isfinite(max_correspondence_distance_m) && max_correspondence_distance_m > 0,
          "max_correspondence_distance_m", "must be > 0");
  require(normal_neighbours >= 3 && normal_neighbours <= 100, "normal_neighbours", "must be in [3, 100]");
  require(std::isfinite(robust_scale_m) && robust_scale_m >= 0, "robust_scale_m", "must be >= 0");
  require(threads >= 0 && threads <= 256, "threads", "must be in [0, 256]");
}

IcpMatcher::IcpMatcher(const IcpConfig& config) : c_(config) {
  c_.validate();
  if (c_.metric == IcpMetric::PointToPlane && c_.threads != 1) pool_ = std::make_unique<ThreadPool>(static_cast<unsigned>(c_.threads));
}

void IcpMatcher::set_reference(std::span<const Vec3> reference) {
  if (reference.size() < 6) throw Error("the reference cloud has fewer than 6 points", "", 0, "reference");
  tree_.emplace(reference);
  shapes_.clear();
  if (c_.metric == IcpMetric::PointToPlane) shapes_ = local_shapes(*tree_, static_cast<std::size_t>(c_.normal_neighbours));
}

CloudMatch IcpMatcher::match_point_to_point(std::span<const Vec3> scan, const Rigid3& guess) const {
  CloudMatch m;
  Rigid3 t = guess;
  const double max_sq = c_.max_correspondence_distance_m * c_.max_correspondence_distance_m;
  Eigen::Matrix3Xd src(3, static_cast<Eigen::Index>(scan.size())), dst(3, static_cast<Eigen::Index>(scan.size()));
  Neighbour nn;
  for (int it = 1; it <= c_.limits.max_iterations; ++it) {
    m.iterations = it;
    Eigen::Index n = 0;
    for (const Vec3& a : scan) {
      const Vec3 p = t * a;
      if (tree_->nearest(p, nn) && nn.squared_distance <= max_sq) {
        src.col(n) = p;
        dst.col(n) = tree_->points()[nn.index];
        ++n;
      }
    }
    if (n < 3) break;
    const Eigen::Matrix4d step4 = Eigen::umeyama(src.leftCols(n), dst.leftCols(n), false);
    Rigid3 step(step4);
    t = step * t;
    if (rotation_angle(step) < c_.limits.rotation_tolerance_rad && translation_norm(step) < c_.limits.translation_tolerance_m) {
      m.converged = true;
      break;
    }
  }
  t.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
  m.transform = t;
  return m;
}

CloudMatch IcpMatcher::match(std::span<const Vec3> scan, const Rigid3& guess) {
  if (!tree_) throw Error("icp: match before set_reference");
  const auto start = std::chrono::steady_clock::now();
  CloudMatch m;
  if (c_.metric == IcpMetric::PointToPoint) {
    m = match_point_to_point(scan, guess);
  } else {
    const double max_sq = c_.max_correspondence_distance_m * c_.max_correspondence_distance_m;
    const double scale_sq = c_.robust_scale_m * c_.robust_scale_m;
    m = gauss_newton(guess, c_.limits, [&](const Rigid3& t) {
      return accumulate(pool_.get(), scan.size(), [&](std::size_t begin, std::size_t end, NormalEquations& eq) {
        Neighbour nn;
        for (std::size_t i = begin; i < end; ++i) {
          const Vec3 p = t * scan[i];
          if (!tree_->nearest(p, nn) || nn.squared_distance > max_sq) continue;
          const LocalShape& s = shapes_[nn.index];
          if (!s.valid) continue;
          const double r = s.normal.dot(p - tree_->points()[nn.index]);
          const double w = scale_sq > 0 ? 1.0 / (1.0 + r * r / scale_sq) : 1.0;
          Vector6 j;
          j.head<3>() = p.cross(s.normal);
          j.tail<3>() = s.normal;
          eq.h.noalias() += w * j * j.transpose();
          eq.g.noalias() += w * r * j;
          eq.cost += w * r * r;
          ++eq.count;
        }
      });
    });
  }
  m.fitness = fitness_score(*tree_, scan, m.transform, c_.limits.fitness_max_range_m);
  m.time_s = seconds_since(start);
  return m;
}

ScanMatcher3dDef icp_scan_matcher() {
  ScanMatcher3dDef d;
  d.info.role = Role::ScanMatcher3d;
  d.info.name = "icp";
  d.info.section = "icp";
  d.info.summary = "Iterative closest point, point-to-point (closed form, PCL's ICP) or point-to-plane (Gauss-Newton)";
  d.info.params = icp_params().specs();
  d.make = [](const ScanMatcher3dContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<ScanMatcher3d> {
    return std::make_unique<IcpMatcher>(configured(icp_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
