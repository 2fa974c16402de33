// libstarnav_pcl.so: PCL's IterativeClosestPoint, GeneralizedIterativeClosestPoint and
// NormalDistributionsTransform for starnav's pcl_icp, pcl_gicp and pcl_ndt (cloud/pcl_matchers.cpp
// loads it with dlopen; cloud/pcl_matchers.hpp describes the interface). The only file of starnav
// that includes PCL. PCL is used as it comes: float points, its own defaults for whatever the
// parameters leave alone.
// GCC's flow warnings fire inside PCL's and Eigen's templates although they are system headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Warray-bounds"
#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <limits>
#include <mutex>
#include <new>
#include <string>

#include "starnav/cloud/pcl_matchers.hpp"

namespace {

using PclPoint = pcl::PointXYZ;
using PclCloud = pcl::PointCloud<PclPoint>;

// The iteration counts and NDT's voxels are protected in PCL.
class IcpWithCount : public pcl::IterativeClosestPoint<PclPoint, PclPoint> {
 public:
  int iterations() const { return nr_iterations_; }
};
class GicpWithCount : public pcl::GeneralizedIterativeClosestPoint<PclPoint, PclPoint> {
 public:
  int iterations() const { return nr_iterations_; }
};
class NdtWithVoxels : public pcl::NormalDistributionsTransform<PclPoint, PclPoint> {
 public:
  bool has_voxels() { return !target_cells_.getCentroids()->empty(); }
};

void fail(starnav::PclAlignOutcome& out, const std::string& message, const std::string& field) {
  out.ok = 0;
  std::snprintf(out.error, sizeof out.error, "%s", message.c_str());
  std::snprintf(out.error_field, sizeof out.error_field, "%s", field.c_str());
}

// The cloud in float, as PCL keeps it; false (and `out` filled) at a point float cannot hold.
bool to_pcl(const double* xyz, std::uint64_t n, const char* what, PclCloud& cloud, starnav::PclAlignOutcome& out) {
  cloud.resize(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    const float x = static_cast<float>(xyz[3 * i]), y = static_cast<float>(xyz[3 * i + 1]),
                z = static_cast<float>(xyz[3 * i + 2]);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      fail(out, "point " + std::to_string(i) + " is not finite", what);
      return false;
    }
    cloud[i] = PclPoint(x, y, z);
  }
  cloud.is_dense = true;
  return true;
}

// The run shared by the three methods once `reg` is set up; `iterations` reads PCL's count.
template <class Registration, class Iterations>
void run(Registration& reg, const PclCloud::Ptr& scan, const Eigen::Matrix4f& guess,
         const starnav::PclAlignParams& p, Iterations iterations, starnav::PclAlignOutcome& out) {
  reg.setMaximumIterations(p.max_iterations);
  reg.setInputSource(scan);
  PclCloud aligned;
  reg.align(aligned, guess);
  const Eigen::Matrix4f t = reg.getFinalTransformation();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.transform[4 * r + c] = static_cast<double>(t(r, c));
  out.iterations = iterations();
  out.converged = reg.hasConverged() && out.iterations < p.max_iterations;
  // getFitnessScore compares squared distances with its argument: the square keeps the range in metres.
  const double fitness = reg.getFitnessScore(p.fitness_max_range_m * p.fitness_max_range_m);
  out.fitness = fitness >= std::numeric_limits<double>::max() ? std::numeric_limits<double>::infinity() : fitness;
  out.ok = 1;
}

void align(const starnav::PclAlignParams& p, const double* reference_xyz, std::uint64_t reference_points,
           const double* scan_xyz, std::uint64_t scan_points, const double* guess_rows, starnav::PclAlignOutcome& out) {
  using starnav::PclMethod;
  static std::once_flag quiet;
  // Every failure comes back in `out`; PCL's own messages would only repeat it on stderr.
  std::call_once(quiet, [] { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); });

  if (p.method != PclMethod::Icp && p.method != PclMethod::Gicp && p.method != PclMethod::Ndt)
    return fail(out, "unknown method " + std::to_string(static_cast<int>(p.method)), "matcher");
  if (p.max_iterations < 1) return fail(out, "must be >= 1", "max_iterations");
  // GICP needs that many neighbours of every point: PCL reads past its covariances with fewer.
  const std::uint64_t min_points =
      p.method == PclMethod::Gicp ? static_cast<std::uint64_t>(std::max(p.covariance_neighbours, 3)) : 3;
  if (reference_points < min_points)
    return fail(out, "the reference cloud has fewer than " + std::to_string(min_points) + " points", "reference");
  if (scan_points < min_points)
    return fail(out, "the scan has fewer than " + std::to_string(min_points) + " points", "scan");
  Eigen::Matrix4f guess;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      guess(r, c) = static_cast<float>(guess_rows[4 * r + c]);
      if (!std::isfinite(guess(r, c))) return fail(out, "the initial guess is not finite", "guess");
    }
  PclCloud::Ptr reference(new PclCloud), scan(new PclCloud);
  if (!to_pcl(reference_xyz, reference_points, "reference", *reference, out)) return;
  if (!to_pcl(scan_xyz, scan_points, "scan", *scan, out)) return;

  switch (p.method) {
    case PclMethod::Icp: {
      if (!(p.transformation_epsilon >= 0)) return fail(out, "must be >= 0", "transformation_epsilon");
      IcpWithCount icp;
      icp.setTransformationEpsilon(p.transformation_epsilon);
      if (p.max_correspondence_distance_m > 0) icp.setMaxCorrespondenceDistance(p.max_correspondence_distance_m);
      icp.setInputTarget(reference);
      return run(icp, scan, guess, p, [&] { return icp.iterations(); }, out);
    }
    case PclMethod::Gicp: {
      if (!(p.transformation_epsilon > 0)) return fail(out, "must be > 0", "transformation_epsilon");
      if (!(p.rotation_epsilon > 0)) return fail(out, "must be > 0", "rotation_epsilon");
      GicpWithCount gicp;
      gicp.setTransformationEpsilon(p.transformation_epsilon);
      gicp.setRotationEpsilon(p.rotation_epsilon);
      gicp.setCorrespondenceRandomness(p.covariance_neighbours);
      if (p.max_correspondence_distance_m > 0) gicp.setMaxCorrespondenceDistance(p.max_correspondence_distance_m);
      gicp.setInputTarget(reference);
      return run(gicp, scan, guess, p, [&] { return gicp.iterations(); }, out);
    }
    case PclMethod::Ndt: {
      if (!(p.transformation_epsilon >= 0)) return fail(out, "must be >= 0", "transformation_epsilon");
      if (!(p.resolution_m > 0) || !std::isfinite(p.resolution_m)) return fail(out, "must be > 0", "resolution_m");
      if (!(p.step_size > 0)) return fail(out, "must be > 0", "step_size");
      if (!(p.outlier_ratio > 0 && p.outlier_ratio < 1)) return fail(out, "must be in (0, 1)", "outlier_ratio");
      NdtWithVoxels ndt;
      ndt.setTransformationEpsilon(p.transformation_epsilon);
      ndt.setResolution(static_cast<float>(p.resolution_m));
      ndt.setStepSize(p.step_size);
      ndt.setOulierRatio(p.outlier_ratio);
      ndt.setInputTarget(reference);
      if (!ndt.has_voxels())
        return fail(out, "no voxel of the reference holds 6 points (or the voxels are too small for its extent)",
                    "resolution_m");
      return run(ndt, scan, guess, p, [&] { return ndt.getFinalNumIteration(); }, out);
    }
  }
}

}  // namespace

extern "C" int starnav_pcl_plugin_abi() { return starnav::kPclPluginAbi; }

extern "C" void starnav_pcl_align(const starnav::PclAlignParams* params, const double* reference_xyz,
                                  std::uint64_t reference_points, const double* scan_xyz, std::uint64_t scan_points,
                                  const double* guess_row_major, starnav::PclAlignOutcome* out) {
  if (!out) return;
  *out = starnav::PclAlignOutcome{};
  if (!params || !reference_xyz || !scan_xyz || !guess_row_major) return fail(*out, "missing argument", "matcher");
  try {
    align(*params, reference_xyz, reference_points, scan_xyz, scan_points, guess_row_major, *out);
  } catch (const std::bad_alloc&) {
    fail(*out, "out of memory in PCL's registration", "matcher");
  } catch (const std::exception& e) {
    fail(*out, std::string("PCL failed: ") + e.what(), "matcher");
  } catch (...) {
    fail(*out, "PCL failed with an unknown exception", "matcher");
  }
}
