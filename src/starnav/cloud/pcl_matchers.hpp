#pragma once
// The Point Cloud Library's registration as 3D scan matchers, to measure starnav's own against:
// `pcl_icp` (IterativeClosestPoint), `pcl_gicp` (GeneralizedIterativeClosestPoint) and `pcl_ndt`
// (NormalDistributionsTransform), each with PCL's own defaults and parameters named after PCL's
// setters. The library never links PCL: starnav's PCL plugin (libstarnav_pcl.so,
// src/plugins/pcl/) does, and the library loads it with dlopen the first time one of these
// matchers is made, so programs that never use one do not load PCL's hundred-odd shared
// libraries. Built without PCL (-DSTARNAV_WITH_PCL=OFF), with the plugin missing, or with
// STARNAV_PCL_PLUGIN=none, making one is an Error naming "matcher".
//
// The plugin's interface is the C functions and the two plain structs below: clouds cross as
// arrays of doubles (x, y, z triples), transforms as row-major 4 x 4 arrays, no exception and no
// library type crosses. kPclPluginAbi changes whenever they do, and the library refuses a
// plugin of another version.
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/params.hpp"

namespace starnav {

inline constexpr int kPclPluginAbi = 1;
inline constexpr const char* kPclPluginAbiSymbol = "starnav_pcl_plugin_abi";
inline constexpr const char* kPclPluginAlignSymbol = "starnav_pcl_align";

enum class PclMethod : std::int32_t { Icp = 0, Gicp = 1, Ndt = 2 };

// What the plugin sets on PCL's registration object; fields another method does not use are ignored.
struct PclAlignParams {
  PclMethod method = PclMethod::Icp;
  std::int32_t max_iterations = 10;              // setMaximumIterations
  double transformation_epsilon = 0.0;           // setTransformationEpsilon (its meaning is the method's)
  double rotation_epsilon = 2e-3;                // gicp: setRotationEpsilon
  double max_correspondence_distance_m = 0.0;    // icp, gicp: setMaxCorrespondenceDistance; <= 0: not set
  std::int32_t covariance_neighbours = 20;       // gicp: setCorrespondenceRandomness
  double resolution_m = 1.0;                     // ndt: setResolution
  double step_size = 0.1;                        // ndt: setStepSize
  double outlier_ratio = 0.55;                   // ndt: setOulierRatio
  double fitness_max_range_m = 5.0;              // the fitness score leaves out points further than this
};

// The plugin's answer. On failure ok is 0 and error holds one line, error_field what it concerns
// ("reference", "scan", "resolution_m", ...).
struct PclAlignOutcome {
  std::int32_t ok = 0;
  char error[256] = {};
  char error_field[32] = {};
  double transform[16] = {};  // row-major, scan frame -> reference frame
  // getFitnessScore: the mean squared distance (m^2) of the aligned scan's points to their nearest
  // reference points within fitness_max_range_m; +infinity when none is that near.
  double fitness = 0.0;
  std::int32_t iterations = 0;
  std::int32_t converged = 0;  // hasConverged(), and stopped before max_iterations
};
static_assert(std::is_standard_layout_v<PclAlignParams> && std::is_trivially_copyable_v<PclAlignParams>);
static_assert(std::is_standard_layout_v<PclAlignOutcome> && std::is_trivially_copyable_v<PclAlignOutcome>);

// The configuration of the three components: the keys each declares are its method's (PCL's
// defaults in pcl_matcher_defaults). limits holds max_iterations and fitness_max_range_m; PCL's
// own epsilons stand for its tolerances.
struct PclMatcherConfig {
  PclMethod method = PclMethod::Icp;
  RegistrationLimits limits;
  double transformation_epsilon = 0.0;
  double rotation_epsilon = 2e-3;
  double max_correspondence_distance_m = 0.0;  // 0: no limit
  int covariance_neighbours = 20;
  double resolution_m = 1.0;
  double step_size = 0.1;
  double outlier_ratio = 0.55;
  void validate() const;
  PclAlignParams align_params() const;
};
PclMatcherConfig pcl_matcher_defaults(PclMethod method);
const ParamTable<PclMatcherConfig>& pcl_matcher_params(PclMethod method);

// Whether the PCL plugin can be used in this process: the file loaded, or why not.
struct PclSupport {
  bool available = false;
  std::string detail;
};
PclSupport pcl_support();

class PclMatcher : public ScanMatcher3d {
 public:
  // Loads the plugin on first use; an Error naming "matcher" when it is not available.
  PclMatcher(const PclMatcherConfig& config, std::string name);
  std::string_view name() const override { return name_; }
  // Keeps a copy: PCL prepares the reference (its k-d tree, covariances or voxels) in every match.
  void set_reference(std::span<const Vec3> reference) override;
  CloudMatch match(std::span<const Vec3> scan, const Rigid3& guess) override;

 private:
  std::size_t min_points() const;
  PclMatcherConfig c_;
  std::string name_;
  std::vector<double> reference_;  // x, y, z triples
};

ScanMatcher3dDef pcl_icp_scan_matcher();
ScanMatcher3dDef pcl_gicp_scan_matcher();
ScanMatcher3dDef pcl_ndt_scan_matcher();

}  // namespace starnav

// The plugin's two entry points (C linkage, looked up with dlsym).
extern "C" int starnav_pcl_plugin_abi();
// Registers scan onto reference from guess (row-major 4 x 4) with the method and parameters of
// params; counts are points. Never throws, and leaves PCL's console messages off.
extern "C" void starnav_pcl_align(const starnav::PclAlignParams* params, const double* reference_xyz,
                                  std::uint64_t reference_points, const double* scan_xyz, std::uint64_t scan_points,
                                  const double* guess_row_major, starnav::PclAlignOutcome* out);
