#pragma once
// The normal distributions transform (Biber and Strasser 2003; Magnusson 2009; Ou et al. 2022
// Eqs. 1-8), the `ndt` and `ndt_mt` 3D scan matchers. The reference is cut into voxels of side
// resolution_m; each voxel with at least min_points_per_voxel points keeps the mean and the
// covariance of its points (eigenvalues below 1 % of the largest raised to it, as PCL and
// Magnusson do). The score of a scan point p = T a is Magnusson's Gaussian-plus-uniform mixture
// -d1 exp(-d2/2 (p - q)^T S^-1 (p - q)) summed over the voxel p falls in and, with DIRECT7, its
// six face neighbours (hdl_graph_slam's NDT_OMP default). The score is maximised by Gauss-Newton
// steps whose weights are the mixture's derivative (the Hessian's positive-definite part; its
// gradient is exact, so the optimum is the score's). `ndt_mt` is the same matcher on all hardware
// threads: the sums are taken over fixed chunks in order, so it returns exactly what `ndt` does.
#include <cstdint>
#include <memory>
#include <vector>

#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav {

enum class NdtNeighbours { Direct1, Direct7 };

struct NdtConfig {
  RegistrationLimits limits;
  double resolution_m = 1.0;
  int min_points_per_voxel = 6;
  double outlier_ratio = 0.55;
  NdtNeighbours neighbours = NdtNeighbours::Direct7;
  int threads = 1;  // 0: one per hardware thread; results do not depend on it
  void validate() const;
};
const ParamTable<NdtConfig>& ndt_params();

// The reference's voxels: means and inverse covariances, found by voxel index.
class NdtVoxels {
 public:
  NdtVoxels() = default;
  NdtVoxels(std::span<const Vec3> reference, double resolution_m, int min_points);
  struct Voxel {
    Vec3 mean = Vec3::Zero();
    Eigen::Matrix3d inverse_covariance = Eigen::Matrix3d::Identity();
  };
  std::size_t size() const { return voxels_.size(); }
  const std::vector<Voxel>& voxels() const { return voxels_; }
  // The voxel holding p displaced by (dx, dy, dz) voxels; nullptr when there is none.
  const Voxel* find(const Vec3& p, int dx = 0, int dy = 0, int dz = 0) const;

 private:
  std::int64_t key_of(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  double inv_resolution_ = 1.0;
  Vec3 origin_ = Vec3::Zero();
  std::vector<Voxel> voxels_;
  std::vector<std::int64_t> keys_;    // open-addressing table: key, or -1 for empty
  std::vector<std::uint32_t> slots_;  // voxel index of each occupied key
  std::uint64_t mask_ = 0;
};

class NdtMatcher : public ScanMatcher3d {
 public:
  explicit NdtMatcher(const NdtConfig& config, std::string name = "ndt");
  std::string_view name() const override { return name_; }
  void set_reference(std::span<const Vec3> reference) override;
  CloudMatch match(std::span<const Vec3> scan, const Rigid3& guess) override;
  unsigned threads() const override { return pool_ ? pool_->size() : 1U; }

 private:
  NdtConfig c_;
  std::string name_;
  NdtVoxels voxels_;
  std::unique_ptr<KdTree3> tree_;  // for the fitness score
  std::unique_ptr<ThreadPool> pool_;
  double d1_ = 0.0, d2_ = 0.0;
};

ScanMatcher3dDef ndt_scan_matcher();
ScanMatcher3dDef ndt_mt_scan_matcher();

}  // namespace starnav
