#pragma once
// Camera trajectories for the 3D simulator: generated loops through the built-in worlds, or
// real trajectories (KITTI 00, TUM fr1_xyz) moved into the world and resampled to the camera
// rate. Poses are camera optical frames (x right, y down, z forward) in the world (z up).
#include <Eigen/Geometry>

#include "plugslam/trajectory.h"
#include "sim3d/world.h"

namespace plugslam {
namespace sim {
namespace sim3d {

/// KITTI's camera above the road: the street drive's camera height [m].
inline constexpr double kCameraHeight = 1.65;

/// A camera at `position` looking along `forward` (any length, not vertical), image x axis
/// horizontal.
Eigen::Isometry3d lookAlong(const Eigen::Vector3d& position, const Eigen::Vector3d& forward);

/// A hand-held-like loop in the living room: an ellipse around the room's middle at about
/// 1.4 m, looking outwards at the walls and furniture, one loop per `duration` seconds.
Trajectory livingRoomLoop(double duration, double rate);

/// A camera driving along `path` at `speed` m/s, `height` metres above the road, sampled at
/// `rate` Hz until the path ends (heading from the path's tangent over a few metres).
Trajectory driveAlong(const RoadPath& path, double height, double speed, double rate,
                      double acceleration = 0.0);

/// The living room's anchor for loaded trajectories: (3.2, 2.6, 1.5) looking at the south wall.
Eigen::Isometry3d livingRoomStart();
/// The street's anchor for loaded trajectories: the origin, 1.65 m up, looking along +x.
Eigen::Isometry3d streetStart();

/// Turns each pose about the world's vertical through the camera by amplitude * sin(2 pi t /
/// period) [rad, s]: a camera panned from side to side as it moves along the trajectory.
Trajectory panTrajectory(const Trajectory& trajectory, double amplitude, double period);

/// Moves a trajectory rigidly so its first pose becomes `start` (relative motion unchanged).
Trajectory anchorTrajectory(const Trajectory& trajectory, const Eigen::Isometry3d& start);

/// Poses at start + k / rate, interpolated (linear position, slerp rotation) between the
/// trajectory's poses; throws InputError if rate <= 0 or fewer than two poses.
Trajectory resampleTrajectory(const Trajectory& trajectory, double rate);

/// The road surface under a driving camera (height metres below it, world z up), one point
/// every `step` metres of travel.
RoadPath roadUnder(const Trajectory& trajectory, double height, double step);

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
