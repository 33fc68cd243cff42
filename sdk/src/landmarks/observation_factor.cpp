#include "plugslam/landmarks/observation_factor.h"

#include "plugslam/geometry.h"

namespace plugslam {
inline namespace abi_v1 {

bool projectInverseDepth(const PinholeCamera& c, const Eigen::Vector3d& pc,
                         Eigen::Vector3d& predicted, Eigen::Matrix3d* jacobian) {
  if (!(pc.z() > kMinProjectionDepth)) return false;
  const double q = 1.0 / pc.z();
  predicted << c.fx * pc.x() * q + c.cx, c.fy * pc.y() * q + c.cy, q;
  if (jacobian) {
    *jacobian << c.fx * q, 0.0, -c.fx * pc.x() * q * q,  //
        0.0, c.fy * q, -c.fy * pc.y() * q * q,            //
        0.0, 0.0, -q * q;
  }
  return true;
}

bool observationError(const Eigen::Isometry3d& t, const Eigen::Isometry3d& mount,
                      const PinholeCamera& camera, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& measured, Eigen::Vector3d& e,
                      Eigen::Matrix<double, 3, 6>* j_pose, Eigen::Matrix3d* j_point) {
  // Robot frame, then camera frame: p_r = R^T (p - t), p_c = M^-1 p_r.
  const Eigen::Vector3d pr = t.linear().transpose() * (p - t.translation());
  const Eigen::Matrix3d rm_t = mount.linear().transpose();
  const Eigen::Vector3d pc = rm_t * (pr - mount.translation());
  Eigen::Vector3d predicted;
  Eigen::Matrix3d dproj;
  if (!projectInverseDepth(camera, pc, predicted, (j_pose || j_point) ? &dproj : nullptr))
    return false;
  e = predicted - measured;
  if (j_pose || j_point) {
    const Eigen::Matrix3d d = dproj * rm_t;  // d(u, v, q) / d p_r
    // T <- T exp(delta): p_r <- exp(-delta) p_r, so d p_r = -d_t + [p_r]x d_w.
    if (j_pose) {
      j_pose->leftCols<3>() = -d;
      j_pose->rightCols<3>() = d * skew(pr);
    }
    if (j_point) *j_point = d * t.linear().transpose();
  }
  return true;
}

LandmarkObservationFactor::LandmarkObservationFactor(VariableSE3* robot, VariablePoint3* landmark,
                                                     const Eigen::Vector3d& measured,
                                                     const PinholeCamera& camera,
                                                     const Eigen::Isometry3d& mount)
    : Factor(robot, landmark), measured_(measured), camera_(camera), mount_(mount) {}

LandmarkObservationFactor::ErrorVector LandmarkObservationFactor::error() const {
  Eigen::Vector3d e;
  // Behind the camera: a large, finite error (as the SDK's ReprojectionFactor).
  if (!observationError(var<0>()->estimate(), mount_, camera_, var<1>()->estimate(), measured_, e,
                        nullptr, nullptr))
    e.setConstant(1e6);
  return e;
}

void LandmarkObservationFactor::errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
  Eigen::Matrix<double, 3, 6> jp;
  Eigen::Matrix3d jl;
  if (!observationError(var<0>()->estimate(), mount_, camera_, var<1>()->estimate(), measured_, e,
                        &jp, &jl)) {
    e.setConstant(1e6);
    J.setZero();
    return;
  }
  J.leftCols<6>() = jp;
  J.rightCols<3>() = jl;
}

}  // namespace abi_v1
}  // namespace plugslam
