#include "prior_slice.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace odometry {

MotionPrior2D::Error MotionPrior2D::error(const Eigen::Isometry2d& t) const {
  return toVector(prior.inverse() * t);
}

void MotionPrior2D::errorAndJacobian(const Eigen::Isometry2d& t, Error& e, Jacobian& j) const {
  const Eigen::Isometry2d d = prior.inverse() * t;
  // E * se2(dx): translation E.t + R(E) dx_xy, angle theta(E) + dtheta.
  j.setZero();
  j.topLeftCorner<2, 2>() = d.linear();
  j(2, 2) = 1.0;
  e = toVector(d);
}

void PriorSlice::configure() {
  if (input.name().empty()) throw ParamError("input", "must name the raw odometry entry");
}

bool PriorSlice::prepare(const AlignContext<Space2D>& context) {
  // Called only when the frame has the reading; a frame without keeps the last reading, so the
  // next delta spans the gap.
  const Odometry2D* odom = input.get();
  // Frames are told apart by sequence number and stamp, so callers that leave seq at 0 still
  // get one delta per frame.
  const bool new_frame =
      !bound_ || bound_->first != context.seq || bound_->second != context.stamp;
  if (new_frame) {
    before_bound_ = last_;
    bound_ = std::make_pair(context.seq, context.stamp);
    observeDisagreement(context);
  }
  last_ = odom->pose;
  // The first reading the slice sees adds no prior, even when the motion model has a delta for
  // it (the tracker's first aligned frame): taking that one moved freiburg-campus's relations
  // from 0.073 to 0.60 m (chaotically; the other logs by the last digits), so it waits.
  if (!before_bound_) return false;
  // The tracker's motion model read this same odometry: its delta (the same product of the same
  // readings) is the one to use, not computed again. Otherwise (no motion model, another entry,
  // a validator's alignment) the slice's own readings give it.
  const Eigen::Isometry2d delta = context.motion && context.motion_entry == input.name()
                                      ? *context.motion
                                      : before_bound_->inverse() * odom->pose;
  prior_ = context.previous * delta;
  const double d = delta.translation().norm();
  const double a = std::abs(angleOf(delta.linear()));
  const double model_st = std::max(min_sigma_translation(), sigma_translation_per_m() * d);
  const double model_sr =
      std::max(min_sigma_rotation(), sigma_rotation_per_rad() * a + sigma_rotation_per_m() * d);
  if (new_frame) last_sigmas_ = Eigen::Vector2d(model_st, model_sr);
  const double st = scale_.x() * model_st, sr = scale_.y() * model_sr;
  information_ = Eigen::Vector3d(1 / (st * st), 1 / (st * st), 1 / (sr * sr)).asDiagonal();
  return true;
}

void PriorSlice::observeDisagreement(const AlignContext<Space2D>& context) {
  const int n = disagreement_frames();
  if (n == 0) {
    scale_.setOnes();
    return;
  }
  // The previous frame's residual, in units of the sigmas its prior had; a running mean of the
  // squares over about n frames (an exponential window), so one slip weighs for a while and
  // then fades. The scale is its root, never below 1: odometry as good as its model keeps it.
  if (context.motion_residual && last_sigmas_) {
    const Eigen::Vector3d e = toVector(*context.motion_residual);
    const Eigen::Vector2d z(e.head<2>().norm() / last_sigmas_->x(),
                            std::abs(e.z()) / last_sigmas_->y());
    const double alpha = 1.0 / n;
    mean_square_ = (1 - alpha) * mean_square_ + alpha * z.cwiseProduct(z);
  }
  last_sigmas_.reset();
  scale_ = mean_square_.cwiseSqrt().cwiseMax(1.0);
}

Eigen::Vector3d PriorSlice::error(const Eigen::Isometry2d& t, Eigen::Matrix3d* jacobian) const {
  const MotionPrior2D factor{prior_};
  if (!jacobian) return factor.error(t);
  Eigen::Vector3d e;
  factor.errorAndJacobian(t, e, *jacobian);
  return e;
}

void PriorSlice::linearize(const Eigen::Isometry2d& t, NormalEquations<Space2D>& eq) const {
  // Least squares (no kernel); the one factor always counts as an inlier.
  eq.add(MotionPrior2D{prior_}, t, information_);
}

}  // namespace odometry
}  // namespace plugslam
