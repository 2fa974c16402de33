// PCL's ICP, GICP and NDT as 3D scan matchers: the parameters, the plugin's lookup (dlopen, the ABI
// check) and the matcher that calls it. Nothing here includes PCL (cloud/pcl_matchers.hpp).
#include "starnav/cloud/pcl_matchers.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <Eigen/Geometry>

#include "starnav/config.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

namespace {

// max_iterations and fitness_max_range_m are the RegistrationLimits PCL's matchers share with
// starnav's (declared as declare_registration_limits does); their convergence tests are PCL's epsilons.
ParamTable<PclMatcherConfig> make_pcl_params(PclMethod method) {
  using C = PclMatcherConfig;
  ParamTable<C> t;
  t.integer("max_iterations", [](C& c) -> int& { return c.limits.max_iterations; }, closed(1, 10000), "",
            "setMaximumIterations: most iterations of one match");
  switch (method) {
    case PclMethod::Icp:
      t.real("transformation_epsilon", &C::transformation_epsilon, closed(0.0, 1.0), "m^2",
             "setTransformationEpsilon: converged when a step's squared translation is at most this and the cosine "
             "of its rotation at least 1 - this (0: only when the pairs' mean squared error stops changing)");
      t.real("max_correspondence_distance_m", &C::max_correspondence_distance_m, closed(0.0, 1e6), "m",
             "setMaxCorrespondenceDistance: pairs further apart are left out (0: no limit)");
      break;
    case PclMethod::Gicp:
      t.real("transformation_epsilon", &C::transformation_epsilon, closed(1e-12, 1.0), "m",
             "setTransformationEpsilon: converged when no entry of the translation changes by more than this and no "
             "entry of the rotation matrix by more than rotation_epsilon");
      t.real("rotation_epsilon", &C::rotation_epsilon, closed(1e-12, 1.0), "",
             "setRotationEpsilon: the largest change of a rotation-matrix entry (about radians) that counts as converged");
      t.real("max_correspondence_distance_m", &C::max_correspondence_distance_m, closed(1e-3, 1e6), "m",
             "setMaxCorrespondenceDistance: pairs further apart are left out");
      t.integer("covariance_neighbours", &C::covariance_neighbours, closed(3, 1000), "",
                "setCorrespondenceRandomness: neighbours each point's covariance is computed from");
      break;
    case PclMethod::Ndt:
      t.real("transformation_epsilon", &C::transformation_epsilon, closed(0.0, 100.0), "m^2",
             "setTransformationEpsilon: converged when a step's squared translation is at most this (half of it is "
             "the line search's tolerance)");
      t.real("resolution_m", &C::resolution_m, closed(0.05, 20.0), "m", "setResolution: side of the reference's voxels");
      t.real("step_size", &C::step_size, closed(1e-4, 10.0), "",
             "setStepSize: the longest step of the More-Thuente line search (metres and radians together)");
      t.real("outlier_ratio", &C::outlier_ratio, open(0.0, 1.0), "",
             "setOulierRatio: weight of the uniform (outlier) part of the score");
      break;
  }
  t.real("fitness_max_range_m", [](C& c) -> double& { return c.limits.fitness_max_range_m; }, closed(1e-3, 1e6), "m",
         "points further than this from the reference are left out of the fitness score");
  return t;
}

// --- The plugin: found and loaded once per process. ---

constexpr const char* kPclPluginFile = "libstarnav_pcl.so";

using PclAbiFn = int (*)();
using PclAlignFn = void (*)(const PclAlignParams*, const double*, std::uint64_t, const double*, std::uint64_t,
                            const double*, PclAlignOutcome*);

struct PclPlugin {
  PclAlignFn align = nullptr;
  PclSupport support;
};

PclPlugin open_pcl_plugin(const std::string& path, std::string& why) {
  PclPlugin p;
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = dlerror();
    why = one_line(e ? e : "dlopen failed");
    return p;
  }
  const auto abi = reinterpret_cast<PclAbiFn>(dlsym(handle, kPclPluginAbiSymbol));
  const auto align = reinterpret_cast<PclAlignFn>(dlsym(handle, kPclPluginAlignSymbol));
  if (!abi || !align) {
    why = path + " is not starnav's PCL plugin";
    dlclose(handle);
    return p;
  }
  if (abi() != kPclPluginAbi) {
    why = path + " is a PCL plugin of another starnav build (interface " + std::to_string(abi()) + ", expected " +
          std::to_string(kPclPluginAbi) + ")";
    dlclose(handle);
    return p;
  }
  // The handle stays open for the life of the process.
  p.align = align;
  p.support = {true, path};
  return p;
}

std::string pcl_executable_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

// Where the plugin is looked for, as the GDAL plugin is (io/geotiff.cpp): $STARNAV_PCL_PLUGIN (a
// path); beside the executable as the build tree and an installation lay it out (bin/ and
// lib/starnav/, the plugins' folder); the installation prefix starnav was configured with.
PclPlugin find_pcl_plugin() {
  using std::filesystem::path;
  PclPlugin p;
  if (const char* env = std::getenv("STARNAV_PCL_PLUGIN"); env && *env) {
    std::string why;
    p = open_pcl_plugin(env, why);
    if (!p.align) p.support = {false, "STARNAV_PCL_PLUGIN: " + why};
    return p;
  }
  if (!STARNAV_HAVE_PCL) {
    p.support = {false, "starnav was built without PCL (-DSTARNAV_WITH_PCL=OFF)"};
    return p;
  }
  std::vector<std::string> candidates;
  const std::string exe_dir = pcl_executable_dir();
  if (!exe_dir.empty()) {
    candidates.push_back((path(exe_dir) / "../lib/starnav" / kPclPluginFile).lexically_normal().string());
    candidates.push_back((path(exe_dir) / STARNAV_GDAL_PLUGIN_FROM_BIN / kPclPluginFile).lexically_normal().string());
  }
  candidates.push_back((path(STARNAV_GDAL_PLUGIN_INSTALL_DIR) / kPclPluginFile).string());
  std::string tried, last_error;
  for (const std::string& c : candidates) {
    if (tried.find(c) != std::string::npos) continue;
    tried += (tried.empty() ? "" : ", ") + c;
    std::error_code ec;
    if (!std::filesystem::exists(c, ec)) continue;
    std::string why;
    p = open_pcl_plugin(c, why);
    if (p.align) return p;
    last_error = why;
  }
  p.support = {false, std::string("its plugin ") + kPclPluginFile +
                          (last_error.empty() ? " was not found (looked at " + tried + "; set STARNAV_PCL_PLUGIN)"
                                              : " did not load: " + last_error)};
  return p;
}

// STARNAV_PCL_PLUGIN=none is honoured at every use (a test turns PCL off in a process that has
// loaded it); a path, like the search, only at the first.
const PclPlugin& pcl_plugin() {
  static const PclPlugin off{nullptr, {false, "turned off by STARNAV_PCL_PLUGIN=none"}};
  if (const char* env = std::getenv("STARNAV_PCL_PLUGIN"); env && std::string(env) == "none") return off;
  static const PclPlugin p = find_pcl_plugin();
  return p;
}

// Text from the plugin's fixed-size fields, safe when it filled them to the end.
std::string pcl_text(const char* chars, std::size_t size) { return one_line(std::string(chars, strnlen(chars, size))); }

ScanMatcher3dDef pcl_def(PclMethod method, const std::string& name, const std::string& summary) {
  const PclMatcherConfig defaults = pcl_matcher_defaults(method);
  ScanMatcher3dDef d;
  d.info.role = Role::ScanMatcher3d;
  d.info.name = name;
  d.info.section = name;
  d.info.summary = summary;
  d.info.capabilities = {Capability::Plugin};
  d.info.params = pcl_matcher_params(method).specs(defaults);
  d.make = [method, name, defaults](const ScanMatcher3dContext& ctx,
                                    std::span<const ParamSetting> settings) -> std::unique_ptr<ScanMatcher3d> {
    return std::make_unique<PclMatcher>(configured(pcl_matcher_params(method), settings, ctx.file, defaults), name);
  };
  return d;
}

}  // namespace

PclMatcherConfig pcl_matcher_defaults(PclMethod method) {
  // PCL 1.13's constructors' values.
  PclMatcherConfig c;
  c.method = method;
  switch (method) {
    case PclMethod::Icp:
      c.limits.max_iterations = 10;
      c.transformation_epsilon = 0.0;
      c.max_correspondence_distance_m = 0.0;  // sqrt(DBL_MAX): no limit
      break;
    case PclMethod::Gicp:
      c.limits.max_iterations = 200;
      c.transformation_epsilon = 5e-4;
      c.rotation_epsilon = 2e-3;
      c.max_correspondence_distance_m = 5.0;
      c.covariance_neighbours = 20;
      break;
    case PclMethod::Ndt:
      c.limits.max_iterations = 35;
      c.transformation_epsilon = 0.1;
      c.resolution_m = 1.0;
      c.step_size = 0.1;
      c.outlier_ratio = 0.55;
      break;
  }
  return c;
}

const ParamTable<PclMatcherConfig>& pcl_matcher_params(PclMethod method) {
  static const ParamTable<PclMatcherConfig> icp = make_pcl_params(PclMethod::Icp);
  static const ParamTable<PclMatcherConfig> gicp = make_pcl_params(PclMethod::Gicp);
  static const ParamTable<PclMatcherConfig> ndt = make_pcl_params(PclMethod::Ndt);
  return method == PclMethod::Icp ? icp : method == PclMethod::Gicp ? gicp : ndt;
}

void PclMatcherConfig::validate() const {
  limits.validate();
  require(std::isfinite(transformation_epsilon) && transformation_epsilon >= 0, "transformation_epsilon", "must be >= 0");
  if (method == PclMethod::Gicp) {
    require(transformation_epsilon > 0, "transformation_epsilon", "must be > 0");
    require_positive(rotation_epsilon, "rotation_epsilon");
    require_positive(max_correspondence_distance_m, "max_correspondence_distance_m");
    require(covariance_neighbours >= 3 && covariance_neighbours <= 1000, "covariance_neighbours", "must be in [3, 1000]");
  }
  if (method == PclMethod::Icp) require_non_negative(max_correspondence_distance_m, "max_correspondence_distance_m");
  if (method == PclMethod::Ndt) {
    require(std::isfinite(resolution_m) && resolution_m >= 0.05 && resolution_m <= 20, "resolution_m",
            "must be in [0.05, 20] m");
    require_positive(step_size, "step_size");
    require(outlier_ratio > 0 && outlier_ratio < 1, "outlier_ratio", "must be in (0, 1)");
  }
}

PclAlignParams PclMatcherConfig::align_params() const {
  PclAlignParams p;
  p.method = method;
  p.max_iterations = limits.max_iterations;
  p.transformation_epsilon = transformation_epsilon;
  p.rotation_epsilon = rotation_epsilon;
  p.max_correspondence_distance_m = max_correspondence_distance_m;
  p.covariance_neighbours = covariance_neighbours;
  p.resolution_m = resolution_m;
  p.step_size = step_size;
  p.outlier_ratio = outlier_ratio;
  p.fitness_max_range_m = limits.fitness_max_range_m;
  return p;
}

PclSupport pcl_support() { return pcl_plugin().support; }

PclMatcher::PclMatcher(const PclMatcherConfig& config, std::string name) : c_(config), name_(std::move(name)) {
  c_.validate();
  const PclPlugin& plugin = pcl_plugin();
  if (!plugin.align) throw Error(name_ + " needs PCL: " + plugin.support.detail, "", 0, "matcher");
}

std::size_t PclMatcher::min_points() const {
  // GICP's covariances need that many neighbours of every point (PCL indexes past its arrays with fewer).
  return c_.method == PclMethod::Gicp ? std::max<std::size_t>(6, static_cast<std::size_t>(c_.covariance_neighbours)) : 6;
}

void PclMatcher::set_reference(std::span<const Vec3> reference) {
  if (reference.size() < min_points())
    throw Error("the reference cloud has fewer than " + std::to_string(min_points()) + " points", "", 0, "reference");
  reference_.resize(3 * reference.size());
  for (std::size_t i = 0; i < reference.size(); ++i)
    for (int k = 0; k < 3; ++k) reference_[3 * i + static_cast<std::size_t>(k)] = reference[i][k];
}

CloudMatch PclMatcher::match(std::span<const Vec3> scan, const Rigid3& guess) {
  if (reference_.empty()) throw Error(name_ + ": match before set_reference");
  if (scan.size() < min_points())
    throw Error("the scan has fewer than " + std::to_string(min_points()) + " points", "", 0, "scan");
  const PclPlugin& plugin = pcl_plugin();
  if (!plugin.align) throw Error(name_ + " needs PCL: " + plugin.support.detail, "", 0, "matcher");
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> xyz(3 * scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i)
    for (int k = 0; k < 3; ++k) xyz[3 * i + static_cast<std::size_t>(k)] = scan[i][k];
  double guess_rows[16];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) guess_rows[4 * r + c] = guess.matrix()(r, c);
  const PclAlignParams params = c_.align_params();
  PclAlignOutcome out;
  plugin.align(&params, reference_.data(), reference_.size() / 3, xyz.data(), scan.size(), guess_rows, &out);
  if (!out.ok) {
    const std::string field = pcl_text(out.error_field, sizeof out.error_field);
    throw Error(name_ + ": " + pcl_text(out.error, sizeof out.error), "", 0, field);
  }
  CloudMatch m;
  Eigen::Matrix4d t;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) t(r, c) = out.transform[4 * r + c];
  // PCL computes in float: the rotation is orthonormal to about 1e-7 only, and Isometry3d assumes it exactly.
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::Matrix3d(t.topLeftCorner<3, 3>())).normalized();
  m.transform = Rigid3::Identity();
  m.transform.linear() = q.toRotationMatrix();
  m.transform.translation() = t.topRightCorner<3, 1>();
  m.fitness = out.fitness;
  m.iterations = out.iterations;
  m.converged = out.converged != 0;
  m.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return m;
}

ScanMatcher3dDef pcl_icp_scan_matcher() {
  return pcl_def(PclMethod::Icp, "pcl_icp", "PCL's IterativeClosestPoint (point to point) through starnav's PCL plugin");
}
ScanMatcher3dDef pcl_gicp_scan_matcher() {
  return pcl_def(PclMethod::Gicp, "pcl_gicp", "PCL's GeneralizedIterativeClosestPoint through starnav's PCL plugin");
}
ScanMatcher3dDef pcl_ndt_scan_matcher() {
  return pcl_def(PclMethod::Ndt, "pcl_ndt",
                 "PCL's NormalDistributionsTransform (one thread, More-Thuente line search) through starnav's PCL plugin");
}

}  // namespace starnav
