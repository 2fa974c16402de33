#include "starnav/cloud/vgicp.hpp"

#include <chrono>
#include <cmath>

#include "starnav/cloud/registration_solver.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

using namespace registration_detail;

const ParamTable<VgicpConfig>& vgicp_params() {
  static const ParamTable<VgicpConfig> table = [] {
    using C = VgicpConfig;
    ParamTable<C> t;
    declare_registration_limits(t);
    t.real("voxel_resolution_m", &C::voxel_resolution_m, closed(0.01, 100.0), "m", "side of the reference's voxels");
    t.choice(
        "neighbours", {"direct1", "direct7"},
        [](C& c, const std::string& v) { c.neighbours = v == "direct7" ? VoxelNeighbours::Direct7 : VoxelNeighbours::Direct1; },
        [](const C& c) { return std::string(c.neighbours == VoxelNeighbours::Direct7 ? "direct7" : "direct1"); },
        "voxels a point may pair with: its own, or the nearest mean among its own and the six sharing a face");
    t.real("max_correspondence_distance_m", &C::max_correspondence_distance_m, closed(1e-3, 100.0), "m",
           "a point pairs with a voxel only when the voxel's mean is at most this far");
    t.integer("covariance_neighbours", &C::covariance_neighbours, closed(3, 100), "", "neighbours a point's covariance comes from");
    t.real("epsilon", &C::epsilon, closed(1e-6, 1.0), "", "thickness of each point's disc relative to its extent");
    t.integer("threads", &C::threads, closed(0, 256), "", "threads (0: one per hardware thread); results do not depend on it");
    return t;
  }();
  return table;
}

void VgicpConfig::validate() const {
  limits.validate();
  require(std::isfinite(voxel_resolution_m) && voxel_resolution_m >= 0.01 && voxel_resolution_m <= 100,
          "voxel_resolution_m", "must be in [0.01, 100] m");
  require(std::isfinite(max_correspondence_distance_m) && max_correspondence_distance_m >= 1e-3 &&
              max_correspondence_distance_m <= 100,
          "max_correspondence_distance_m", "must be in [0.001, 100] m");
  require(covariance_neighbours >= 3 && covariance_neighbours <= 100, "covariance_neighbours", "must be in [3, 100]");
  require(std::isfinite(epsilon) && epsilon >= 1e-6 && epsilon <= 1.0, "epsilon", "must be in [1e-6, 1]");
  require(threads >= 0 && threads <= 256, "threads", "must be in [0, 256]");
}

GaussianVoxels::GaussianVoxels(std::span<const Vec3> points, std::span<const Eigen::Matrix3d> covariances,
                               double resolution_m)
    : hash_(resolution_m) {
  if (points.size() != covariances.size()) throw Error("gaussian voxels: one covariance per point is needed");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::uint64_t key = hash_.key_of(points[i]);
    if (key == VoxelHash::kNoKey)
      throw Error("a reference point lies more than 2^20 voxels from the origin (or is not finite)", "", 0,
                  "voxel_resolution_m");
    const std::uint32_t v = hash_.insert(key);
    if (v == voxels_.size()) voxels_.emplace_back();
    Voxel& voxel = voxels_[v];
    voxel.mean += points[i];
    voxel.covariance += covariances[i];
    ++voxel.points;
  }
  for (Voxel& v : voxels_) {
    v.mean /= static_cast<double>(v.points);
    v.covariance /= static_cast<double>(v.points);
  }
}

VgicpMatcher::VgicpMatcher(const VgicpConfig& config) : c_(config), voxels_(config.voxel_resolution_m) {
  c_.validate();
  if (c_.threads != 1) pool_ = std::make_unique<ThreadPool>(static_cast<unsigned>(c_.threads));
}

void VgicpMatcher::set_reference(std::span<const Vec3> reference) {
  if (reference.size() < 6) throw Error("the reference cloud has fewer than 6 points", "", 0, "reference");
  tree_.emplace(reference);
  const std::vector<Eigen::Matrix3d> covariances =
      disc_covariances(*tree_, static_cast<std::size_t>(c_.covariance_neighbours), c_.epsilon, pool_.get());
  voxels_ = GaussianVoxels(tree_->points(), covariances, c_.voxel_resolution_m);
}

CloudMatch VgicpMatcher::match(std::span<const Vec3> scan, const Rigid3& guess) {
  if (!tree_) throw Error("vgicp: match before set_reference");
  const auto start = std::chrono::steady_clock::now();
  CloudMatch m;
  std::optional<KdTree3> scan_tree_storage;
  std::span<const std::uint32_t> scan_order;
  if (scan.size() >= 3) {
    const KdTree3& scan_tree = scan_tree_storage.emplace(scan);
    scan_order = scan_tree.leaf_order();
    const std::vector<Eigen::Matrix3d> scan_covariances =
        disc_covariances(scan_tree, static_cast<std::size_t>(c_.covariance_neighbours), c_.epsilon, pool_.get());
    const double max_sq = c_.max_correspondence_distance_m * c_.max_correspondence_distance_m;
    const VoxelHash& hash = voxels_.hash();
    const std::vector<GaussianVoxels::Voxel>& voxels = voxels_.voxels();
    static constexpr int kOffsets[7][3] = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const int n_offsets = c_.neighbours == VoxelNeighbours::Direct7 ? 7 : 1;
    m = gauss_newton(guess, c_.limits, [&](const Rigid3& t) {
      const Eigen::Matrix3d r = t.linear();
      return accumulate(pool_.get(), scan.size(), [&](std::size_t begin, std::size_t end, NormalEquations& eq) {
        std::int64_t c[3];
        for (std::size_t i = begin; i < end; ++i) {
          const Vec3 p = t * scan[i];
          if (!hash.coords_of(p, c)) continue;
          const GaussianVoxels::Voxel* best = nullptr;
          double best_sq = max_sq;
          for (int o = 0; o < n_offsets; ++o) {
            const std::uint32_t v = hash.find(
                VoxelHash::key_of_coords(c[0] + kOffsets[o][0], c[1] + kOffsets[o][1], c[2] + kOffsets[o][2]));
            if (v == VoxelHash::kNone) continue;
            const double sq = (p - voxels[v].mean).squaredNorm();
            if (sq <= best_sq && (!best || sq < best_sq)) {
              best = &voxels[v];
              best_sq = sq;
            }
          }
          if (!best) continue;
          add_plane_to_plane(eq, p, p - best->mean, best->covariance + r * scan_covariances[i] * r.transpose());
        }
      });
    });
  }
  m.fitness = fitness_score(*tree_, scan, m.transform, c_.limits.fitness_max_range_m, pool_.get(), scan_order);
  m.time_s = seconds_since(start);
  return m;
}

ScanMatcher3dDef vgicp_scan_matcher() {
  ScanMatcher3dDef d;
  d.info.role = Role::ScanMatcher3d;
  d.info.name = "vgicp";
  d.info.section = "vgicp";
  d.info.summary =
      "Voxelised GICP (Koide et al. 2021): GICP's plane-to-plane cost against the reference's voxels (mean point, mean "
      "covariance), found by a voxel hash";
  d.info.params = vgicp_params().specs();
  d.make = [](const ScanMatcher3dContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<ScanMatcher3d> {
    return std::make_unique<VgicpMatcher>(configured(vgicp_params(), settings, ctx.file));
  };
  return d;
}

}  // namespace starnav
