#include "starnav/cloud/gicp.hpp"

#include <chrono>
#include <cmath>

#include "starnav/cloud/registration_solver.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

using namespace registration_detail;

const ParamTable<GicpConfig>& gicp_params() {
  static const ParamTable<GicpConfig> table = [] {
    using C = GicpConfig;
    ParamTable<C> t;
    declare_registration_limits(t);
    t.real("max_correspondence_distance_m", &C::max_correspondence_distance_m, closed(1e-3, 100.0), "m",
           "pairs further apart than this are left out");
    t.integer("covariance_neighbours", &C::covariance_neighbours, closed(3, 100), "", "neighbours a point's covariance comes from");
    t.real("epsilon", &C::epsilon, closed(1e-6, 1.0), "", "thickness of each point's disc relative to its extent");
    t.integer("threads", &C::threads, closed(0, 256), "", "threads (0: one per hardware thread); results do not depend on it");
    return t;
  }();
  return table;
}

void GicpConfig::validate() const {
  limits.validate();
  require(std::isfinite(max_correspondence_distance_m) && max_correspondence_distance_m > 0,
          "max_correspondence_distance_m", "must be > 0");
  require(covariance_neighbours >= 3 && covariance_neighbours <= 100, "covariance_neighbours", "must be in [3, 100]");
  require(std::isfinite(epsilon) && epsilon >= 1e-6 && epsilon <= 1.0, "epsilon", "must be in [1e-6, 1]");
  require(threads >= 0 && threads <= 256, "threads", "must be in [0, 256]");
}

GicpMatcher::GicpMatcher(const GicpConfig& config) : c_(config) {
  c_.validate();
  if (c_.threads != 1) pool_ = std::make_unique<ThreadPool>(static_cast<unsigned>(c_.threads));
}

std::vector<Eigen::Matrix3d> GicpMatcher::covariances(const KdTree3& tree) const {
  return disc_covariances(tree, static_cast<std::size_t>(c_.covariance_neighbours), c_.epsilon, pool_.get());
}

void GicpMatcher::set_reference(std::span<const Vec3> reference) {
  if (reference.size() < 6) throw Error("the reference cloud has fewer than 6 points", "", 0, "reference");
  tree_.emplace(reference);
  reference_covariances_ = covariances(*tree_);
}

CloudMatch GicpMatcher::match(std::span<const Vec3> scan, const Rigid3& guess) {
  if (!tree_) throw Error("gicp: match before set_reference");
  const auto start = std::chrono::steady_clock::now();
  CloudMatch m;
  std::optional<KdTree3> scan_tree_storage;
  std::span<const std::uint32_t> scan_order;
  if (scan.size() >= 3) {
    const KdTree3& scan_tree = scan_tree_storage.emplace(scan);
    scan_order = scan_tree.leaf_order();
    const std::vector<Eigen::Matrix3d> scan_covariances = covariances(scan_tree);
    const double max_sq = c_.max_correspondence_distance_m * c_.max_correspondence_distance_m;
    m = gauss_newton(guess, c_.limits, [&](const Rigid3& t) {
      const Eigen::Matrix3d r = t.linear();
      return accumulate(pool_.get(), scan.size(), [&](std::size_t begin, std::size_t end, NormalEquations& eq) {
        Neighbour nn;
        for (std::size_t i = begin; i < end; ++i) {
          const Vec3 p = t * scan[i];
          if (!tree_->nearest_within(p, max_sq, nn)) continue;
          add_plane_to_plane(eq, p, p - tree_->points()[nn.index],
                             reference_covariances_[nn.index] + r * scan_covariances[i] * r.transpose());
        }
      });
    });
  }
  m.fitness = fitness_score(*tree_, scan, m.transform, c_.limits.fitness_max_range_m, pool_.get(), scan_order);
  m.time_s = seconds_since(start);
  return m;
}

ScanMatcher3dDef gicp_scan_matcher() {
  ScanMatcher3dDef d;
  d.info.role = Role::ScanMatcher3d;
  d.info.name = "gicp";
  d.info.section = "gicp";
  d.info.summary = "Generalized ICP (Segal et al. 2009): plane-to-plane distances under both clouds' local covariances";
  d.info.params = gicp_params().specs();
  d.make = [](const ScanMatcher3dContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<ScanMatcher3d> {
    return std::make_unique<GicpMatcher>(configured(gicp_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
