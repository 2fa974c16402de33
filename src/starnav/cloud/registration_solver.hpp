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
using Jacobian = Eigen::Matrix<double, 3, 6>;

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

// dp/dxi at p.
inline Jacobian point_jacobian(const Vec3& p) {
  Jacobian j;
  j << 0, p.z(), -p.y(), 1, 0, 0,  //
      -p.z(), 0, p.x(), 0, 1, 0,   //
      p.y(), -p.x(), 0, 0, 0, 1;
  return j;
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
