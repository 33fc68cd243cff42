#include "sim3d/odometry.h"

#include <cmath>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "plugslam/pose_space.h"

namespace plugslam {
namespace sim {
namespace sim3d {

Eigen::Isometry3d cameraInVehicle(double height) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear().col(0) = -Eigen::Vector3d::UnitY();  // image x: right of the vehicle
  m.linear().col(1) = -Eigen::Vector3d::UnitZ();  // image y: down
  m.linear().col(2) = Eigen::Vector3d::UnitX();   // optical axis: forward
  m.translation() = Eigen::Vector3d(0.0, 0.0, height);
  return m;
}

namespace {

// The arc a differential drive follows for wheel travels (dl, dr), from the origin.
Eigen::Isometry2d arc(double dl, double dr, double wheel_base) {
  return se2(sim2d::driveArc(Eigen::Vector3d::Zero(), dl, dr, wheel_base));
}

}  // namespace

std::vector<Eigen::Isometry2d> wheelOdometry(const Trajectory& camera,
                                             const WheelOdometryOptions& o) {
  if (!(o.wheel_base > 0.0)) throw InputError("sim3d odometry: wheel_base must be > 0");
  const sim2d::OdometryNoise& n = o.noise;
  if (!(std::abs(n.left_scale_error) < 0.5 && std::abs(n.right_scale_error) < 0.5 &&
        std::abs(n.wheel_base_error) < 0.5))
    throw InputError("sim3d odometry: scale errors must be in (-0.5, 0.5)");
  if (!(n.slip_per_distance >= 0.0 && n.slip_per_rotation >= 0.0))
    throw InputError("sim3d odometry: slip must be >= 0");
  std::vector<Eigen::Isometry2d> out;
  if (camera.empty()) return out;
  out.reserve(camera.size());
  const Eigen::Isometry3d to_base = cameraInVehicle(o.camera_height).inverse();
  // The encoders: sim2d's noise on each wheel's travel; its own integrated pose is not used.
  sim2d::WheelOdometry wheels(Eigen::Vector3d::Zero(), o.wheel_base, n, o.seed);
  const double measured_base = o.wheel_base * (1.0 + n.wheel_base_error);
  Eigen::Isometry3d base = camera[0].pose * to_base;
  out.push_back(Space2D::from3D(base));
  for (size_t k = 1; k < camera.size(); ++k) {
    const Eigen::Isometry3d next = camera[k].pose * to_base;
    const Eigen::Isometry2d step = Space2D::from3D(base.inverse() * next);
    base = next;
    // The wheel travels of the arc through the step's end (its chord is ds * sinc(dtheta / 2));
    // backwards when the step is.
    const double dtheta = angleOf(step.linear());
    const double h = 0.5 * dtheta;
    const double sinc = std::abs(h) < 1e-4 ? 1.0 - h * h / 6.0 : std::sin(h) / h;
    const double chord = step.translation().norm();
    const double ds = (step.translation().x() < 0.0 ? -chord : chord) / sinc;
    const double dl = ds - 0.5 * dtheta * o.wheel_base, dr = ds + 0.5 * dtheta * o.wheel_base;
    const Eigen::Vector2d measured = wheels.update(dl, dr);
    // The encoders' error as a motion in the vehicle frame, applied to the true step rather than
    // replacing it: the sideways part of a step (a camera ahead of the rear axle in a turn, the
    // trajectory file's own jitter) is kept, so zero noise gives the ground truth exactly.
    const Eigen::Isometry2d error =
        arc(dl, dr, o.wheel_base).inverse() * arc(measured.x(), measured.y(), measured_base);
    out.push_back(Space2D::normalized(out.back() * step * error));
  }
  return out;
}

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
