#include "wheel_odometry.h"

#include "plugslam/errors.h"

namespace plugslam {
namespace odometry {

void WheelOdometry::configure() {
  if (input.name().empty()) throw ParamError("input", "must name the raw odometry entry");
}

std::optional<Eigen::Isometry2d> WheelOdometry::predict(const Frame& frame) {
  const Odometry2D* odom = input.find(frame);
  if (!odom) return std::nullopt;
  std::optional<Eigen::Isometry2d> delta;
  if (last_) delta = last_->inverse() * odom->pose;
  last_ = odom->pose;
  return delta;
}

void WheelOdometry::reset() { last_.reset(); }

}  // namespace odometry
}  // namespace plugslam
