#include "odometry_calibration.h"

#include <algorithm>
#include <cmath>

#include "plugslam/geometry.h"

namespace plugslam {
namespace odometry {

namespace {
// No wheel is off its nominal radius or base by 30 %, nor drifts 0.2 rad per metre: a fit beyond
// that is the cues' error, not the wheels'; so is a step that far from the calibrated odometry.
constexpr double kMaxScaleError = 0.3;
constexpr double kMaxHeadingPerMetre = 0.2;
// A step within this of the calibrated odometry may still teach (an alignment's own noise).
constexpr double kTranslationNoise = 0.05, kRotationNoise = 0.05;
// Evidence held at the nominal calibration: a metre driven, a radian turned.
constexpr double kPriorMetres = 1.0, kPriorRadians = 1.0;
}  // namespace

Eigen::Isometry2d OdometryCalibration::apply(const Eigen::Isometry2d& raw) const {
  if (!enabled()) return raw;
  const Eigen::Vector3d v = toVector(raw);
  return se2(scale_ * v.x(), scale_ * v.y(), rotation_scale_ * v.z() + heading_per_m_ * v.x());
}

bool OdometryCalibration::observe(const Eigen::Isometry2d& raw, const Eigen::Isometry2d& solved) {
  if (!enabled()) return false;
  const Eigen::Vector3d r = toVector(raw), s = toVector(solved), c = toVector(apply(raw));
  const double d = r.head<2>().norm(), a = std::abs(r.z());
  if (d + a < 1e-6) return false;  // standing still says nothing of the wheels
  const bool translation_ok =
      (s.head<2>() - c.head<2>()).norm() <= kMaxScaleError * d + kTranslationNoise;
  const bool rotation_ok = std::abs(normalizeAngle(s.z() - c.z())) <=
                           kMaxScaleError * a + kMaxHeadingPerMetre * d + kRotationNoise;
  if (!translation_ok || !rotation_ok) return false;
  // Older steps fade with the distance driven since (a robot's load and tyres change over a
  // run, not between two steps).
  const double keep = std::exp(-d / memory_);
  t_solved_ *= keep, t_raw_ *= keep;
  r_aa_ *= keep, r_ab_ *= keep, r_bb_ *= keep, r_ya_ *= keep, r_yb_ *= keep;
  if (d > 1e-6) {
    // Weighted by 1/|raw|: each metre driven counts once, whatever the step size.
    t_solved_ += s.head<2>().dot(r.head<2>()) / d;
    t_raw_ += d;
  }
  // The same for rotation: a radian turned or a metre driven counts once.
  const double w = 1.0 / (a + d);
  const double dtheta = r.z() + normalizeAngle(s.z() - r.z());  // unwrapped
  r_aa_ += w * r.z() * r.z();
  r_ab_ += w * r.z() * r.x();
  r_bb_ += w * r.x() * r.x();
  r_ya_ += w * dtheta * r.z();
  r_yb_ += w * dtheta * r.x();
  distance_ += d;
  solve();
  return true;
}

void OdometryCalibration::solve() {
  scale_ = std::clamp((t_solved_ + kPriorMetres) / (t_raw_ + kPriorMetres), 1 - kMaxScaleError,
                      1 + kMaxScaleError);
  // Normal equations of theta_solved = r theta_raw + b forward, with the prior r = 1, b = 0.
  Eigen::Matrix2d A;
  A << r_aa_ + kPriorRadians, r_ab_, r_ab_, r_bb_ + kPriorMetres;
  const Eigen::Vector2d x = A.ldlt().solve(Eigen::Vector2d(r_ya_ + kPriorRadians, r_yb_));
  rotation_scale_ = std::clamp(x.x(), 1 - kMaxScaleError, 1 + kMaxScaleError);
  heading_per_m_ = std::clamp(x.y(), -kMaxHeadingPerMetre, kMaxHeadingPerMetre);
}

}  // namespace odometry
}  // namespace plugslam
