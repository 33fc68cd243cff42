#include "plugslam/slice_check.h"

#include <algorithm>

namespace plugslam {
inline namespace abi_v1 {

namespace {

// How far a check is from passing: its largest block error in units of its tolerance.
double excess(const JacobianCheckResult& r) {
  double worst = 0;
  for (size_t i = 0; i < r.max_abs_error.size(); ++i)
    worst = std::max(worst, r.max_abs_error[i] / (r.tolerance * std::max(1.0, r.max_abs_value[i])));
  return r.ok ? worst : std::max(worst, 1.0);
}

class Checker final : public FactorObserver {
 public:
  Checker(double tolerance, double h) : tolerance_(tolerance), h_(h) {}
  void observe(const FactorBase& factor) override {
    const JacobianCheckResult r = checkJacobian(factor, tolerance_, h_);
    ++result.factors;
    if (!r.ok) ++result.failed;
    const double e = excess(r);
    if (result.factors == 1 || e > worst_) {
      worst_ = e;
      result.worst = r;
    }
  }
  SliceJacobianCheck result;

 private:
  double tolerance_, h_, worst_ = 0;
};

}  // namespace

std::string SliceJacobianCheck::describe() const {
  return std::to_string(failed) + " of " + std::to_string(factors) +
         " factors outside the tolerance; worst: " + (factors ? worst.describe() : "none");
}

template <class S>
SliceJacobianCheck checkSliceJacobians(const AlignerSlice<S>& slice, const typename S::Pose& t,
                                       double tolerance, double h) {
  Checker checker(tolerance, h);
  NormalEquations<S> eq;
  eq.observer = &checker;
  slice.linearize(t, eq);
  return checker.result;
}

template SliceJacobianCheck checkSliceJacobians<Space2D>(const AlignerSlice<Space2D>&,
                                                         const Space2D::Pose&, double, double);
template SliceJacobianCheck checkSliceJacobians<Space3D>(const AlignerSlice<Space3D>&,
                                                         const Space3D::Pose&, double, double);

}  // namespace abi_v1
}  // namespace plugslam
