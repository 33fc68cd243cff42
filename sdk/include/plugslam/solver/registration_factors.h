#pragma once
// Registration factors of an aligner: one pose variable T (moving -> fixed frame) and fixed
// measured points. p is a point of the moving set, q its associated fixed point, n the fixed
// normal (unit length).
#include "plugslam/solver/factor.h"

namespace plugslam {
inline namespace abi_v1 {

/// 2D point-to-point: e = T p - q.
class PointToPointFactor2D final : public Factor<2, VariableSE2> {
 public:
  /// Aligns moving point p to fixed point q.
  PointToPointFactor2D(VariableSE2* t, const Eigen::Vector2d& p, const Eigen::Vector2d& q);
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  Eigen::Vector2d p_, q_;
};

/// 3D point-to-point: e = T p - q.
class PointToPointFactor3D final : public Factor<3, VariableSE3> {
 public:
  /// Aligns moving point p to fixed point q.
  PointToPointFactor3D(VariableSE3* t, const Eigen::Vector3d& p, const Eigen::Vector3d& q);
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  Eigen::Vector3d p_, q_;
};

/// 2D point-to-line: e = n^T (T p - q).
class PointToLineFactor2D final : public Factor<1, VariableSE2> {
 public:
  /// Aligns moving point p to the line through q with normal n.
  PointToLineFactor2D(VariableSE2* t, const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                      const Eigen::Vector2d& n);
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  Eigen::Vector2d p_, q_, n_;
};

/// 3D point-to-plane: e = n^T (T p - q).
class PointToPlaneFactor3D final : public Factor<1, VariableSE3> {
 public:
  /// Aligns moving point p to the plane through q with normal n.
  PointToPlaneFactor3D(VariableSE3* t, const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                       const Eigen::Vector3d& n);
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  Eigen::Vector3d p_, q_, n_;
};

}  // namespace abi_v1
}  // namespace plugslam
