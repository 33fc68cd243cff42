#pragma once
// SE(2)/SE(3) helpers on Eigen shared by every module: construction, minimal vectors, SO(3)
// exponential and logarithm. Trivial functions are inline; the rest lives in geometry.cpp.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace plugslam {
inline namespace abi_v1 {

/// A rigid transform in the plane.
using SE2 = Eigen::Isometry2d;
/// A rigid transform in space.
using SE3 = Eigen::Isometry3d;
/// Minimal vector of an SE3: translation then rotation vector (axis * angle).
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// Wraps an angle to [-pi, pi).
inline double normalizeAngle(double a) {
  if (a >= -M_PI && a < M_PI) return a;
  return a - 2.0 * M_PI * std::floor((a + M_PI) / (2.0 * M_PI));
}

/// The 2D rotation matrix of angle theta.
inline Eigen::Matrix2d rotation2(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

/// The SE2 with translation (x, y) and heading theta.
inline SE2 se2(double x, double y, double theta) {
  SE2 t = SE2::Identity();
  t.linear() = rotation2(theta);
  t.translation() << x, y;
  return t;
}

/// The heading of a 2D rotation matrix.
inline double angleOf(const Eigen::Matrix2d& r) { return std::atan2(r(1, 0), r(0, 0)); }

/// (x, y, theta) of an SE2, theta in [-pi, pi).
inline Eigen::Vector3d toVector(const SE2& t) {
  return Eigen::Vector3d(t.translation().x(), t.translation().y(), angleOf(t.linear()));
}

/// The SE2 of a (x, y, theta) vector.
inline SE2 se2(const Eigen::Vector3d& v) { return se2(v.x(), v.y(), v.z()); }

/// The skew-symmetric matrix of v, so that skew(v) * w = v x w.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// SO(3) exponential: the rotation of rotation vector w (Rodrigues).
Eigen::Matrix3d so3Exp(const Eigen::Vector3d& w);

/// SO(3) logarithm: the rotation vector (angle in [0, pi]) of rotation r.
Eigen::Vector3d so3Log(const Eigen::Matrix3d& r);

/// The SE3 with translation t and rotation q (q need not be normalised; it is normalised here).
inline SE3 se3(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  SE3 x = SE3::Identity();
  x.linear() = q.normalized().toRotationMatrix();
  x.translation() = t;
  return x;
}

/// The unit quaternion of an SE3's rotation, with w >= 0.
inline Eigen::Quaterniond quaternionOf(const SE3& x) {
  Eigen::Quaterniond q(x.linear());
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return q;
}

/// The SE3 of a minimal 6-vector (translation, rotation vector).
inline SE3 se3(const Vector6d& v) {
  SE3 x = SE3::Identity();
  x.linear() = so3Exp(v.tail<3>());
  x.translation() = v.head<3>();
  return x;
}

/// The minimal 6-vector (translation, rotation vector) of an SE3.
inline Vector6d toVector(const SE3& x) {
  Vector6d v;
  v.head<3>() = x.translation();
  v.tail<3>() = so3Log(x.linear());
  return v;
}

/// The rotation of r projected to the nearest proper rotation (SVD; fixes drift and chordal
/// relaxation outputs).
Eigen::Matrix3d projectToSO3(const Eigen::Matrix3d& r);

/// The 2D rotation nearest to m in Frobenius norm.
Eigen::Matrix2d projectToSO2(const Eigen::Matrix2d& m);

}  // namespace abi_v1
}  // namespace plugslam
