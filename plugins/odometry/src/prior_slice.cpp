#include "prior_slice.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "odometry_frame.h"
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

namespace {

// (t, q.vec) of a pose, q with w >= 0 (g2o's SE3 error).
Eigen::Matrix<double, 6, 1> translationAndQuaternionVec(const Eigen::Isometry3d& x,
                                                        Eigen::Quaterniond* q_out = nullptr) {
  const Eigen::Quaterniond q = quaternionOf(x);
  if (q_out) *q_out = q;
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = x.translation();
  e.tail<3>() = q.vec();
  return e;
}

}  // namespace

MotionPrior3D::Error MotionPrior3D::error(const Eigen::Isometry3d& t) const {
  return translationAndQuaternionVec(mount.inverse() * prior.inverse() * t * mount);
}

void MotionPrior3D::errorAndJacobian(const Eigen::Isometry3d& t, Error& e, Jacobian& j) const {
  const Eigen::Isometry3d eb = mount.inverse() * prior.inverse() * t * mount;
  Eigen::Quaterniond q;
  e = translationAndQuaternionVec(eb, &q);
  // T * se3(v, w) moves E_b to E_b * K with K = B se3(v, w) B^-1, B = mount^-1 (the robot in
  // the base frame); to first order K = (R_B v + t_B x R_B w, rotation R_B w). Then E_b * K has
  // translation t_E + R_E K_t and rotation R_E exp(R_B w), whose q.vec moves by
  // 0.5 (q.w I + [q.vec]x) R_B w.
  const Eigen::Matrix3d rb = mount.linear().transpose();
  const Eigen::Vector3d tb = -(rb * mount.translation());
  j.setZero();
  j.block<3, 3>(0, 0) = eb.linear() * rb;
  j.block<3, 3>(0, 3) = eb.linear() * skew(tb) * rb;
  j.block<3, 3>(3, 3) = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + skew(q.vec())) * rb;
}

template <class S>
void OdometryPriorSlice<S>::configure() {
  if (input.name().empty()) throw ParamError("input", "must name the raw odometry entry");
}

template <class S>
bool OdometryPriorSlice<S>::prepare(const AlignContext<S>& context) {
  // Called only when the frame has the reading; a frame without keeps the last reading, so the
  // next delta spans the gap.
  const Odometry2D* odom = input.get();
  // Frames are told apart by sequence number and stamp, so callers that leave seq at 0 still
  // get one delta per frame.
  const bool new_frame = !bound_ || bound_->first != context.seq || bound_->second != context.stamp;
  if (new_frame) {
    before_bound_ = last_;
    bound_ = std::make_pair(context.seq, context.stamp);
  }
  last_ = odom->pose;
  // The first reading the slice sees adds no prior, even when the motion model has a delta for
  // it (the tracker's first aligned frame): taking that one moved a sparse outdoor log's relations
  // from 0.073 to 0.60 m (chaotically; the other logs by the last digits), so it waits.
  if (!before_bound_) return false;
  // The tracker's motion model read this same odometry: its delta (the same product of the same
  // readings) is the one to use, not computed again. Otherwise (no motion model, another entry,
  // a validator's alignment) the slice's own readings give it.
  const bool model_delta = context.motion && context.motion_entry == input.name();
  const Eigen::Isometry2d delta =
      model_delta ? planar(*context.motion) : before_bound_->inverse() * odom->pose;
  prior_ = context.previous * lift(delta);
  const double d = delta.translation().norm();
  const double a = std::abs(angleOf(delta.linear()));
  const double st = std::max(min_sigma_translation(), sigma_translation_per_m() * d);
  const double sr =
      std::max(min_sigma_rotation(), sigma_rotation_per_rad() * a + sigma_rotation_per_m() * d);
  information_ = informationFor(st, sr);
  return true;
}

template <class S>
typename S::Vector OdometryPriorSlice<S>::error(const Pose& t, typename S::Matrix* jacobian) const {
  const Factor f = factor(prior_);
  if (!jacobian) return f.error(t);
  typename S::Vector e;
  f.errorAndJacobian(t, e, *jacobian);
  return e;
}

template <class S>
void OdometryPriorSlice<S>::linearize(const Pose& t, NormalEquations<S>& eq) const {
  // Least squares (no kernel); the one factor always counts as an inlier.
  eq.add(factor(prior_), t, information_);
}

template class OdometryPriorSlice<Space2D>;
template class OdometryPriorSlice<Space3D>;

Eigen::Matrix3d PriorSlice::informationFor(double st, double sr) const {
  return Eigen::Vector3d(1 / (st * st), 1 / (st * st), 1 / (sr * sr)).asDiagonal();
}

void PriorSlice3D::configure() {
  OdometryPriorSlice<Space3D>::configure();
  mount_ = mountFromParam(mount(), "mount");
}

Eigen::Isometry3d PriorSlice3D::lift(const Eigen::Isometry2d& delta) const {
  return liftToRobot(delta, mount_);
}

Eigen::Isometry2d PriorSlice3D::planar(const Eigen::Isometry3d& motion) const {
  return planarInBase(motion, mount_);
}

Eigen::Matrix<double, 6, 6> PriorSlice3D::informationFor(double st, double sr) const {
  // The rotation error is q.vec, half the angle to first order: its information is 4 / sigma^2.
  const double sz = out_of_plane_sigma_translation(), sa = out_of_plane_sigma_rotation();
  Eigen::Matrix<double, 6, 1> w;
  w << 1 / (st * st), 1 / (st * st), 1 / (sz * sz), 4 / (sa * sa), 4 / (sa * sa), 4 / (sr * sr);
  return w.asDiagonal();
}

}  // namespace odometry
}  // namespace plugslam
