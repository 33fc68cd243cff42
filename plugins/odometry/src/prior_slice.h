#pragma once
// odometry.PriorSlice / odometry.PriorSlice3D: a factor on the aligner's relative pose from the
// wheel odometry, so laser or camera cues and odometry fuse in one solve.
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "odometry_frame.h"
#include "plugslam/aligner_slice.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace odometry {

/// The 2D prior's factor: e = (x, y, theta) of Z^-1 T, whose Jacobian w.r.t. the right
/// perturbation of T (Space2D::boxplus, T * se2(dx)) is exactly blockdiag(R(E), 1) with
/// E = Z^-1 T.
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

/// The 3D prior's factor, in the odometry's base frame: e = (t, q.vec) of
/// E_b = mount^-1 Z^-1 T mount (g2o's SE3 error convention, as sdk PriorFactorSE3), so its
/// components are the base's x, y, z and half its roll, pitch, yaw error to first order, and a
/// diagonal information weighs what the wheels measure apart from what they do not.
struct MotionPrior3D {
  using Space = Space3D;                         ///< the pose space of T
  static constexpr int kErrorDim = 6;            ///< dimension of e
  using Error = Eigen::Matrix<double, 6, 1>;     ///< e
  using Jacobian = Eigen::Matrix<double, 6, 6>;  ///< de / dx
  Eigen::Isometry3d prior;                       ///< Z (scene <- robot)
  Eigen::Isometry3d mount;                       ///< the odometry's base in the robot frame
  /// The error at T.
  Error error(const Eigen::Isometry3d& t) const;
  /// The error and its Jacobian at T.
  void errorAndJacobian(const Eigen::Isometry3d& t, Error& e, Jacobian& j) const;
};

/// Adds one factor on the relative pose T toward Z = previous * (odometry delta since the
/// previous frame), with an information matrix from a motion-proportional noise model on the
/// delta's planar distance d and turn dtheta (in the odometry's base frame):
///   sigma_t = max(min_sigma_translation, sigma_translation_per_m * |d|)
///   sigma_r = max(min_sigma_rotation,
///                 sigma_rotation_per_rad * |dtheta| + sigma_rotation_per_m * |d|)
/// The delta is the tracker's motion model's (AlignContext::motion) when the model read the same
/// entry, else the slice's own. PriorSlice and PriorSlice3D are this, instantiated per space.
template <class S>
class OdometryPriorSlice : public AlignerSlice<S> {
 public:
  using Pose = typename S::Pose;
  /// The factor type of the space.
  using Factor = std::conditional_t<S::kDim == 2, MotionPrior2D, MotionPrior3D>;

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
  void configure() override;
  void linearize(const Pose& t, NormalEquations<S>& eq) const override;

  /// The prior pose of the bound frame (scene <- robot).
  const Pose& prior() const { return prior_; }
  /// The information matrix of the bound frame's factor.
  const typename S::Matrix& information() const { return information_; }
  /// The error e(T) and its Jacobian w.r.t. the right perturbation of T.
  typename S::Vector error(const Pose& t, typename S::Matrix* jacobian = nullptr) const;

 protected:
  bool prepare(const AlignContext<S>& context) override;
  /// The planar odometry delta (in the previous base frame) as the robot frame's motion.
  virtual Pose lift(const Eigen::Isometry2d& delta) const = 0;
  /// A motion of the robot frame as the base's planar motion.
  virtual Eigen::Isometry2d planar(const Pose& motion) const = 0;
  /// The information of the factor for the model's sigmas of the planar motion.
  virtual typename S::Matrix informationFor(double sigma_t, double sigma_r) const = 0;
  /// The factor toward `prior`.
  virtual Factor factor(const Pose& prior) const = 0;

 private:
  // Reading of the last frame seen, and the one before the frame being bound (so binding the
  // same frame twice gives the same delta).
  std::optional<Eigen::Isometry2d> last_;
  std::optional<Eigen::Isometry2d> before_bound_;
  std::optional<std::pair<uint64_t, double>> bound_;  // (seq, stamp) of the bound frame
  Pose prior_ = Pose::Identity();
  typename S::Matrix information_ = S::Matrix::Identity();
};

extern template class OdometryPriorSlice<Space2D>;
extern template class OdometryPriorSlice<Space3D>;

/// The 2D prior: e = log(Z^-1 * T), log being (x, y, theta) of the pose, matching
/// Space2D::boxplus (T * se2(dx)), so the Jacobian is exactly blockdiag(R(E), 1) with
/// E = Z^-1 * T; information diag(1/sigma_t^2, 1/sigma_t^2, 1/sigma_r^2).
class PriorSlice : public OdometryPriorSlice<Space2D> {
 protected:
  Eigen::Isometry2d lift(const Eigen::Isometry2d& delta) const override { return delta; }
  Eigen::Isometry2d planar(const Eigen::Isometry2d& motion) const override { return motion; }
  Eigen::Matrix3d informationFor(double sigma_t, double sigma_r) const override;
  MotionPrior2D factor(const Eigen::Isometry2d& prior) const override { return {prior}; }
};

/// The 3D prior for a ground vehicle: the planar odometry delta lifted into the robot frame
/// through the base's mount (as odometry.WheelOdometry3D), its factor in the base frame
/// (MotionPrior3D) with the 2D noise model on x, y and yaw and loose sigmas on z, roll, pitch.
class PriorSlice3D : public OdometryPriorSlice<Space3D> {
 public:
  Param<std::vector<double>> mount = mountParam(this);
  // A wheel encoder measures nothing about height, roll or pitch: the other cues fix them. They
  // are held loosely (not left free) so that the prior alone, on a frame where the camera sees
  // nothing, still gives a well-posed solve: the motion's planar part from the wheels and the
  // rest from the previous attitude, which on a road changes by far less than these sigmas.
  Param<double> out_of_plane_sigma_translation{
      this,
      "out_of_plane_sigma_translation",
      1.0,
      "m",
      "loose sigma of the base's height change (not measured by wheels)",
      Range{1e-9, 1e6}};
  Param<double> out_of_plane_sigma_rotation{
      this,
      "out_of_plane_sigma_rotation",
      0.1,
      "rad",
      "loose sigma of the base's roll and pitch change (not measured by wheels)",
      Range{1e-9, 1e6}};

  void configure() override;

 protected:
  Eigen::Isometry3d lift(const Eigen::Isometry2d& delta) const override;
  Eigen::Isometry2d planar(const Eigen::Isometry3d& motion) const override;
  Eigen::Matrix<double, 6, 6> informationFor(double sigma_t, double sigma_r) const override;
  MotionPrior3D factor(const Eigen::Isometry3d& prior) const override { return {prior, mount_}; }

 private:
  Eigen::Isometry3d mount_ = Eigen::Isometry3d::Identity();
};

}  // namespace odometry
}  // namespace plugslam
