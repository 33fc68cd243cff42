#include "wheel_odometry.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "odometry_frame.h"
#include "plugslam/errors.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace odometry {

template <class S>
void WheelOdometryModel<S>::configure() {
  if (input.name().empty()) throw ParamError("input", "must name the raw odometry entry");
}

template <class S>
std::optional<MotionEstimate<S>> WheelOdometryModel<S>::predict(const Frame& frame) {
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
  if (history_.empty() || odom->stamp > history_.back().stamp) {
    history_.push_back(*odom);
    if (history_.size() > kHistory) history_.pop_front();
  } else if (odom->stamp == history_.back().stamp) {
    history_.back() = *odom;
  } else {
    history_.assign(1, *odom);  // the clock went back (a replay, a new log): start over
  }
  // The reading saw the motion up to its own stamp: what happened between it and the frame,
  // here and at the previous frame (this delta starts from that frame's reading), it did not.
  const double unseen = std::abs(frame.stamp - odom->stamp);
  std::optional<MotionEstimate<S>> out;
  if (last_) {
    const Eigen::Isometry2d delta = last_->inverse() * odom->pose;
    const double d = delta.translation().norm();
    const double a = std::abs(angleOf(delta.linear()));
    const auto [speed, turn_rate] = recentSpeed();
    const double gap = unseen + last_unseen_;
    const double st = std::max(min_sigma_translation(),
                               sigma_translation_per_m() * d + sigma_translation_per_rad() * a) +
                      speed * gap;
    const double sr =
        std::max(min_sigma_rotation(), sigma_rotation_per_m() * d + sigma_rotation_per_rad() * a) +
        turn_rate * gap;
    out = MotionEstimate<S>::isotropic(lift(delta), st, sr);
  }
  last_ = odom->pose;
  last_unseen_ = unseen;
  return out;
}

template <class S>
std::pair<double, double> WheelOdometryModel<S>::recentSpeed() const {
  if (history_.size() < 2) return {0.0, 0.0};
  // Path length and turned angle summed reading to reading, so a turn and its return do not
  // cancel out.
  double distance = 0, angle = 0;
  for (size_t i = 1; i < history_.size(); ++i) {
    const Eigen::Isometry2d step = history_[i - 1].pose.inverse() * history_[i].pose;
    distance += step.translation().norm();
    angle += std::abs(angleOf(step.linear()));
  }
  const double span = history_.back().stamp - history_.front().stamp;
  if (!(span > 0)) return {0.0, 0.0};
  return {distance / span, angle / span};
}

template <class S>
void WheelOdometryModel<S>::reset() {
  last_.reset();
  last_unseen_ = 0;
  history_.clear();
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
