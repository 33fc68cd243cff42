#include "odometry_frame.h"

#include <cmath>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "plugslam/pose_space.h"

namespace plugslam {
namespace odometry {

Param<std::vector<double>> mountParam(Configurable* owner) {
  return {owner,
          "mount",
          {},
          "m, rad",
          "the odometry's base frame (x forward, y left, z up) in the robot frame [x y z rx ry rz] "
          "(rotation vector); empty = the robot frame is the base"};
}

Eigen::Isometry3d mountFromParam(const std::vector<double>& v, const std::string& param) {
  if (v.empty()) return Eigen::Isometry3d::Identity();
  if (v.size() != 6)
    throw ParamError(param,
                     "expected [x y z rx ry rz] (6 values), got " + std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) throw ParamError(param, "expected finite values");
  Vector6d x;
  x << v[0], v[1], v[2], v[3], v[4], v[5];
  return se3(x);
}

Eigen::Isometry3d liftToRobot(const Eigen::Isometry2d& delta, const Eigen::Isometry3d& mount) {
  return Space3D::normalized(mount * Space2D::to3D(delta) * mount.inverse());
}

Eigen::Isometry2d planarInBase(const Eigen::Isometry3d& motion, const Eigen::Isometry3d& mount) {
  return Space2D::from3D(mount.inverse() * motion * mount);
}

}  // namespace odometry
}  // namespace plugslam
