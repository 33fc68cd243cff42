#include "prior_slice.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace odometry {

void PriorSlice::configure() {
  if (input().empty()) throw ParamError("input", "must name the raw odometry entry");
}

bool PriorSlice::bind(const Frame& frame, const PropertyContainer& scene,
                      const AlignContext<Space2D>& context) {
  const Odometry2D* odom = frame.raw.find<Odometry2D>(input());
  if (!odom) return false;  // keep the last reading: the next delta spans the gap
  // Frames are told apart by sequence number and stamp, so callers that leave seq at 0 still
  // get one delta per frame.
  if (!bound_ || bound_->first != frame.seq || bound_->second != frame.stamp) {
    before_bound_ = last_;
    bound_ = std::make_pair(frame.seq, frame.stamp);
  }
  last_ = odom->pose;
  if (!before_bound_) return false;  // the first reading has nothing to be relative to

  const Eigen::Isometry2d delta = before_bound_->inverse() * odom->pose;
  prior_ = context.previous * delta;
  const double d = delta.translation().norm();
  const double a = std::abs(angleOf(delta.linear()));
  const double st = std::max(min_sigma_translation(), sigma_translation_per_m() * d);
  const double sr =
      std::max(min_sigma_rotation(), sigma_rotation_per_rad() * a + sigma_rotation_per_m() * d);
  information_ = Eigen::Vector3d(1 / (st * st), 1 / (st * st), 1 / (sr * sr)).asDiagonal();
  return true;
}

Eigen::Vector3d PriorSlice::error(const Eigen::Isometry2d& t, Eigen::Matrix3d* jacobian) const {
  const Eigen::Isometry2d e = prior_.inverse() * t;
  if (jacobian) {
    // E * se2(dx): translation E.t + R(E) dx_xy, angle theta(E) + dtheta.
    jacobian->setZero();
    jacobian->topLeftCorner<2, 2>() = e.linear();
    (*jacobian)(2, 2) = 1.0;
  }
  return toVector(e);
}

void PriorSlice::linearize(const Eigen::Isometry2d& t, NormalEquations<Space2D>& eq) const {
  Eigen::Matrix3d j;
  const Eigen::Vector3d e = error(t, &j);
  const Eigen::Matrix3d jt_omega = j.transpose() * information_;
  eq.H += jt_omega * j;
  eq.b += jt_omega * e;
  eq.chi2 += e.dot(information_ * e);
  eq.inliers += 1;
  eq.factors += 1;
}

}  // namespace odometry
}  // namespace plugslam
