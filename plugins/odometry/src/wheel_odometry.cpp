#include "wheel_odometry.h"

#include <spdlog/spdlog.h>

#include "odometry_frame.h"
#include "plugslam/errors.h"

namespace plugslam {
namespace odometry {

template <class S>
void WheelOdometryModel<S>::configure() {
  if (input.name().empty()) throw ParamError("input", "must name the raw odometry entry");
}

template <class S>
std::optional<typename S::Pose> WheelOdometryModel<S>::predict(const Frame& frame) {
  const Odometry2D* odom = input.find(frame);
  if (!odom) {
    // A log or bag without odometry runs on the other cues alone (the tracker predicts constant
    // velocity): said once, when it is clear the readings are not just late.
    if (!seen_ && ++frames_without_ == kSayLaserOnlyAfter)
      spdlog::warn(
          "{}: no odometry '{}' in the first {} frames: tracking without odometry (the "
          "tracker predicts constant velocity)",
          this->name(), input.name(), kSayLaserOnlyAfter);
    return std::nullopt;
  }
  seen_ = true;
  std::optional<Pose> delta;
  if (last_) delta = lift(last_->inverse() * odom->pose);
  last_ = odom->pose;
  return delta;
}

template <class S>
void WheelOdometryModel<S>::reset() {
  last_.reset();
}

template class WheelOdometryModel<Space2D>;
template class WheelOdometryModel<Space3D>;

void WheelOdometry3D::configure() {
  WheelOdometryModel<Space3D>::configure();
  mount_ = mountFromParam(mount(), "mount");
}

Eigen::Isometry3d WheelOdometry3D::lift(const Eigen::Isometry2d& delta) const {
  return liftToRobot(delta, mount_);
}

}  // namespace odometry
}  // namespace plugslam
