#pragma once
// Generalized ICP (Segal, Haehnel and Thrun 2009), the `gicp` 3D scan matcher: every point of
// both clouds carries the covariance of its k nearest neighbours, regularised to a flat disc
// (eigenvalues epsilon, 1, 1); each Gauss-Newton step minimises sum d^T (C_ref + R C_scan R^T)^-1 d
// over the nearest-neighbour pairs d = T a - b within max_correspondence_distance_m ("plane to
// plane"). PCL's defaults: 20 neighbours, epsilon 0.001.
#include <memory>
#include <optional>

#include "starnav/cloud/local_shape.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav {

struct GicpConfig {
  RegistrationLimits limits;
  double max_correspondence_distance_m = 1.0;
  int covariance_neighbours = 20;
  double epsilon = 1e-3;  // the disc's thickness relative to its extent
  int threads = 1;        // 0: one per hardware thread; results do not depend on it
  void validate() const;
};
const ParamTable<GicpConfig>& gicp_params();

class GicpMatcher : public ScanMatcher3d {
 public:
  explicit GicpMatcher(const GicpConfig& config);
  std::string_view name() const override { return "gicp"; }
  void set_reference(std::span<const Vec3> reference) override;
  CloudMatch match(std::span<const Vec3> scan, const Rigid3& guess) override;
  unsigned threads() const override { return pool_ ? pool_->size() : 1U; }

 private:
  std::vector<Eigen::Matrix3d> covariances(const KdTree3& tree) const;
  GicpConfig c_;
  std::optional<KdTree3> tree_;
  std::vector<Eigen::Matrix3d> reference_covariances_;
  std::unique_ptr<ThreadPool> pool_;
};

ScanMatcher3dDef gicp_scan_matcher();

}  // namespace starnav
