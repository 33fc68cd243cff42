#pragma once
// Wheel odometry of the vehicle that carries the 3D simulator's camera: the ground-truth motion
// projected onto the vehicle's ground plane, with sim2d's wheel-encoder errors (per-wheel scale,
// wheel base, slip; sim2d::OdometryNoise), so 2D and 3D sessions share one odometry model.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "plugslam/trajectory.h"
#include "sim2d/robot.h"
#include "sim3d/trajectory.h"

namespace plugslam {
namespace sim {
namespace sim3d {

/// The vehicle's wheel odometry settings.
struct WheelOdometryOptions {
  sim2d::OdometryNoise noise;            ///< per-wheel errors (sim2d's preset by default)
  double wheel_base = 1.6;               ///< distance between the left and right wheels [m]
  double camera_height = kCameraHeight;  ///< camera above the road (the vehicle base) [m]
  uint64_t seed = 0;                     ///< the noise stream
};

/// The camera (optical frame: x right, y down, z forward) in the vehicle's base frame (x
/// forward, y left, z up, on the road under the camera): level, `height` metres up.
Eigen::Isometry3d cameraInVehicle(double height);

/// The odometry pose (the base in the odometry frame) at each pose of a camera trajectory. The
/// odometry frame is the world's ground plane at the first pose, so the first reading is the
/// first base pose projected to (x, y, yaw). Each step integrates the base's true motion
/// projected onto the base's own plane (x, y, yaw of the 3D step in the base frame; what a
/// wheel encoder sees of a car on a slope), perturbed by the encoder errors of the wheel travels
/// that motion takes. Without noise the readings are the projected ground truth exactly.
std::vector<Eigen::Isometry2d> wheelOdometry(const Trajectory& camera,
                                             const WheelOdometryOptions& options);

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
