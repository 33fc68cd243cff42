#pragma once
// odometry.PriorSlice: a factor on the aligner's relative pose from the wheel odometry, so laser
// (or any other cue) and odometry fuse in one solve.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "plugslam/aligner_slice.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace odometry {

/// The prior's factor: e = (x, y, theta) of Z^-1 T, whose Jacobian w.r.t. the right perturbation
/// of T (Space2D::boxplus, T * se2(dx)) is exactly blockdiag(R(E), 1) with E = Z^-1 T.
struct MotionPrior2D {
  using Space = Space2D;                         ///< the pose space of T
  static constexpr int kErrorDim = 3;            ///< dimension of e
  using Error = Eigen::Matrix<double, 3, 1>;     ///< e
  using Jacobian = Eigen::Matrix<double, 3, 3>;  ///< de / dx
  Eigen::Isometry2d prior;                       ///< Z (scene <- robot)
  /// The error at T.
  Error error(const Eigen::Isometry2d& t) const;
  /// The error and its Jacobian at T.
  void errorAndJacobian(const Eigen::Isometry2d& t, Error& e, Jacobian& j) const;
};

/// Adds e = log(Z^-1 * T) with Z = previous * (odometry delta since the previous frame) and an
/// information matrix from a motion-proportional noise model:
///   sigma_t = max(min_sigma_translation, sigma_translation_per_m * |d|)
///   sigma_r = max(min_sigma_rotation,
///                 sigma_rotation_per_rad * |dtheta| + sigma_rotation_per_m * |d|)
/// log here is (x, y, theta) of the pose, matching Space2D::boxplus (T * se2(dx)), so the
/// Jacobian is exactly blockdiag(R(E), 1) with E = Z^-1 * T. The delta is the tracker's motion
/// model's (AlignContext::motion) when the model read the same entry, else the slice's own.
class PriorSlice : public AlignerSlice<Space2D> {
 public:
  Input<Odometry2D> input{this, Container::raw, "input", "odom", "wheel odometry to read"};
  Param<double> sigma_translation_per_m{
      this,         "sigma_translation_per_m", 0.05, "m/m", "translation noise per metre travelled",
      Range{0, 100}};
  Param<double> sigma_rotation_per_rad{
      this,      "sigma_rotation_per_rad",           0.05,
      "rad/rad", "rotation noise per radian turned", Range{0, 100}};
  Param<double> sigma_rotation_per_m{
      this,         "sigma_rotation_per_m", 0.02, "rad/m", "rotation noise per metre travelled",
      Range{0, 100}};
  Param<double> min_sigma_translation{this, "min_sigma_translation",   0.01,
                                      "m",  "translation noise floor", Range{1e-9, 1e6}};
  Param<double> min_sigma_rotation{this,  "min_sigma_rotation",   0.005,
                                   "rad", "rotation noise floor", Range{1e-9, 1e6}};
  // Odometry that disagrees with the other cues (wheel slip, a wrong scale, a kidnap) must not
  // hold the solve: the prior's sigmas grow with the disagreement observed on the last frames,
  // relative to the noise model above (never below it). Off by default: on the shared CARMEN
  // logs it did not yet pay (freiburg-campus's relations went from 0.07 to 0.65 m with it on).
  Param<int> disagreement_frames{
      this, "disagreement_frames", 0, "frames",
      "memory of the observed disagreement (the solved motion against the odometry, in units of "
      "the model's sigmas) that scales the sigmas up when above 1; 0: the model's sigmas only",
      Range{0, 100000}};

  void configure() override;
  void linearize(const Eigen::Isometry2d& t, NormalEquations<Space2D>& eq) const override;

  /// The prior pose of the bound frame (scene <- robot).
  const Eigen::Isometry2d& prior() const { return prior_; }
  /// The information matrix of the bound frame's factor.
  const Eigen::Matrix3d& information() const { return information_; }
  /// The factor by which the bound frame's translation and rotation sigmas are scaled up for
  /// the observed disagreement (1: none).
  const Eigen::Vector2d& disagreementScale() const { return scale_; }
  /// The error e(T) and its Jacobian w.r.t. the right perturbation of T.
  Eigen::Vector3d error(const Eigen::Isometry2d& t, Eigen::Matrix3d* jacobian = nullptr) const;

 protected:
  bool prepare(const AlignContext<Space2D>& context) override;

 private:
  // Folds the previous frame's residual (context.motion_residual) into the running mean and
  // sets scale_ for this frame.
  void observeDisagreement(const AlignContext<Space2D>& context);
  // Reading of the last frame seen, and the one before the frame being bound (so binding the
  // same frame twice gives the same delta).
  std::optional<Eigen::Isometry2d> last_;
  std::optional<Eigen::Isometry2d> before_bound_;
  std::optional<std::pair<uint64_t, double>> bound_;  // (seq, stamp) of the bound frame
  Eigen::Isometry2d prior_ = Eigen::Isometry2d::Identity();
  Eigen::Matrix3d information_ = Eigen::Matrix3d::Identity();
  // The model's sigmas (translation, rotation) of the last bound frame, to normalize its
  // residual when the next frame brings it.
  std::optional<Eigen::Vector2d> last_sigmas_;
  Eigen::Vector2d mean_square_ = Eigen::Vector2d::Zero();  // running, normalized residuals
  Eigen::Vector2d scale_ = Eigen::Vector2d::Ones();
};

}  // namespace odometry
}  // namespace plugslam
