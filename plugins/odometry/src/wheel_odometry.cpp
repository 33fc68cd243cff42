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
  calibration_.setMemory(calibration_distance());
}

template <class S>
std::optional<typename S::Pose> WheelOdometryModel<S>::predict(const Frame& frame) {
  const Odometry2D* odom = input.find(frame);
  extrapolated_.reset();
  raw_delta_.reset();
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
  // A reading new since the previous frame measured part of this frame's step, and the
  // tracker's gate allows for the rest (its time says little more: CARMEN logs interleave
  // readings stamped before a laser but logged after it). The previous frame's reading again
  // measured none of the step: "no motion" is then a claim the wheels never made, and the
  // prediction goes on from where the previous frame's left off, by the time between them.
  double covered = 0;
  const bool again = previous_reading_ && odom->stamp == previous_reading_->stamp &&
                     odom->pose.isApprox(previous_reading_->pose, 0.0);
  if (again && previous_stamp_ && frame.stamp > *previous_stamp_)
    covered = std::min(max_extrapolation(), covered_ + (frame.stamp - *previous_stamp_));
  const std::optional<Eigen::Isometry2d> carried =
      covered > 0 ? extrapolation(*odom, covered) : std::nullopt;
  const Eigen::Isometry2d at = carried ? odom->pose * *carried : odom->pose;
  std::optional<Pose> delta;
  if (last_) {
    const Eigen::Isometry2d raw = last_->inverse() * at;
    delta = lift(calibration_.apply(raw));
    // Not measured in this delta: the guess it ends with, and the one the last delta ended with
    // (this delta starts from it, so that guess's error comes back here, the other way).
    double distance = 0, angle = 0;
    const auto add = [&](const std::optional<Eigen::Isometry2d>& guess) {
      if (!guess) return;
      distance += guess->translation().norm();
      angle += std::abs(angleOf(guess->linear()));
    };
    add(last_carried_);
    add(carried);
    // The last frame's reading was older than that frame, and this delta starts from it, so
    // the motion after it is in this delta too, though that frame's estimate took it up where
    // its alignment held (where it failed, this delta is right): either way up to that much is
    // not this frame's step.
    add(last_unseen_);
    // A new reading older than its frame measured the step up to its stamp only. The rest is
    // not carried into the prediction (the stamps of CARMEN logs are too loose for that: see
    // above), but it is said, bounded by the recent velocity over the reading's age, so the gate
    // and the prior widen by it and the aligner's seeder may check the frame.
    std::optional<Eigen::Isometry2d> unseen;
    if (!again && frame.stamp > odom->stamp)
      unseen = extrapolation(*odom, std::min(max_extrapolation(), frame.stamp - odom->stamp));
    add(unseen);
    if (last_carried_ || carried || unseen || last_unseen_)
      extrapolated_ = lift(se2(distance, 0, angle));
    else
      raw_delta_ = raw;
    last_unseen_ = unseen;
  } else {
    last_unseen_.reset();
  }
  last_ = at;
  last_carried_ = carried;
  previous_reading_ = *odom;
  previous_stamp_ = frame.stamp;
  covered_ = carried ? covered : 0.0;
  return delta;
}

template <class S>
std::optional<Eigen::Isometry2d> WheelOdometryModel<S>::extrapolation(const Odometry2D& odom,
                                                                       double time) const {
  if (history_.size() < 2 || history_.back().stamp != odom.stamp) return std::nullopt;
  // The velocity over the newest span of readings at least as long as the time carried, so the
  // motion extrapolated is never more than the motion measured (with too short a history: all
  // of it).
  const Odometry2D* from = &history_.front();
  for (auto it = history_.rbegin() + 1; it != history_.rend(); ++it)
    if (odom.stamp - it->stamp >= time) {
      from = &*it;
      break;
    }
  const double span = odom.stamp - from->stamp;
  if (!(span > 0)) return std::nullopt;
  const double ratio = std::min(1.0, time / span);
  return se2(ratio * toVector(from->pose.inverse() * odom.pose));
}

template <class S>
void WheelOdometryModel<S>::solved(const Pose& motion) {
  if (!raw_delta_) return;
  const double before = calibration_.distance();
  if (calibration_.observe(*raw_delta_, planar(motion)) &&
      std::floor(calibration_.distance() / kSayCalibrationEvery) >
          std::floor(before / kSayCalibrationEvery))
    spdlog::debug("{}: odometry calibration after {:.0f} m: scale {:.4f}, rotation scale {:.4f}, "
                  "heading drift {:.4f} rad/m",
                  this->name(), calibration_.distance(), calibration_.scale(),
                  calibration_.rotationScale(), calibration_.headingPerMetre());
  raw_delta_.reset();
}

template <class S>
void WheelOdometryModel<S>::reset() {
  last_.reset();
  history_.clear();
  extrapolated_.reset();
  raw_delta_.reset();  // the calibration stays: it is the wheels', not the run's
  last_carried_.reset();
  last_unseen_.reset();
  previous_reading_.reset();
  previous_stamp_.reset();
  covered_ = 0;
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

Eigen::Isometry2d WheelOdometry3D::planar(const Eigen::Isometry3d& motion) const {
  return planarInBase(motion, mount_);
}

}  // namespace odometry
}  // namespace plugslam
