#pragma once
// The landmark cue's measurement model: a camera at `mount` on a robot at pose T sees landmark p
// at pixel (u, v) with inverse depth q = 1/z. For a rectified stereo pair q is the disparity over
// fx * baseline, for an RGB-D camera the inverse of the depth reading: one residual serves both
// (a feature without depth simply gives q no weight).
#include <Eigen/Geometry>

#include "plugslam/solver/factor.h"
#include "plugslam/solver/projection_factors.h"

namespace plugslam {
inline namespace abi_v1 {

/// Nearer points than this along the optical axis are not projected [m].
constexpr double kMinProjectionDepth = 1e-3;

/// Projects the camera-frame point pc to (u, v, 1/z); false when it is not in front of the camera.
/// With `jacobian`, also d(u, v, 1/z) / d pc.
bool projectInverseDepth(const PinholeCamera& camera, const Eigen::Vector3d& pc,
                         Eigen::Vector3d& predicted, Eigen::Matrix3d* jacobian = nullptr);

/// Residual e = predicted - measured of one observation and its Jacobians w.r.t. a right
/// perturbation (translation, rotation vector) of the robot pose T (scene <- robot) and w.r.t.
/// the landmark p (scene frame). Returns false when p is behind the camera (e, J untouched).
bool observationError(const Eigen::Isometry3d& t, const Eigen::Isometry3d& mount,
                      const PinholeCamera& camera, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& measured, Eigen::Vector3d& e,
                      Eigen::Matrix<double, 3, 6>* j_pose, Eigen::Matrix3d* j_point);

/// One observation (u, v, 1/z) of a landmark from a camera mounted on a robot pose: the factor
/// behind the reprojection slice, and a bundle-adjustment term (both blocks analytic).
class LandmarkObservationFactor final : public Factor<3, VariableSE3, VariablePoint3> {
 public:
  /// `measured` = (u, v, 1/z); give 1/z zero information for a feature without depth.
  LandmarkObservationFactor(VariableSE3* robot, VariablePoint3* landmark,
                            const Eigen::Vector3d& measured, const PinholeCamera& camera,
                            const Eigen::Isometry3d& mount);
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  Eigen::Vector3d measured_;
  PinholeCamera camera_;
  Eigen::Isometry3d mount_;
};

}  // namespace abi_v1
}  // namespace plugslam
