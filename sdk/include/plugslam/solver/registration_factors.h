#pragma once
// Registration factors on one pose T (moving -> fixed frame): p is a point of the moving set, q
// its associated fixed point, n the fixed normal (unit length). Each is a small typed factor with
// its error dimension and Jacobian size fixed at compile time, used two ways: an aligner slice
// adds it through NormalEquations::add at the aligner's estimate (inline, nothing allocated), and
// PoseFactor<F> makes it a graph factor on a pose variable (the optimizer, checkJacobian). The
// Jacobians are w.r.t. the right perturbation T * exp(dx) of Space2D/Space3D::boxplus, which is
// also the pose variables' oplus.
#include <type_traits>

#include "plugslam/pose_space.h"
#include "plugslam/solver/factor.h"

namespace plugslam {
inline namespace abi_v1 {

/// The pose variable of a pose space: VariableSE2 for Space2D, VariableSE3 for Space3D.
template <class S>
using PoseVariable = std::conditional_t<S::kDim == 2, VariableSE2, VariableSE3>;

namespace detail {
// The columns of de/dx for the rotation part of x, where e's rotated point is rp = R p. They are
// written per dimension (the plane's rotation is one angle, the space's a rotation vector); the
// rest of each factor is one template over the pose space.
inline Eigen::Vector2d pointRotationJacobian(const SE2&, const Eigen::Vector2d&,
                                             const Eigen::Vector2d& rp) {
  return Eigen::Vector2d(-rp.y(), rp.x());
}
inline Eigen::Matrix3d pointRotationJacobian(const SE3& t, const Eigen::Vector3d& p,
                                             const Eigen::Vector3d&) {
  return -t.linear() * skew(p);
}
// The same for n^T (T p - q), with nr = R^T n.
inline Eigen::Matrix<double, 1, 1> planeRotationJacobian(const Eigen::Vector2d&,
                                                         const Eigen::Vector2d& rp,
                                                         const Eigen::Vector2d& n,
                                                         const Eigen::Vector2d&) {
  return Eigen::Matrix<double, 1, 1>(n.y() * rp.x() - n.x() * rp.y());
}
inline Eigen::RowVector3d planeRotationJacobian(const Eigen::Vector3d& p, const Eigen::Vector3d&,
                                                const Eigen::Vector3d&,
                                                const Eigen::Vector3d& nr) {
  // d/dphi n^T R Exp(phi) p = -n^T R [p]x = (p x R^T n)^T.
  return p.cross(nr).transpose();
}
}  // namespace detail

/// Point-to-point in pose space S: e = T p - q.
template <class S>
struct PointToPoint {
  using Space = S;                                            ///< the pose space of T
  static constexpr int kErrorDim = S::kDim;                   ///< dimension of e
  using Point = Eigen::Matrix<double, S::kDim, 1>;            ///< a point of the space
  using Error = Point;                                        ///< e
  using Jacobian = Eigen::Matrix<double, S::kDim, S::kDof>;  ///< de / dx
  Point p;                                                    ///< moving point
  Point q;                                                    ///< fixed point
  /// The error at T.
  Error error(const typename S::Pose& t) const { return t.linear() * p + t.translation() - q; }
  /// The error and its Jacobian at T.
  void errorAndJacobian(const typename S::Pose& t, Error& e, Jacobian& j) const {
    const Point rp = t.linear() * p;
    e = rp + t.translation() - q;
    j.template leftCols<S::kDim>() = t.linear();
    j.template rightCols<S::kDof - S::kDim>() = detail::pointRotationJacobian(t, p, rp);
  }
};

/// Point-to-plane in pose space S (in 2D the plane is a line): e = n^T (T p - q).
template <class S>
struct PointToPlane {
  using Space = S;                                       ///< the pose space of T
  static constexpr int kErrorDim = 1;                    ///< dimension of e
  using Point = Eigen::Matrix<double, S::kDim, 1>;       ///< a point of the space
  using Error = Eigen::Matrix<double, 1, 1>;             ///< e
  using Jacobian = Eigen::Matrix<double, 1, S::kDof>;  ///< de / dx
  Point p;                                               ///< moving point
  Point q;                                               ///< a point of the fixed plane
  Point n;                                               ///< the fixed plane's normal
  /// The error at T.
  Error error(const typename S::Pose& t) const {
    return Error(n.dot(t.linear() * p + t.translation() - q));
  }
  /// The error and its Jacobian at T.
  void errorAndJacobian(const typename S::Pose& t, Error& e, Jacobian& j) const {
    const Point rp = t.linear() * p;
    e[0] = n.dot(rp + t.translation() - q);
    const Point nr = t.linear().transpose() * n;
    j.template leftCols<S::kDim>() = nr.transpose();
    j.template rightCols<S::kDof - S::kDim>() = detail::planeRotationJacobian(p, rp, n, nr);
  }
};

/// 2D point-to-point: e = T p - q.
using PointToPoint2D = PointToPoint<Space2D>;
/// 3D point-to-point: e = T p - q.
using PointToPoint3D = PointToPoint<Space3D>;
/// 2D point-to-line: e = n^T (T p - q).
using PointToLine2D = PointToPlane<Space2D>;
/// 3D point-to-plane: e = n^T (T p - q).
using PointToPlane3D = PointToPlane<Space3D>;

/// A typed factor F on one pose (F::Space, F::kErrorDim, F::error(T), F::errorAndJacobian(T, e,
/// J)) as a graph factor on a pose variable.
template <class F>
class PoseFactor : public Factor<F::kErrorDim, PoseVariable<typename F::Space>> {
  using Base = Factor<F::kErrorDim, PoseVariable<typename F::Space>>;
  static_assert(std::is_same_v<typename F::Error, typename Base::ErrorVector> &&
                    std::is_same_v<typename F::Jacobian, typename Base::JacobianMatrix>,
                "a pose factor's Error and Jacobian are E x 1 and E x dof");

 public:
  /// F on the pose variable t.
  PoseFactor(PoseVariable<typename F::Space>* t, const F& factor) : Base(t), factor_(factor) {}
  /// The typed factor.
  const F& factor() const { return factor_; }
  typename Base::ErrorVector error() const override {
    return factor_.error(this->template var<0>()->estimate());
  }
  void errorAndJacobian(typename Base::ErrorVector& e,
                        typename Base::JacobianMatrix& j) const override {
    factor_.errorAndJacobian(this->template var<0>()->estimate(), e, j);
  }

 private:
  F factor_;
};

/// 2D point-to-point as a graph factor.
class PointToPointFactor2D final : public PoseFactor<PointToPoint2D> {
 public:
  /// Aligns moving point p to fixed point q.
  PointToPointFactor2D(VariableSE2* t, const Eigen::Vector2d& p, const Eigen::Vector2d& q)
      : PoseFactor(t, PointToPoint2D{p, q}) {}
};

/// 3D point-to-point as a graph factor.
class PointToPointFactor3D final : public PoseFactor<PointToPoint3D> {
 public:
  /// Aligns moving point p to fixed point q.
  PointToPointFactor3D(VariableSE3* t, const Eigen::Vector3d& p, const Eigen::Vector3d& q)
      : PoseFactor(t, PointToPoint3D{p, q}) {}
};

/// 2D point-to-line as a graph factor.
class PointToLineFactor2D final : public PoseFactor<PointToLine2D> {
 public:
  /// Aligns moving point p to the line through q with normal n.
  PointToLineFactor2D(VariableSE2* t, const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                      const Eigen::Vector2d& n)
      : PoseFactor(t, PointToLine2D{p, q, n}) {}
};

/// 3D point-to-plane as a graph factor.
class PointToPlaneFactor3D final : public PoseFactor<PointToPlane3D> {
 public:
  /// Aligns moving point p to the plane through q with normal n.
  PointToPlaneFactor3D(VariableSE3* t, const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                       const Eigen::Vector3d& n)
      : PoseFactor(t, PointToPlane3D{p, q, n}) {}
};

}  // namespace abi_v1
}  // namespace plugslam
