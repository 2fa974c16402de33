#pragma once
// Voxelised GICP (Koide et al. 2021; small_gicp's VGICP), the `vgicp` 3D scan matcher. Every
// point of both clouds carries GICP's disc covariance from its k nearest neighbours; the
// reference is then cut into voxels of side voxel_resolution_m, each keeping the mean of its
// points and the mean of their covariances, found through a flat voxel hash. A scan point
// p = T a pairs with the voxel it falls in (or, with direct7, the nearest mean among that voxel
// and its six face neighbours) when the mean is within max_correspondence_distance_m, and each
// Gauss-Newton step minimises sum d^T (C_voxel + R C_scan R^T)^-1 d, d = p - mean: GICP's cost
// without a k-d tree query per point and iteration. Defaults are small_gicp's (1 m voxels, one
// voxel per point, 20 neighbours, pairs within 1 m).
#include <memory>
#include <optional>
#include <vector>

#include "starnav/cloud/local_shape.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/cloud/voxel_hash.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav {

enum class VoxelNeighbours { Direct1, Direct7 };

struct VgicpConfig {
  RegistrationLimits limits;
  double voxel_resolution_m = 1.0;
  VoxelNeighbours neighbours = VoxelNeighbours::Direct1;
  double max_correspondence_distance_m = 1.0;
  int covariance_neighbours = 20;
  double epsilon = 1e-3;  // the disc's thickness relative to its extent
  int threads = 1;        // 0: one per hardware thread; results do not depend on it
  void validate() const;
};
const ParamTable<VgicpConfig>& vgicp_params();

// The reference's voxels: per voxel the mean of its points and the mean of their covariances,
// in the order the voxels are first met in the cloud.
class GaussianVoxels {
 public:
  struct Voxel {
    Vec3 mean = Vec3::Zero();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    std::uint32_t points = 0;
  };
  explicit GaussianVoxels(double resolution_m = 1.0) : hash_(resolution_m) {}
  // Throws Error naming voxel_resolution_m when a point lies beyond the hash's range.
  GaussianVoxels(std::span<const Vec3> points, std::span<const Eigen::Matrix3d> covariances, double resolution_m);
  std::size_t size() const { return voxels_.size(); }
  const std::vector<Voxel>& voxels() const { return voxels_; }
  const VoxelHash& hash() const { return hash_; }
  // The voxel holding p moved by (dx, dy, dz) voxels; nullptr when there is none.
  const Voxel* find(const Vec3& p, int dx = 0, int dy = 0, int dz = 0) const {
    const std::uint32_t i = hash_.find(hash_.key_of(p, dx, dy, dz));
    return i == VoxelHash::kNone ? nullptr : &voxels_[i];
  }

 private:
  VoxelHash hash_;
  std::vector<Voxel> voxels_;
};

class VgicpMatcher : public ScanMatcher3d {
 public:
  explicit VgicpMatcher(const VgicpConfig& config);
  std::string_view name() const override { return "vgicp"; }
  void set_reference(std::span<const Vec3> reference) override;
  CloudMatch match(std::span<const Vec3> scan, const Rigid3& guess) override;
  unsigned threads() const override { return pool_ ? pool_->size() : 1U; }

 private:
  VgicpConfig c_;
  std::optional<KdTree3> tree_;  // the reference's covariances and the fitness score
  GaussianVoxels voxels_;
  std::unique_ptr<ThreadPool> pool_;
};

ScanMatcher3dDef vgicp_scan_matcher();

}  // namespace starnav
