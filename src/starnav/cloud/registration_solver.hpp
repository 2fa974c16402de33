#pragma once
// The machinery the least-squares matchers (point-to-plane ICP, GICP, NDT) share: per-point
// contributions to the 6 x 6 normal equations about the current transform, summed over fixed
// chunks of points in chunk order (so the sums, and every result, are the same on any number of
// threads), and the Gauss-Newton iteration on SE(3) with the left perturbation
// T <- exp(dxi) T, dxi = (omega, v). For a point p = T a of the scan, dp/dxi = [-[p]x | I].
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/thread_pool.hpp"

namespace starnav::registration_detail {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

struct NormalEquations {
  Matrix6 h = Matrix6::Zero();
  Vector6 g = Vector6::Zero();
  double cost = 0.0;
  std::size_t count = 0;  // points that contributed
  void add(const NormalEquations& o) {
    h += o.h;
    g += o.g;
    cost += o.cost;
    count += o.count;
  }
};

// Adds w J^T S J to h and w J^T v to g, for J = dp/dxi = [-[p]x | I] at p (3 x 6) and any 3 x 3 S.
// By blocks, with K = [p]x: J^T S J = [[-K S K, K S], [-S K, S]] and J^T v = [p x v; v]; K times a
// vector is a cross product. Written out for the sanitizer build: there Eigen's small products are
// not inlined, and the dense 3 x 6 form made the 3D registration tests 12-22 times slower than in
// Release (where both forms cost the same).
inline void add_point(NormalEquations& eq, const Vec3& p, const Eigen::Matrix3d& s_matrix, const Vec3& v, double w) {
  const double x = p.x(), y = p.y(), z = p.z();
  double s[3][3], ks[3][3], sk[3][3];  // S, K S and S K
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s[r][c] = s_matrix.data()[r + 3 * c];  // column-major
  for (int c = 0; c < 3; ++c) {
    // Column c of K S is p x (column c of S).
    ks[0][c] = y * s[2][c] - z * s[1][c];
    ks[1][c] = z * s[0][c] - x * s[2][c];
    ks[2][c] = x * s[1][c] - y * s[0][c];
  }
  for (int r = 0; r < 3; ++r) {
    // Row r of S K is -(p x (row r of S)).
    sk[r][0] = z * s[r][1] - y * s[r][2];
    sk[r][1] = x * s[r][2] - z * s[r][0];
    sk[r][2] = y * s[r][0] - x * s[r][1];
  }
  double* h = eq.h.data();  // column-major: h(r, c) = h[r + 6 c]
  for (int r = 0; r < 3; ++r) {
    // Row r of -K S K is p x (row r of K S).
    h[r + 0] += w * (y * ks[r][2] - z * ks[r][1]);
    h[r + 6] += w * (z * ks[r][0] - x * ks[r][2]);
    h[r + 12] += w * (x * ks[r][1] - y * ks[r][0]);
    for (int c = 0; c < 3; ++c) {
      h[r + 6 * (3 + c)] += w * ks[r][c];
      h[3 + r + 6 * c] -= w * sk[r][c];
      h[3 + r + 6 * (3 + c)] += w * s[r][c];
    }
  }
  double* g = eq.g.data();
  const double vx = v.x(), vy = v.y(), vz = v.z();
  g[0] += w * (y * vz - z * vy);
  g[1] += w * (z * vx - x * vz);
  g[2] += w * (x * vy - y * vx);
  g[3] += w * vx;
  g[4] += w * vy;
  g[5] += w * vz;
}

// One GICP pair: the moved scan point p, its residual d to the reference point or voxel mean, and
// the pair's combined covariance C_ref + R C_scan R^T: the plane-to-plane term d^T C^-1 d.
inline void add_plane_to_plane(NormalEquations& eq, const Vec3& p, const Vec3& d, const Eigen::Matrix3d& combined_covariance) {
  const Eigen::Matrix3d info = combined_covariance.inverse();
  const Vec3 info_d = info * d;
  add_point(eq, p, info, info_d, 1.0);
  eq.cost += d.dot(info_d);
  ++eq.count;
}

inline constexpr std::size_t kChunk = 256;

// Sums per_chunk(begin, end, equations) over [0, n) in chunks of kChunk.
template <class PerChunk>
NormalEquations accumulate(ThreadPool* pool, std::size_t n, PerChunk&& per_chunk) {
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<NormalEquations> partial(chunks);
  auto task = [&](std::size_t c) { per_chunk(c * kChunk, std::min(n, (c + 1) * kChunk), partial[c]); };
  if (pool) {
    pool->run(chunks, task);
  } else {
    for (std::size_t c = 0; c < chunks; ++c) task(c);
  }
  NormalEquations total;
  for (const NormalEquations& p : partial) total.add(p);
  return total;
}

// Gauss-Newton from `guess`: linearise(T) gives the normal equations at T (correspondences found
// anew each time). Stops when a step is within the tolerances (converged), after max_iterations,
// or when fewer than 6 points contribute (not converged).
template <class Linearise>
CloudMatch gauss_newton(const Rigid3& guess, const RegistrationLimits& limits, Linearise&& linearise) {
  CloudMatch m;
  Rigid3 t = guess;
  for (int it = 1; it <= limits.max_iterations; ++it) {
    const NormalEquations eq = linearise(t);
    m.iterations = it;
    if (eq.count < 6) break;
    // A tiny damping keeps a degenerate direction (a corridor along its axis) from exploding.
    const Matrix6 h = eq.h + 1e-9 * eq.h.diagonal().cwiseAbs().maxCoeff() * Matrix6::Identity();
    const Vector6 step = -h.ldlt().solve(eq.g);
    if (!step.allFinite()) break;
    t = se3_exp(step) * t;
    if (step.head<3>().norm() < limits.rotation_tolerance_rad && step.tail<3>().norm() < limits.translation_tolerance_m) {
      m.converged = true;
      break;
    }
  }
  // Re-orthonormalise: many small products drift off SO(3) by rounding.
  t.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
  m.transform = t;
  return m;
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace starnav::registration_detail
