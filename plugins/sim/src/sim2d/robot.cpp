#include "sim2d/robot.h"

#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim2d {

double wrapAngle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

Eigen::Vector3d driveArc(const Eigen::Vector3d& pose, double dl, double dr, double wheel_base) {
  const double ds = 0.5 * (dl + dr);
  const double dth = (dr - dl) / wheel_base;
  const double th = pose.z();
  // Chord of the arc: length ds * sin(h)/h along the mid heading; stable for tiny rotations
  // where ds/dth * (sin(th+dth) - sin(th)) would cancel catastrophically.
  const double h = 0.5 * dth;
  const double sinc = std::abs(h) < 1e-4 ? 1.0 - h * h / 6.0 : std::sin(h) / h;
  Eigen::Vector3d out = pose;
  out.x() += ds * sinc * std::cos(th + h);
  out.y() += ds * sinc * std::sin(th + h);
  out.z() = wrapAngle(th + dth);
  return out;
}

PurePursuit::PurePursuit(std::vector<Eigen::Vector2d> path, const DriveLimits& limits)
    : path_(std::move(path)), limits_(limits) {
  if (path_.size() < 2)
    throw InputError("sim2d pure pursuit: expected a path of at least two points");
  arc_.assign(path_.size(), 0.0);
  for (size_t i = 1; i < path_.size(); ++i)
    arc_[i] = arc_[i - 1] + (path_[i] - path_[i - 1]).norm();
}

Eigen::Vector2d PurePursuit::pointAt(double s) const {
  if (s >= arc_.back()) return path_.back();
  const size_t i = std::upper_bound(arc_.begin(), arc_.end(), s) - arc_.begin() - 1;
  const double len = arc_[i + 1] - arc_[i];
  const double u = len > 0.0 ? (s - arc_[i]) / len : 0.0;
  return path_[i] + u * (path_[i + 1] - path_[i]);
}

Eigen::Vector2d PurePursuit::command(const Eigen::Vector3d& pose, double dt) {
  const Eigen::Vector2d p = pose.head<2>();
  // Closest point, searched forward only (within 1.5 lookaheads) so loops in the tour are not
  // short-cut where the path passes near itself.
  const double window = progress_ + 1.5 * limits_.lookahead;
  double best_d = (pointAt(progress_) - p).squaredNorm();
  for (size_t i = segment_; i + 1 < path_.size() && arc_[i] <= window; ++i) {
    const Eigen::Vector2d e = path_[i + 1] - path_[i];
    const double len2 = e.squaredNorm();
    double u = len2 > 0.0 ? std::clamp((p - path_[i]).dot(e) / len2, 0.0, 1.0) : 0.0;
    const double s = arc_[i] + u * std::sqrt(len2);
    if (s < progress_ || s > window) continue;
    const double d = (path_[i] + u * e - p).squaredNorm();
    if (d < best_d) {
      best_d = d;
      progress_ = s;
      segment_ = i;
    }
  }

  Eigen::Vector2d cmd(0.0, 0.0);
  if (arc_.back() - progress_ < 0.5 * limits_.lookahead) {
    finished_ = true;
  } else {
    const Eigen::Vector2d target = pointAt(progress_ + limits_.lookahead);
    const Eigen::Vector2d d = target - p;
    const double c = std::cos(pose.z()), s = std::sin(pose.z());
    const Eigen::Vector2d local(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
    const double alpha = std::atan2(local.y(), local.x());
    if (std::abs(alpha) > 1.0) turning_in_place_ = true;
    if (std::abs(alpha) < 0.3) turning_in_place_ = false;
    if (turning_in_place_) {
      cmd.y() = std::clamp(2.5 * alpha, -limits_.max_angular, limits_.max_angular);
    } else {
      const double dist = std::max(local.norm(), 1e-6);
      const double kappa = 2.0 * std::sin(alpha) / dist;
      double v = limits_.max_linear * std::max(0.25, 1.0 - std::abs(alpha));
      if (std::abs(kappa) * v > limits_.max_angular) v = limits_.max_angular / std::abs(kappa);
      cmd = Eigen::Vector2d(v, kappa * v);
    }
  }
  const double dv = limits_.max_linear_acc * dt, dw = limits_.max_angular_acc * dt;
  velocity_.x() += std::clamp(cmd.x() - velocity_.x(), -dv, dv);
  velocity_.y() += std::clamp(cmd.y() - velocity_.y(), -dw, dw);
  return velocity_;
}

OdometryNoise OdometryNoise::scaled(double k) const {
  return {left_scale_error * k, right_scale_error * k, wheel_base_error * k, slip_per_distance * k,
          slip_per_rotation * k};
}

WheelOdometry::WheelOdometry(const Eigen::Vector3d& start, double wheel_base,
                             const OdometryNoise& noise, uint64_t seed)
    : pose_(start), wheel_base_(wheel_base), noise_(noise), rng_(seed, 1) {}

Eigen::Vector2d WheelOdometry::update(double dl, double dr) {
  const double rotation = std::abs(dr - dl) / wheel_base_;
  const double rot_var = noise_.slip_per_rotation * noise_.slip_per_rotation * rotation;
  const double kd2 = noise_.slip_per_distance * noise_.slip_per_distance;
  const double ml =
      dl * (1.0 + noise_.left_scale_error) + rng_.gaussian(std::sqrt(kd2 * std::abs(dl) + rot_var));
  const double mr = dr * (1.0 + noise_.right_scale_error) +
                    rng_.gaussian(std::sqrt(kd2 * std::abs(dr) + rot_var));
  pose_ = driveArc(pose_, ml, mr, wheel_base_ * (1.0 + noise_.wheel_base_error));
  return Eigen::Vector2d(ml, mr);
}

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
