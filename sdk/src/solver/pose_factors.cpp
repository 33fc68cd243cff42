#include "plugslam/solver/pose_factors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
// d tE / d phi for a planar rotation: J v with J = [0 -1; 1 0].
inline Eigen::Vector2d perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

// Derivative of q.vec of R * Exp(phi) w.r.t. phi at 0, q with w >= 0.
inline Eigen::Matrix3d quaternionVecJacobian(const Eigen::Quaterniond& q) {
  return 0.5 * (q.w() * Eigen::Matrix3d::Identity() + skew(q.vec()));
}

inline Eigen::Quaterniond positiveQuaternion(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return q;
}
}  // namespace

BetweenFactorSE2::BetweenFactorSE2(VariableSE2* xi, VariableSE2* xj, const SE2& measurement,
                                   const Eigen::Matrix3d& information)
    : PoseMeasurementFactor(xi, xj, measurement, information),
      measurement_angle_(angleOf(measurement.linear())) {}

BetweenFactorSE2::ErrorVector BetweenFactorSE2::error() const {
  const SE2& xi = var<0>()->estimate();
  const SE2& xj = var<1>()->estimate();
  const Eigen::Vector2d tij = xi.linear().transpose() * (xj.translation() - xi.translation());
  const double th = angleOf(xj.linear()) - angleOf(xi.linear()) - measurement_angle_;
  ErrorVector e;
  e.head<2>() = inverse_measurement_.linear() * tij + inverse_measurement_.translation();
  e[2] = normalizeAngle(th);
  return e;
}

void BetweenFactorSE2::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE2& xi = var<0>()->estimate();
  const SE2& xj = var<1>()->estimate();
  const Eigen::Matrix2d& rzt = inverse_measurement_.linear();
  const Eigen::Matrix2d rij = xi.linear().transpose() * xj.linear();
  const Eigen::Vector2d tij = xi.linear().transpose() * (xj.translation() - xi.translation());
  e.head<2>() = rzt * tij + inverse_measurement_.translation();
  e[2] = normalizeAngle(angleOf(xj.linear()) - angleOf(xi.linear()) - measurement_angle_);
  J.setZero();
  J.block<2, 2>(0, 0) = -rzt;
  J.block<2, 1>(0, 2) = -rzt * perp(tij);
  J(2, 2) = -1.0;
  J.block<2, 2>(0, 3) = rzt * rij;
  J(2, 5) = 1.0;
}

BetweenFactorSE3::BetweenFactorSE3(VariableSE3* xi, VariableSE3* xj, const SE3& measurement,
                                   const Eigen::Matrix<double, 6, 6>& information)
    : PoseMeasurementFactor(xi, xj, measurement, information) {}

BetweenFactorSE3::ErrorVector BetweenFactorSE3::error() const {
  const SE3& xi = var<0>()->estimate();
  const SE3& xj = var<1>()->estimate();
  const Eigen::Matrix3d rij = xi.linear().transpose() * xj.linear();
  const Eigen::Vector3d tij = xi.linear().transpose() * (xj.translation() - xi.translation());
  ErrorVector e;
  e.head<3>() = inverse_measurement_.linear() * tij + inverse_measurement_.translation();
  e.tail<3>() = positiveQuaternion(inverse_measurement_.linear() * rij).vec();
  return e;
}

void BetweenFactorSE3::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE3& xi = var<0>()->estimate();
  const SE3& xj = var<1>()->estimate();
  const Eigen::Matrix3d& rzt = inverse_measurement_.linear();
  const Eigen::Matrix3d rij = xi.linear().transpose() * xj.linear();
  const Eigen::Vector3d tij = xi.linear().transpose() * (xj.translation() - xi.translation());
  const Eigen::Matrix3d re = rzt * rij;
  const Eigen::Quaterniond q = positiveQuaternion(re);
  e.head<3>() = rzt * tij + inverse_measurement_.translation();
  e.tail<3>() = q.vec();
  const Eigen::Matrix3d qd = quaternionVecJacobian(q);
  J.setZero();
  J.block<3, 3>(0, 0) = -rzt;
  J.block<3, 3>(0, 3) = rzt * skew(tij);
  J.block<3, 3>(3, 3) = -qd * rij.transpose();
  J.block<3, 3>(0, 6) = re;
  J.block<3, 3>(3, 9) = qd;
}

PriorFactorSE2::PriorFactorSE2(VariableSE2* x, const SE2& measurement,
                               const Eigen::Matrix3d& information)
    : PoseMeasurementFactor(x, measurement, information),
      measurement_angle_(angleOf(measurement.linear())) {}

PriorFactorSE2::ErrorVector PriorFactorSE2::error() const {
  const SE2& x = var<0>()->estimate();
  ErrorVector e;
  e.head<2>() =
      inverse_measurement_.linear() * x.translation() + inverse_measurement_.translation();
  e[2] = normalizeAngle(angleOf(x.linear()) - measurement_angle_);
  return e;
}

void PriorFactorSE2::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE2& x = var<0>()->estimate();
  e = error();
  J.setZero();
  J.block<2, 2>(0, 0) = inverse_measurement_.linear() * x.linear();
  J(2, 2) = 1.0;
}

PriorFactorSE3::PriorFactorSE3(VariableSE3* x, const SE3& measurement,
                               const Eigen::Matrix<double, 6, 6>& information)
    : PoseMeasurementFactor(x, measurement, information) {}

PriorFactorSE3::ErrorVector PriorFactorSE3::error() const {
  const SE3& x = var<0>()->estimate();
  ErrorVector e;
  e.head<3>() =
      inverse_measurement_.linear() * x.translation() + inverse_measurement_.translation();
  e.tail<3>() = positiveQuaternion(inverse_measurement_.linear() * x.linear()).vec();
  return e;
}

void PriorFactorSE3::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE3& x = var<0>()->estimate();
  const Eigen::Matrix3d re = inverse_measurement_.linear() * x.linear();
  const Eigen::Quaterniond q = positiveQuaternion(re);
  e.head<3>() =
      inverse_measurement_.linear() * x.translation() + inverse_measurement_.translation();
  e.tail<3>() = q.vec();
  J.setZero();
  J.block<3, 3>(0, 0) = re;
  J.block<3, 3>(3, 3) = quaternionVecJacobian(q);
}

}  // namespace abi_v1
}  // namespace plugslam
