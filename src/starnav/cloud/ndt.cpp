#include "starnav/cloud/ndt.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "starnav/cloud/registration_solver.hpp"
#include "starnav/core/error.hpp"

namespace starnav {

using namespace registration_detail;

const ParamTable<NdtConfig>& ndt_params() {
  static const ParamTable<NdtConfig> table = [] {
    using C = NdtConfig;
    ParamTable<C> t;
    declare_registration_limits(t);
    t.real("resolution_m", &C::resolution_m, closed(0.05, 20.0), "m", "side of the reference's voxels");
    t.integer("min_points_per_voxel", &C::min_points_per_voxel, closed(3, 1000), "", "voxels with fewer points are left out");
    t.real("outlier_ratio", &C::outlier_ratio, open(0.0, 1.0), "", "weight of the uniform (outlier) part of the score");
    t.choice(
        "neighbours", {"direct1", "direct7"},
        [](C& c, const std::string& v) { c.neighbours = v == "direct1" ? NdtNeighbours::Direct1 : NdtNeighbours::Direct7; },
        [](const C& c) { return std::string(c.neighbours == NdtNeighbours::Direct1 ? "direct1" : "direct7"); },
        "voxels a point is scored against: its own, or its own and the six sharing a face");
    t.integer("threads", &C::threads, closed(0, 256), "", "threads (0: one per hardware thread); results do not depend on it");
    return t;
  }();
  return table;
}

void NdtConfig::validate() const {
  limits.validate();
  require(std::isfinite(resolution_m) && resolution_m >= 0.05 && resolution_m <= 20, "resolution_m", "must be in [0.05, 20] m");
  require(min_points_per_voxel >= 3 && min_points_per_voxel <= 1000, "min_points_per_voxel", "must be in [3, 1000]");
  require(outlier_ratio > 0 && outlier_ratio < 1, "outlier_ratio", "must be in (0, 1)");
  require(threads >= 0 && threads <= 256, "threads", "must be in [0, 256]");
}

namespace {
constexpr std::int64_t kNdtAxisBits = 21;
constexpr std::int64_t kNdtAxisLimit = std::int64_t{1} << kNdtAxisBits;

std::uint64_t mix_key(std::int64_t key) {
  auto x = static_cast<std::uint64_t>(key);
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  return x;
}
}  // namespace

std::int64_t NdtVoxels::key_of(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  if (ix < 0 || iy < 0 || iz < 0 || ix >= kNdtAxisLimit || iy >= kNdtAxisLimit || iz >= kNdtAxisLimit) return -1;
  return (iz << (2 * kNdtAxisBits)) | (iy << kNdtAxisBits) | ix;
}

NdtVoxels::NdtVoxels(std::span<const Vec3> reference, double resolution_m, int min_points) {
  inv_resolution_ = 1.0 / resolution_m;
  const CloudBounds b = cloud_bounds(reference);
  // One voxel of margin below so that DIRECT7 neighbours of edge voxels have valid indices.
  origin_ = ((b.min * inv_resolution_).array().floor() - 1.0).matrix() * resolution_m;
  const Vec3 extent = (b.max - origin_) * inv_resolution_;
  require(extent.maxCoeff() < double(kNdtAxisLimit - 2), "resolution_m", "too small for the reference's extent");
  // Sort points by voxel key; each run of one key is a voxel.
  std::vector<std::pair<std::int64_t, std::uint32_t>> keyed(reference.size());
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const Vec3 v = ((reference[i] - origin_) * inv_resolution_).array().floor();
    keyed[i] = {key_of(static_cast<std::int64_t>(v.x()), static_cast<std::int64_t>(v.y()), static_cast<std::int64_t>(v.z())),
                static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::int64_t> voxel_keys;
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    const auto m = static_cast<double>(j - i);
    if (j - i >= static_cast<std::size_t>(min_points)) {
      Vec3 mean = Vec3::Zero();
      for (std::size_t k = i; k < j; ++k) mean += reference[keyed[k].second];
      mean /= m;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (std::size_t k = i; k < j; ++k) {
        const Vec3 d = reference[keyed[k].second] - mean;
        cov += d * d.transpose();
      }
      cov /= m - 1.0;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(cov);
      Eigen::Vector3d ev = eig.eigenvalues();
      const double floor = 0.01 * ev(2);
      if (ev(2) > 0) {
        ev = ev.cwiseMax(floor);
        const Eigen::Matrix3d& vecs = eig.eigenvectors();
        Voxel v;
        v.mean = mean;
        v.inverse_covariance = vecs * ev.cwiseInverse().asDiagonal() * vecs.transpose();
        voxels_.push_back(v);
        voxel_keys.push_back(keyed[i].first);
      }
    }
    i = j;
  }
  std::size_t capacity = 16;
  while (capacity < 2 * voxels_.size()) capacity *= 2;
  keys_.assign(capacity, -1);
  slots_.assign(capacity, 0);
  mask_ = capacity - 1;
  for (std::size_t v = 0; v < voxel_keys.size(); ++v) {
    std::uint64_t h = mix_key(voxel_keys[v]) & mask_;
    while (keys_[h] != -1) h = (h + 1) & mask_;
    keys_[h] = voxel_keys[v];
    slots_[h] = static_cast<std::uint32_t>(v);
  }
}

const NdtVoxels::Voxel* NdtVoxels::find(const Vec3& p, int dx, int dy, int dz) const {
  if (voxels_.empty()) return nullptr;
  const Vec3 v = (p - origin_) * inv_resolution_;
  if (!(v.minCoeff() >= -2.0 && v.maxCoeff() < double(kNdtAxisLimit))) return nullptr;
  const std::int64_t key = key_of(static_cast<std::int64_t>(std::floor(v.x())) + dx,
                                  static_cast<std::int64_t>(std::floor(v.y())) + dy,
                                  static_cast<std::int64_t>(std::floor(v.z())) + dz);
  if (key < 0) return nullptr;
  for (std::uint64_t h = mix_key(key) & mask_;; h = (h + 1) & mask_) {
    if (keys_[h] == key) return &voxels_[slots_[h]];
    if (keys_[h] == -1) return nullptr;
  }
}

NdtMatcher::NdtMatcher(const NdtConfig& config, std::string name) : c_(config), name_(std::move(name)) {
  c_.validate();
  if (c_.threads != 1) pool_ = std::make_unique<ThreadPool>(static_cast<unsigned>(c_.threads));
  // Magnusson 2009, Eqs. 6.8-6.9: the Gaussian-plus-uniform mixture fitted by a Gaussian.
  const double r3 = c_.resolution_m * c_.resolution_m * c_.resolution_m;
  const double c1 = 10.0 * (1.0 - c_.outlier_ratio), c2 = c_.outlier_ratio / r3;
  const double d3 = -std::log(c2);
  d1_ = -std::log(c1 + c2) - d3;
  d2_ = -2.0 * std::log((-std::log(c1 * std::exp(-0.5) + c2) - d3) / d1_);
}

void NdtMatcher::set_reference(std::span<const Vec3> reference) {
  if (reference.size() < 6) throw Error("the reference cloud has fewer than 6 points", "", 0, "reference");
  voxels_ = NdtVoxels(reference, c_.resolution_m, c_.min_points_per_voxel);
  if (voxels_.size() == 0)
    throw Error("no voxel of the reference holds " + std::to_string(c_.min_points_per_voxel) + " points", "", 0,
                "resolution_m");
  tree_ = std::make_unique<KdTree3>(reference);
}

CloudMatch NdtMatcher::match(std::span<const Vec3> scan, const Rigid3& guess) {
  if (!tree_) throw Error(name_ + ": match before set_reference");
  const auto start = std::chrono::steady_clock::now();
  static constexpr int kOffsets[7][3] = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int n_offsets = c_.neighbours == NdtNeighbours::Direct7 ? 7 : 1;
  CloudMatch m = gauss_newton(guess, c_.limits, [&](const Rigid3& t) {
    return accumulate(pool_.get(), scan.size(), [&](std::size_t begin, std::size_t end, NormalEquations& eq) {
      for (std::size_t i = begin; i < end; ++i) {
        const Vec3 p = t * scan[i];
        bool used = false;
        for (int o = 0; o < n_offsets; ++o) {
          const NdtVoxels::Voxel* v = voxels_.find(p, kOffsets[o][0], kOffsets[o][1], kOffsets[o][2]);
          if (!v) continue;
          const Vec3 x = p - v->mean;
          const Vec3 sx = v->inverse_covariance * x;
          const double e = std::exp(-0.5 * d2_ * x.dot(sx));
          if (!(e > 1e-12)) continue;
          const double w = -d1_ * d2_ * e;
          add_point(eq, p, v->inverse_covariance, sx, w);
          eq.cost += d1_ * e;
          used = true;
        }
        eq.count += used;
      }
    });
  });
  m.fitness = fitness_score(*tree_, scan, m.transform, c_.limits.fitness_max_range_m);
  m.time_s = seconds_since(start);
  return m;
}

namespace {
ScanMatcher3dDef ndt_def(const std::string& name, int threads, const std::string& summary) {
  NdtConfig defaults;
  defaults.threads = threads;
  ScanMatcher3dDef d;
  d.info.role = Role::ScanMatcher3d;
  d.info.name = name;
  d.info.section = name;
  d.info.summary = summary;
  d.info.params = ndt_params().specs(defaults);
  d.make = [name, defaults](const ScanMatcher3dContext& ctx, std::span<const ParamSetting> settings) -> std::unique_ptr<ScanMatcher3d> {
    return std::make_unique<NdtMatcher>(configured(ndt_params(), settings, ctx.file, defaults), name);
  };
  return d;
}
}  // namespace

ScanMatcher3dDef ndt_scan_matcher() {
  return ndt_def("ndt", 1, "Normal distributions transform (Magnusson 2009), DIRECT7 voxel neighbours, one thread");
}
ScanMatcher3dDef ndt_mt_scan_matcher() {
  return ndt_def("ndt_mt", 0, "The NDT on every hardware thread (NDT_OMP's role in the paper); the same result as ndt");
}

}  // namespace starnav
