#pragma once
// The 3D scan-matcher role, the twin of slam/scan_matcher.hpp for point clouds: the rigid
// transform that lays a scan onto a reference cloud. ICP (point-to-point and point-to-plane),
// GICP, VGICP and NDT (one thread or many) implement it (cloud/icp.cpp, gicp.cpp, vgicp.cpp,
// ndt.cpp); the registry finds them by name. Both clouds are in their own sensor frames; the
// transform maps `scan` into `reference`'s frame: reference_point ~= transform * scan_point.
//
// A matcher prepares the reference once (set_reference: a k-d tree, NDT's voxel statistics) so
// that several scans can be matched against it; register_clouds does both and times them.
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "starnav/cloud/kd_tree.hpp"
#include "starnav/cloud/point_cloud.hpp"
#include "starnav/core/component.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav {

struct CloudMatch {
  bool converged = false;                  // the step fell below the tolerances within max_iterations
  Rigid3 transform = Rigid3::Identity();   // scan frame -> reference frame
  // PCL's getFitnessScore: the mean squared distance (m^2) from the aligned scan's points to
  // their nearest reference points, over the points nearer than fitness_max_range_m.
  double fitness = 0.0;
  int iterations = 0;
  double time_s = 0.0;  // wall-clock time of the match (register_clouds: with set_reference)
};

// What every 3D matcher takes besides its own parameters.
struct RegistrationLimits {
  int max_iterations = 64;
  double translation_tolerance_m = 1e-4;  // converged when a step moves less than this ...
  double rotation_tolerance_rad = 1e-4;   // ... and turns less than this
  double fitness_max_range_m = 5.0;
  void validate() const;
};

class ScanMatcher3d {
 public:
  virtual ~ScanMatcher3d() = default;
  virtual std::string_view name() const = 0;
  // Prepares `reference`; throws Error when it is too small for the method.
  virtual void set_reference(std::span<const Vec3> reference) = 0;
  // `scan` onto the reference set last, starting from `guess`.
  virtual CloudMatch match(std::span<const Vec3> scan, const Rigid3& guess) = 0;
  // The threads a match uses (1 unless the matcher runs on a pool).
  virtual unsigned threads() const { return 1U; }
};

// set_reference and match in one call; time_s covers both.
CloudMatch register_clouds(ScanMatcher3d& matcher, std::span<const Vec3> reference, std::span<const Vec3> scan,
                           const Rigid3& guess = Rigid3::Identity());

// PCL's fitness score of `scan` under `transform` against the points of `reference`.
double fitness_score(const KdTree3& reference, std::span<const Vec3> scan, const Rigid3& transform, double max_range_m);
// The same, summed over fixed chunks of points in chunk order on `pool` (the same bytes on any
// number of threads; the last bits may differ from the one-pass sum above). `order` (empty: the
// scan's own) is the order the points are visited in: a spatially coherent one (the scan's k-d
// tree's leaf_order) lets each search start from the bound the previous point gives.
double fitness_score(const KdTree3& reference, std::span<const Vec3> scan, const Rigid3& transform, double max_range_m,
                     ThreadPool* pool, std::span<const std::uint32_t> order = {});

// Declares the RegistrationLimits every matcher's configuration holds as `limits`.
template <class Config>
void declare_registration_limits(ParamTable<Config>& t) {
  t.integer("max_iterations", [](Config& c) -> int& { return c.limits.max_iterations; }, closed(1, 10000), "",
            "most iterations of one match");
  t.real("translation_tolerance_m", [](Config& c) -> double& { return c.limits.translation_tolerance_m; },
         closed(1e-9, 1.0), "m", "converged when a step moves less than this and turns less than rotation_tolerance_deg");
  t.real("rotation_tolerance_deg", [](Config& c) -> double& { return c.limits.rotation_tolerance_rad; },
         closed(1e-7, 10.0), "deg", "converged when a step turns less than this and moves less than translation_tolerance_m",
         kPi / 180.0);
  t.real("fitness_max_range_m", [](Config& c) -> double& { return c.limits.fitness_max_range_m; }, closed(1e-3, 1e6),
         "m", "points further than this from the reference are left out of the fitness score");
}

struct ScanMatcher3dContext {
  std::string file;
};
using ScanMatcher3dDef = ComponentDef<ScanMatcher3d, ScanMatcher3dContext>;

}  // namespace starnav
