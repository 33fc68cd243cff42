#include "plugslam/geometry.h"

#include <Eigen/SVD>

namespace plugslam {
inline namespace abi_v1 {

Eigen::Matrix3d so3Exp(const Eigen::Vector3d& w) {
  const double theta2 = w.squaredNorm();
  const Eigen::Matrix3d k = skew(w);
  if (theta2 < 1e-20) return Eigen::Matrix3d::Identity() + k;
  const double theta = std::sqrt(theta2);
  // Taylor branch keeps full precision where sin/cos cancel.
  double a, b;
  if (theta < 1e-4) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta2;
  }
  return Eigen::Matrix3d::Identity() + a * k + b * k * k;
}

Eigen::Vector3d so3Log(const Eigen::Matrix3d& r) {
  // The quaternion route is accurate near 0 and near pi, unlike acos((tr-1)/2).
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double vn = q.vec().norm();
  if (vn < 1e-12) return 2.0 * q.vec() / q.w();
  const double angle = 2.0 * std::atan2(vn, q.w());
  return q.vec() * (angle / vn);
}

Eigen::Matrix3d projectToSO3(const Eigen::Matrix3d& r) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) d(2, 2) = -1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

Eigen::Matrix2d projectToSO2(const Eigen::Matrix2d& m) {
  // For 2x2 the nearest rotation has angle atan2(m10 - m01, m00 + m11).
  return rotation2(std::atan2(m(1, 0) - m(0, 1), m(0, 0) + m(1, 1)));
}

}  // namespace abi_v1
}  // namespace plugslam
