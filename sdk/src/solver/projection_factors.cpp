#include "plugslam/solver/projection_factors.h"

#include <algorithm>

namespace plugslam {
inline namespace abi_v1 {

namespace {
// Depth is kept away from 0 so a landmark crossing the image plane gives a large, finite error.
constexpr double kMinDepth = 1e-6;

inline Eigen::Vector3d toCamera(const SE3& pose, const Eigen::Vector3d& pw) {
  return pose.linear().transpose() * (pw - pose.translation());
}

// Jacobian of the camera-frame point w.r.t. (rho, phi, landmark).
inline Eigen::Matrix<double, 3, 9> cameraPointJacobian(const SE3& pose, const Eigen::Vector3d& pc) {
  Eigen::Matrix<double, 3, 9> j;
  j.block<3, 3>(0, 0) = -Eigen::Matrix3d::Identity();
  j.block<3, 3>(0, 3) = skew(pc);
  j.block<3, 3>(0, 6) = pose.linear().transpose();
  return j;
}
}  // namespace

ReprojectionFactor::ReprojectionFactor(VariableSE3* pose, VariablePoint3* point,
                                       const Eigen::Vector2d& uv, const PinholeCamera& camera)
    : Factor(pose, point), uv_(uv), camera_(camera) {}

ReprojectionFactor::ErrorVector ReprojectionFactor::error() const {
  const Eigen::Vector3d pc = toCamera(var<0>()->estimate(), var<1>()->estimate());
  const double z = std::max(pc.z(), kMinDepth);
  return Eigen::Vector2d(camera_.fx * pc.x() / z + camera_.cx - uv_.x(),
                         camera_.fy * pc.y() / z + camera_.cy - uv_.y());
}

void ReprojectionFactor::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE3& pose = var<0>()->estimate();
  const Eigen::Vector3d pc = toCamera(pose, var<1>()->estimate());
  const double z = std::max(pc.z(), kMinDepth);
  e << camera_.fx * pc.x() / z + camera_.cx - uv_.x(),
      camera_.fy * pc.y() / z + camera_.cy - uv_.y();
  Eigen::Matrix<double, 2, 3> dp;
  dp << camera_.fx / z, 0.0, -camera_.fx * pc.x() / (z * z), 0.0, camera_.fy / z,
      -camera_.fy * pc.y() / (z * z);
  J = dp * cameraPointJacobian(pose, pc);
}

StereoFactor::StereoFactor(VariableSE3* pose, VariablePoint3* point, const Eigen::Vector3d& uvu,
                           const PinholeCamera& camera)
    : Factor(pose, point), uvu_(uvu), camera_(camera) {}

StereoFactor::ErrorVector StereoFactor::error() const {
  const Eigen::Vector3d pc = toCamera(var<0>()->estimate(), var<1>()->estimate());
  const double z = std::max(pc.z(), kMinDepth);
  return Eigen::Vector3d(camera_.fx * pc.x() / z + camera_.cx - uvu_.x(),
                         camera_.fy * pc.y() / z + camera_.cy - uvu_.y(),
                         camera_.fx * (pc.x() - camera_.baseline) / z + camera_.cx - uvu_.z());
}

void StereoFactor::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  const SE3& pose = var<0>()->estimate();
  const Eigen::Vector3d pc = toCamera(pose, var<1>()->estimate());
  const double z = std::max(pc.z(), kMinDepth);
  const double xr = pc.x() - camera_.baseline;
  e << camera_.fx * pc.x() / z + camera_.cx - uvu_.x(),
      camera_.fy * pc.y() / z + camera_.cy - uvu_.y(), camera_.fx * xr / z + camera_.cx - uvu_.z();
  Eigen::Matrix3d dp;
  dp << camera_.fx / z, 0.0, -camera_.fx * pc.x() / (z * z), 0.0, camera_.fy / z,
      -camera_.fy * pc.y() / (z * z), camera_.fx / z, 0.0, -camera_.fx * xr / (z * z);
  J = dp * cameraPointJacobian(pose, pc);
}

}  // namespace abi_v1
}  // namespace plugslam
