#pragma once
// Where a planar wheel odometry sits in a 3D robot frame: the odometry measures its base (x
// forward, y left, z up, on the ground), while a 3D pipeline's robot frame is often a camera's
// optical frame (x right, y down, z forward). The 3D modules take the base's pose in the robot
// frame (`mount`) and move deltas between the two.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "plugslam/param.h"

namespace plugslam {
namespace odometry {

/// The `mount` parameter [x y z rx ry rz] on `owner`; each 3D module declares it as
/// `mount = mountParam(this)`, so that all of them describe the base's pose alike.
Param<std::vector<double>> mountParam(Configurable* owner);

/// The mount parameter [x y z rx ry rz] (metres, rotation vector in radians) as a pose; empty =
/// identity. Throws ParamError naming `param` for another length or a non-finite value.
Eigen::Isometry3d mountFromParam(const std::vector<double>& values, const std::string& param);

/// A planar odometry delta (in the base frame) as the robot frame's 3D motion, for the base at
/// `mount` in the robot frame: mount * to3D(delta) * mount^-1.
Eigen::Isometry3d liftToRobot(const Eigen::Isometry2d& delta, const Eigen::Isometry3d& mount);

/// The robot frame's 3D motion as the base's planar motion (x, y, yaw of
/// mount^-1 * motion * mount): what a wheel odometry can say about it.
Eigen::Isometry2d planarInBase(const Eigen::Isometry3d& motion, const Eigen::Isometry3d& mount);

}  // namespace odometry
}  // namespace plugslam
