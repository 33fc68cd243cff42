#pragma once
// Wheel odometry's systematic error, learnt online from the motions the other cues solve.
#include <Eigen/Geometry>

namespace plugslam {
namespace odometry {

/// A differential drive's three calibration errors, learnt from pairs (odometry step, solved
/// step) in the odometry's base frame: the translation scale (the wheels' mean radius against
/// its nominal value), the rotation scale (the wheel base) and the heading drift per metre
/// driven (the two radii differ). Each is a weighted least-squares fit over an exponential
/// window of `memory` metres driven, held at the nominal value until a metre of travel (or a
/// radian of turning) says otherwise.
class OdometryCalibration {
 public:
  /// `memory` in metres driven; 0 leaves the odometry as it is.
  explicit OdometryCalibration(double memory = 0) : memory_(memory) {}
  void setMemory(double memory) { memory_ = memory; }
  bool enabled() const { return memory_ > 0; }
  /// The odometry step `raw` corrected by the calibration learnt so far.
  Eigen::Isometry2d apply(const Eigen::Isometry2d& raw) const;
  /// Learns from one step: `raw` the odometry's, `solved` the motion the tracker solved for it.
  /// A step that disagrees with the calibrated odometry by more than any calibration error
  /// explains (a slip, a kidnap, a wrong alignment) teaches nothing; returns whether it was used.
  bool observe(const Eigen::Isometry2d& raw, const Eigen::Isometry2d& solved);
  double scale() const { return scale_; }                     ///< translation scale
  double rotationScale() const { return rotation_scale_; }    ///< rotation scale
  double headingPerMetre() const { return heading_per_m_; }   ///< rad per metre forward
  double distance() const { return distance_; }               ///< metres learnt from, in all

 private:
  void solve();
  double memory_;
  // Decayed sums of the weighted fits: translation (solved . unit(raw), |raw|), rotation
  // (theta_solved = r theta_raw + b forward, normal equations).
  double t_solved_ = 0, t_raw_ = 0;
  double r_aa_ = 0, r_ab_ = 0, r_bb_ = 0, r_ya_ = 0, r_yb_ = 0;
  double scale_ = 1, rotation_scale_ = 1, heading_per_m_ = 0;
  double distance_ = 0;
};

}  // namespace odometry
}  // namespace plugslam
