#pragma once
// The Multi-Aligner's Gauss-Newton normal equations on its one pose, and the one path by which
// every aligner slice adds its factors: NormalEquations::add takes a typed factor (error
// dimension and Jacobian size fixed at compile time, see solver/registration_factors.h), applies
// the slice's robust kernel and counts inliers. Nothing is allocated per factor.
// A typed factor F has `using Space` (Space2D/3D), `kErrorDim`, `Error` (E x 1), `Jacobian`
// (E x dof), `Error error(T)` and `errorAndJacobian(T, e, J)`; the latter may return bool, false
// when the factor does not apply at T (a landmark behind the camera): add() then adds nothing.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include "plugslam/pose_space.h"
#include "plugslam/solver/registration_factors.h"
#include "plugslam/solver/robust_kernel.h"

namespace plugslam {
inline namespace abi_v1 {

/// How a slice's factors are robustified and counted.
struct Robust {
  /// Kernel on each factor's squared Mahalanobis error (nullptr: plain least squares).
  const RobustKernel* kernel = nullptr;
  /// A factor whose error has at most this Euclidean norm (in the error's own units, before the
  /// information) is an inlier...
  double inlier_bound = std::numeric_limits<double>::infinity();
  /// ...and whose squared Mahalanobis error is at most this (e.g. a chi-square quantile).
  double inlier_chi2 = std::numeric_limits<double>::infinity();
};

/// Sees every factor added to NormalEquations (tests run checkJacobian on each).
class FactorObserver {
 public:
  virtual ~FactorObserver();
  /// One factor as a graph factor on a pose variable at the linearisation point, with the
  /// information it was added with (valid during the call only).
  virtual void observe(const FactorBase& factor) = 0;
};

/// Gauss-Newton normal equations of the aligner's single pose: the sums over one slice's factors
/// (the aligner gives each slice its own, then adds them up).
template <class S>
struct NormalEquations {
  using Pose = typename S::Pose;  ///< the pose the factors are on
  /// An E x E information matrix.
  template <int E>
  using Information = Eigen::Matrix<double, E, E>;

  typename S::Matrix H = S::Matrix::Zero();  ///< J^T W J
  typename S::Vector b = S::Vector::Zero();  ///< J^T W e
  double chi2 = 0;                           ///< sum of robustified squared errors
  size_t inliers = 0;                        ///< factors within their slice's inlier band
  size_t factors = 0;                        ///< factors added
  /// Measurement elements the slice tried to associate, the base of its overlap; the slice sets
  /// it (0: not known, the overlap is then the inlier ratio).
  size_t candidates = 0;
  /// Sees every factor added (nullptr: none; tests). Kept by clear().
  FactorObserver* observer = nullptr;

  /// Zeroes the sums and counts.
  void clear() {
    H.setZero();
    b.setZero();
    chi2 = 0;
    inliers = factors = candidates = 0;
  }

  /// Adds factor F at estimate t with isotropic information (1 / sigma^2 on every component).
  /// Returns false when the factor does not apply at t (nothing added).
  template <class F>
  bool add(const F& factor, const Pose& t, double information, const Robust& robust = {}) {
    static_assert(std::is_same_v<typename F::Space, S>, "a factor of another pose space");
    typename F::Error e;
    typename F::Jacobian j;
    if (!evaluate(factor, t, e, j)) return false;
    double norm, w;
    if constexpr (F::kErrorDim == 1) {
      norm = std::abs(e[0]);
      w = weight(e[0] * e[0] * information, norm, robust) * information;
      H.noalias() += w * j.transpose() * j;
      b.noalias() += w * e[0] * j.transpose();
    } else {
      const double sq = e.squaredNorm();
      norm = std::sqrt(sq);
      w = weight(sq * information, norm, robust) * information;
      H.noalias() += w * j.transpose() * j;
      b.noalias() += w * j.transpose() * e;
    }
    if (observer)
      observe(factor, t, Information<F::kErrorDim>::Identity() * information);
    return true;
  }

  /// Adds factor F at estimate t with a full information matrix. Returns false when the factor
  /// does not apply at t.
  template <class F>
  bool add(const F& factor, const Pose& t, const Information<F::kErrorDim>& information,
           const Robust& robust = {}) {
    static_assert(std::is_same_v<typename F::Space, S>, "a factor of another pose space");
    typename F::Error e;
    typename F::Jacobian j;
    if (!evaluate(factor, t, e, j)) return false;
    const Eigen::Matrix<double, S::kDof, F::kErrorDim> jt_omega = j.transpose() * information;
    const double w = weight(e.dot(information * e), std::sqrt(e.squaredNorm()), robust);
    // Without a kernel w is exactly 1: the sums are the plain J^T Omega J and J^T Omega e.
    H += w * (jt_omega * j);
    b += w * (jt_omega * e);
    if (observer) observe(factor, t, information);
    return true;
  }

  /// Adds factor F at estimate t with a diagonal information matrix (one 1 / sigma^2 per error
  /// component; a zero gives that component no weight). Returns false when the factor does not
  /// apply at t.
  template <class F>
  bool addDiagonal(const F& factor, const Pose& t,
                   const Eigen::Matrix<double, F::kErrorDim, 1>& information,
                   const Robust& robust = {}) {
    static_assert(std::is_same_v<typename F::Space, S>, "a factor of another pose space");
    typename F::Error e;
    typename F::Jacobian j;
    if (!evaluate(factor, t, e, j)) return false;
    const double w =
        weight(e.dot(information.cwiseProduct(e)), std::sqrt(e.squaredNorm()), robust);
    const Eigen::Matrix<double, S::kDof, F::kErrorDim> jt_w =
        j.transpose() * (w * information).asDiagonal();
    H.noalias() += jt_w * j;
    b.noalias() += jt_w * e;
    if (observer) observe(factor, t, Information<F::kErrorDim>(information.asDiagonal()));
    return true;
  }

 private:
  // The factor's error and Jacobian at t; false when it does not apply there.
  template <class F>
  static bool evaluate(const F& factor, const Pose& t, typename F::Error& e,
                       typename F::Jacobian& j) {
    if constexpr (std::is_same_v<decltype(factor.errorAndJacobian(t, e, j)), bool>) {
      return factor.errorAndJacobian(t, e, j);
    } else {
      factor.errorAndJacobian(t, e, j);
      return true;
    }
  }

  // Counts the factor and adds its robust cost; returns the IRLS weight rho'(s).
  double weight(double s, double norm, const Robust& robust) {
    ++factors;
    if (norm <= robust.inlier_bound && s <= robust.inlier_chi2) ++inliers;
    if (!robust.kernel) {
      chi2 += s;
      return 1.0;
    }
    const Eigen::Vector3d rho = robust.kernel->robustify(s);
    chi2 += rho[0];
    return rho[1];
  }

  template <class F>
  void observe(const F& factor, const Pose& t,
               const Information<F::kErrorDim>& information) const {
    PoseVariable<S> pose(0, t);
    PoseFactor<F> graph_factor(&pose, factor);
    graph_factor.setInformation(information);
    observer->observe(graph_factor);
  }
};

}  // namespace abi_v1
}  // namespace plugslam
