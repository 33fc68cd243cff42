#pragma once
// Differential-drive kinematics, a pure-pursuit path follower and wheel odometry with realistic
// errors. Poses are Eigen::Vector3d (x, y, theta), theta in (-pi, pi].
#include <Eigen/Core>
#include <vector>

#include "sim2d/random.h"

namespace plugslam {
namespace sim {
namespace sim2d {

/// Wraps an angle to (-pi, pi].
double wrapAngle(double a);

/// Moves `pose` along the circular arc driven by left/right wheel travels dl, dr [m] with the
/// given wheel base [m] (exact for constant wheel speeds).
Eigen::Vector3d driveArc(const Eigen::Vector3d& pose, double dl, double dr, double wheel_base);

/// Robot geometry and motion limits of the simulated differential-drive platform.
struct DriveLimits {
  double max_linear = 0.5;       ///< [m/s]
  double max_angular = 1.0;      ///< [rad/s]
  double max_linear_acc = 0.6;   ///< [m/s^2]
  double max_angular_acc = 2.0;  ///< [rad/s^2]
  double lookahead = 0.6;        ///< pure-pursuit lookahead distance [m]
  double wheel_base = 0.4;       ///< distance between the wheels [m]
  double robot_radius = 0.25;    ///< body radius, for clearance checks [m]
};

/// Follows a polyline with the pure-pursuit law; turns in place when the path turns back.
class PurePursuit {
 public:
  /// The path must have at least two points; limits give speeds, accelerations and lookahead.
  PurePursuit(std::vector<Eigen::Vector2d> path, const DriveLimits& limits);

  /// Velocity command (v, omega) for the pose after dt seconds since the last call, respecting
  /// the acceleration limits; (0, 0) once the end of the path is reached.
  Eigen::Vector2d command(const Eigen::Vector3d& pose, double dt);

  /// True once the robot is within the lookahead of the path's last point.
  bool finished() const { return finished_; }

 private:
  Eigen::Vector2d pointAt(double s) const;  // point at arc length s along the path

  std::vector<Eigen::Vector2d> path_;
  std::vector<double> arc_;  // cumulative arc length at each path point
  DriveLimits limits_;
  double progress_ = 0.0;  // arc length of the closest path point
  size_t segment_ = 0;     // path segment holding progress_
  Eigen::Vector2d velocity_{0.0, 0.0};
  bool turning_in_place_ = false;
  bool finished_ = false;
};

/// Wheel-odometry errors. Measured wheel travel = true * (1 + scale_error) + slip, where slip is
/// zero-mean normal with variance slip_per_distance^2 * |wheel travel| +
/// slip_per_rotation^2 * |robot rotation|; the integrator uses wheel_base * (1 + wheel_base_error).
struct OdometryNoise {
  double left_scale_error = 0.0008;   ///< fractional scale error of the left wheel
  double right_scale_error = 0.0003;  ///< fractional scale error of the right wheel
  double wheel_base_error = 0.003;    ///< fractional error of the calibrated wheel base
  double slip_per_distance = 0.002;   ///< slip std per sqrt(metre) of wheel travel [m/sqrt(m)]
  double slip_per_rotation = 0.002;   ///< slip std per sqrt(radian) of rotation [m/sqrt(rad)]

  /// No error at all: odometry equals ground truth.
  static OdometryNoise none() { return {0.0, 0.0, 0.0, 0.0, 0.0}; }
  /// Every error times `k`: the simulators' `odometry_noise` scales this preset.
  OdometryNoise scaled(double k) const;
};

/// Integrates noisy wheel encoder readings into an odometry pose, as a robot's base does.
class WheelOdometry {
 public:
  /// Starts at `start` (odometry frame = world frame at the first pose).
  WheelOdometry(const Eigen::Vector3d& start, double wheel_base, const OdometryNoise& noise,
                uint64_t seed);

  /// Consumes one true wheel increment pair [m]; returns the measured (noisy) pair.
  Eigen::Vector2d update(double dl, double dr);

  /// The integrated odometry pose.
  const Eigen::Vector3d& pose() const { return pose_; }

 private:
  Eigen::Vector3d pose_;
  double wheel_base_;
  OdometryNoise noise_;
  Rng rng_;
};

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
