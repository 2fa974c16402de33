#pragma once
// The damped step both pose graphs (pose_graph, pose_graph_3d) take: Levenberg-Marquardt with
// Marquardt's scaling, H + lambda (diag(H) + 1e-9), on a sparse normal system given by its lower
// triangle, solved by a sparse LDLT whose fill-reducing ordering (AMD) is analysed once. Up to 10
// tries per iteration: lambda x10 after a failed factorisation, x4 after a step that does not lower
// the cost, /3 (down to 1e-9) after one that does.
#include <algorithm>
#include <vector>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

namespace starnav {

class SparseLevenbergMarquardt {
 public:
  enum class Step { Accepted, Converged, Failed };

  // One iteration on H (its lower-triangle `triplets` and its `diagonal`) and the gradient `b`:
  // `retract(delta)` returns the state moved by delta, `cost_of(state)` its cost. On a lower cost
  // `state` and `cost` take the new values; Converged when the drop is at most
  // `relative_tolerance` of the cost before; Failed when no try lowered the cost.
  template <class State, class Retract, class Cost>
  Step step(const std::vector<Eigen::Triplet<double>>& triplets, const Eigen::VectorXd& diagonal, const Eigen::VectorXd& b,
            State& state, double& cost, double relative_tolerance, Retract&& retract, Cost&& cost_of) {
    const Eigen::Index n = b.size();
    for (int attempt = 0; attempt < 10; ++attempt) {
      damped_ = triplets;
      for (Eigen::Index i = 0; i < n; ++i) damped_.emplace_back(i, i, lambda_ * (diagonal(i) + 1e-9));
      Eigen::SparseMatrix<double> h(n, n);
      h.setFromTriplets(damped_.begin(), damped_.end());
      if (!analysed_) solver_.analyzePattern(h), analysed_ = true;
      solver_.factorize(h);
      if (solver_.info() != Eigen::Success) {
        lambda_ *= 10.0;
        continue;
      }
      const Eigen::VectorXd delta = solver_.solve(-b);
      State candidate = retract(delta);
      const double new_cost = cost_of(candidate);
      if (new_cost < cost) {
        const double drop = cost - new_cost;
        state = std::move(candidate);
        cost = new_cost;
        lambda_ = std::max(1e-9, lambda_ / 3.0);
        return drop <= relative_tolerance * std::max(cost + drop, 1e-300) ? Step::Converged : Step::Accepted;
      }
      lambda_ *= 4.0;
    }
    return Step::Failed;
  }

 private:
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> solver_;
  bool analysed_ = false;
  double lambda_ = 1e-4;
  std::vector<Eigen::Triplet<double>> damped_;
};

}  // namespace starnav
