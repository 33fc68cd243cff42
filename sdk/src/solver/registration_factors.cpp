#include "plugslam/solver/registration_factors.h"

namespace plugslam {
inline namespace abi_v1 {

PointToPointFactor2D::PointToPointFactor2D(VariableSE2* t, const Eigen::Vector2d& p,
                                           const Eigen::Vector2d& q)
    : Factor(t), p_(p), q_(q) {}

PointToPointFactor2D::ErrorVector PointToPointFactor2D::error() const {
  const SE2& t = var<0>()->estimate();
  return t.linear() * p_ + t.translation() - q_;
}

void PointToPointFactor2D::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE2& t = var<0>()->estimate();
  const Eigen::Vector2d rp = t.linear() * p_;
  e = rp + t.translation() - q_;
  J.block<2, 2>(0, 0) = t.linear();
  J.col(2) = Eigen::Vector2d(-rp.y(), rp.x());
}

PointToPointFactor3D::PointToPointFactor3D(VariableSE3* t, const Eigen::Vector3d& p,
                                           const Eigen::Vector3d& q)
    : Factor(t), p_(p), q_(q) {}

PointToPointFactor3D::ErrorVector PointToPointFactor3D::error() const {
  const SE3& t = var<0>()->estimate();
  return t.linear() * p_ + t.translation() - q_;
}

void PointToPointFactor3D::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE3& t = var<0>()->estimate();
  e = t.linear() * p_ + t.translation() - q_;
  J.block<3, 3>(0, 0) = t.linear();
  J.block<3, 3>(0, 3) = -t.linear() * skew(p_);
}

PointToLineFactor2D::PointToLineFactor2D(VariableSE2* t, const Eigen::Vector2d& p,
                                         const Eigen::Vector2d& q, const Eigen::Vector2d& n)
    : Factor(t), p_(p), q_(q), n_(n) {}

PointToLineFactor2D::ErrorVector PointToLineFactor2D::error() const {
  const SE2& t = var<0>()->estimate();
  return ErrorVector(n_.dot(t.linear() * p_ + t.translation() - q_));
}

void PointToLineFactor2D::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE2& t = var<0>()->estimate();
  const Eigen::Vector2d rp = t.linear() * p_;
  e[0] = n_.dot(rp + t.translation() - q_);
  const Eigen::Vector2d nr = t.linear().transpose() * n_;
  J(0, 0) = nr.x();
  J(0, 1) = nr.y();
  J(0, 2) = n_.y() * rp.x() - n_.x() * rp.y();
}

PointToPlaneFactor3D::PointToPlaneFactor3D(VariableSE3* t, const Eigen::Vector3d& p,
                                           const Eigen::Vector3d& q, const Eigen::Vector3d& n)
    : Factor(t), p_(p), q_(q), n_(n) {}

PointToPlaneFactor3D::ErrorVector PointToPlaneFactor3D::error() const {
  const SE3& t = var<0>()->estimate();
  return ErrorVector(n_.dot(t.linear() * p_ + t.translation() - q_));
}

void PointToPlaneFactor3D::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE3& t = var<0>()->estimate();
  e[0] = n_.dot(t.linear() * p_ + t.translation() - q_);
  const Eigen::Vector3d nr = t.linear().transpose() * n_;
  J.block<1, 3>(0, 0) = nr.transpose();
  // d/dphi n^T R Exp(phi) p = -n^T R [p]x = (p x R^T n)^T.
  J.block<1, 3>(0, 3) = p_.cross(nr).transpose();
}

}  // namespace abi_v1
}  // namespace plugslam
