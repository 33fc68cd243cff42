#include "plugslam/multi_aligner.h"

#include <Eigen/Dense>

namespace plugslam {
inline namespace abi_v1 {

template <class S>
AlignerSlice<S>::~AlignerSlice() = default;

template <class S>
MultiAligner<S>::MultiAligner() = default;
template <class S>
MultiAligner<S>::~MultiAligner() = default;

template <class S>
AlignResult<S> MultiAligner<S>::align(const Frame& frame, const PropertyContainer& scene,
                                      const AlignContext<S>& context) {
  AlignResult<S> result;
  result.pose = context.guess;
  result.H.setZero();
  std::vector<AlignerSlice<S>*> active;
  for (auto& slice : slices)
    if (slice->bind(frame, scene, context)) active.push_back(slice.get());
  if (active.empty()) return result;

  NormalEquations<S> eq;
  typename S::Pose t = context.guess;
  for (int outer = 0; outer < outer_iterations(); ++outer) {
    for (auto* slice : active) slice->associate(t);
    bool step_converged = false;
    for (int inner = 0; inner < inner_iterations(); ++inner) {
      eq.clear();
      for (auto* slice : active) slice->linearize(t, eq);
      if (eq.factors == 0) return result;
      typename S::Matrix h = eq.H;
      h.diagonal().array() += damping();
      Eigen::LDLT<typename S::Matrix> ldlt(h);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return result;
      typename S::Vector dx = ldlt.solve(-eq.b);
      if (!dx.allFinite()) return result;
      t = S::boxplus(t, dx);
      ++result.iterations;
      if (dx.norm() < convergence()) {
        step_converged = true;
        break;
      }
    }
    // Converged when a fresh association no longer moves the estimate.
    if (step_converged && outer > 0) {
      result.converged = true;
      break;
    }
  }
  // Statistics and information at the solution.
  for (auto* slice : active) slice->associate(t);
  eq.clear();
  for (auto* slice : active) slice->linearize(t, eq);
  result.pose = t;
  result.H = eq.H;
  result.chi2 = eq.chi2;
  result.inliers = eq.inliers;
  result.factors = eq.factors;
  result.candidates = eq.candidates;
  // A solution needs enough inliers and a full-rank information matrix.
  Eigen::SelfAdjointEigenSolver<typename S::Matrix> eig(eq.H);
  result.valid = eq.inliers >= static_cast<size_t>(min_inliers()) &&
                 eig.eigenvalues().minCoeff() > 1e-9 * std::max(1.0, eig.eigenvalues().maxCoeff());
  return result;
}

template class AlignerSlice<Space2D>;
template class AlignerSlice<Space3D>;
template class MultiAligner<Space2D>;
template class MultiAligner<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
