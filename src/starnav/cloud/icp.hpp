#pragma once
// Iterative closest point (Besl and McKay 1992), the `icp` 3D scan matcher: each iteration pairs
// every scan point with its nearest reference point within max_correspondence_distance_m, then
//  - point_to_point: the rigid transform minimising the pairs' squared distances in closed form
//    (Umeyama 1991; PCL's IterativeClosestPoint, the paper's ICP);
//  - point_to_plane: one Gauss-Newton step on the distances along the reference's surface
//    normals (Chen and Medioni 1992), optionally under a Cauchy loss of scale robust_scale_m.
#include <memory>
#include <optional>

#include "starnav/cloud/local_shape.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/params.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav {

enum class IcpMetric { PointToPoint, PointToPlane };

struct IcpConfig {
  RegistrationLimits limits;
  IcpMetric metric = IcpMetric::PointToPoint;
  double max_correspondence_distance_m = 1.0;
  int normal_neighbours = 10;   // point_to_plane: the reference's normals from this many neighbours
  double robust_scale_m = 0.0;  // point_to_plane: Cauchy loss scale (0: plain least squares)
  int threads = 1;              // 0: one per hardware thread
  void validate() const;
};
const ParamTable<IcpConfig>& icp_params();

class IcpMatcher : public ScanMatcher3d {
 public:
  explicit IcpMatcher(const IcpConfig& config);
  std::string_view name() const override { return "icp"; }
  void set_reference(std::span<const Vec3> reference) override;
  CloudMatch match(std::span<const Vec3> scan, const Rigid3& guess) override;

 private:
  CloudMatch match_point_to_point(std::span<const Vec3> scan, const Rigid3& guess) const;
  IcpConfig c_;
  std::optional<KdTree3> tree_;
  std::vector<LocalShape> shapes_;
  std::unique_ptr<ThreadPool> pool_;
};

ScanMatcher3dDef icp_scan_matcher();

}  // namespace starnav
