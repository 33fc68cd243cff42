#pragma once
// Camera factors for Point3 landmarks. The pose variable is the camera pose in the world
// (camera -> world); the camera looks along +z, x right, y down.
#include "plugslam/solver/factor.h"

namespace plugslam {
inline namespace abi_v1 {

/// Pinhole intrinsics (pixels) and, for stereo, the baseline (metres, right camera at +x).
struct PinholeCamera {
  double fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0;  ///< focal lengths and principal point
  double baseline = 0.0;                          ///< stereo baseline
};

/// Monocular reprojection: e = project(T^-1 p) - (u, v).
class ReprojectionFactor final : public Factor<2, VariableSE3, VariablePoint3> {
 public:
  /// Observation (u, v) of landmark p from camera pose T.
  ReprojectionFactor(VariableSE3* pose, VariablePoint3* point, const Eigen::Vector2d& uv,
                     const PinholeCamera& camera);
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  Eigen::Vector2d uv_;
  PinholeCamera camera_;
};

/// Rectified stereo: e = (uL, v, uR)(T^-1 p) - measurement, uR = fx (x - baseline) / z + cx.
class StereoFactor final : public Factor<3, VariableSE3, VariablePoint3> {
 public:
  /// Observation (uL, v, uR) of landmark p from the left camera pose T.
  StereoFactor(VariableSE3* pose, VariablePoint3* point, const Eigen::Vector3d& uvu,
               const PinholeCamera& camera);
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  Eigen::Vector3d uvu_;
  PinholeCamera camera_;
};

}  // namespace abi_v1
}  // namespace plugslam
