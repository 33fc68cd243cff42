#include "plugslam/multi_aligner.h"

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

template <class S>
AlignerSlice<S>::~AlignerSlice() = default;

template <class S>
MultiAligner<S>::MultiAligner() = default;
template <class S>
MultiAligner<S>::~MultiAligner() = default;

template <class S>
void MultiAligner<S>::configure() {
  for (double h : retry_headings())
    if (!(std::abs(h) <= M_PI))
      throw ParamError("retry_headings",
                       "every value must be an angle in [-pi, pi] rad, got " + std::to_string(h));
}

template <class S>
AlignResult<S> MultiAligner<S>::align(const Frame& frame, const PropertyContainer& scene,
                                      const AlignContext<S>& context) {
  std::vector<AlignerSlice<S>*> active;
  for (auto& slice : slices)
    if (slice->bind(frame, scene, context)) active.push_back(slice.get());
  if (active.empty()) {
    AlignResult<S> none;
    none.pose = context.guess;
    none.H.setZero();
    return none;
  }
  AlignResult<S> result = solve(active, context.guess);
  if (result.valid) return result;
  // The last tangent coordinate is the rotation about the vertical axis in 2D and 3D alike.
  for (double heading : retry_headings()) {
    typename S::Vector turn = S::Vector::Zero();
    turn(S::kDof - 1) = heading;
    AlignResult<S> retry = solve(active, S::boxplus(context.guess, turn));
    if (retry.valid && (!result.valid || retry.inliers > result.inliers)) result = retry;
  }
  return result;
}

template <class S>
AlignResult<S> MultiAligner<S>::solve(const std::vector<AlignerSlice<S>*>& active,
                                      const Pose& guess) {
  AlignResult<S> result;
  result.pose = guess;
  result.H.setZero();
  NormalEquations<S> eq;
  typename S::Pose t = guess;
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
