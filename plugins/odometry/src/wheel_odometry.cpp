#include "wheel_odometry.h"

#include <spdlog/spdlog.h>

#include "plugslam/errors.h"

namespace plugslam {
namespace odometry {

void WheelOdometry::configure() {
  if (input.name().empty()) throw ParamError("input", "must name the raw odometry entry");
}

std::optional<Eigen::Isometry2d> WheelOdometry::predict(const Frame& frame) {
  const Odometry2D* odom = input.find(frame);
  if (!odom) {
    // A log or bag without odometry runs on the other cues alone (the tracker predicts constant
    // velocity): said once, when it is clear the readings are not just late.
    if (!seen_ && ++frames_without_ == kSayLaserOnlyAfter)
      spdlog::warn("{}: no odometry '{}' in the first {} frames: tracking without odometry (the "
                   "tracker predicts constant velocity)",
                   name(), input.name(), kSayLaserOnlyAfter);
    return std::nullopt;
  }
  seen_ = true;
  std::optional<Eigen::Isometry2d> delta;
  if (last_) delta = last_->inverse() * odom->pose;
  last_ = odom->pose;
  return delta;
}

void WheelOdometry::reset() { last_.reset(); }

}  // namespace odometry
}  // namespace plugslam
