#pragma once
// odometry.WheelOdometry / odometry.WheelOdometry3D: motion prediction from the wheel odometry in
// the raw frame, for a 2D pipeline and (lifted into the robot frame) for a 3D one, with the
// covariance of its error.
#include <deque>
#include <optional>
#include <vector>

#include "odometry_frame.h"
#include "plugslam/motion_model.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace odometry {

/// Predicts the motion since the previous reading as last_odom^-1 * odom (in the previous base
/// frame), turned into the pipeline's pose space by lift(). A frame without the entry predicts
/// nothing and keeps the last reading, so the next prediction spans the gap.
///
/// The covariance grows with the motion the wheels measured (scale and slip per metre, skid per
/// radian turned) and with the time between the frames and the readings given to them: a
/// reading taken before (or after) its frame did not see the motion in between, which the
/// odometry's recent speed bounds. That covers odometry read less often than the frames (a
/// frame given the previous frame's reading again predicts no motion, with the covariance of the
/// motion it did not see) without guessing that motion.
template <class S>
class WheelOdometryModel : public MotionModel<S> {
 public:
  using Pose = typename S::Pose;
  Input<Odometry2D> input{this, Container::raw, "input", "odom", "wheel odometry to read"};
  // Wheel odometry errs by the wheels' scale and slip along the path (a few per cent of it), by
  // skid when turning, and in heading by the wheel base's error, which a differential drive
  // makes its worst: a few per cent of a wheel's travel turns the robot by hundredths of a
  // radian per metre and by a fifth of every turn. The floors cover a step too short to show them
  // (the encoders' resolution, the readings' timing).
  Param<double> sigma_translation_per_m{this,
                                        "sigma_translation_per_m",
                                        0.02,
                                        "m/m",
                                        "translation error per metre travelled (scale, slip)",
                                        Range{0, 100}};
  Param<double> sigma_translation_per_rad{this,
                                          "sigma_translation_per_rad",
                                          0.05,
                                          "m/rad",
                                          "translation error per radian turned (skid)",
                                          Range{0, 100}};
  Param<double> sigma_rotation_per_m{this,
                                     "sigma_rotation_per_m",
                                     0.02,
                                     "rad/m",
                                     "heading error per metre travelled (wheel base, uneven "
                                     "wheels)",
                                     Range{0, 100}};
  Param<double> sigma_rotation_per_rad{this,
                                       "sigma_rotation_per_rad",
                                       0.2,
                                       "rad/rad",
                                       "heading error per radian turned (skid, wheel base)",
                                       Range{0, 100}};
  Param<double> min_sigma_translation{this, "min_sigma_translation",   0.02,
                                      "m",  "translation error floor", Range{1e-9, 1e6}};
  Param<double> min_sigma_rotation{this,  "min_sigma_rotation",  0.05,
                                   "rad", "heading error floor", Range{1e-9, 1e6}};

  void configure() override;
  std::optional<MotionEstimate<S>> predict(const Frame& frame) override;
  void reset() override;

 protected:
  /// The planar delta (in the previous base frame) as a motion of the robot frame.
  virtual Pose lift(const Eigen::Isometry2d& delta) const = 0;

 private:
  static constexpr int kSayLaserOnlyAfter = 10;  // frames without a reading
  static constexpr size_t kHistory = 8;          // readings kept for the recent speed
  // The odometry's recent speed (m/s, rad/s) over the readings kept; zero when unknown.
  std::pair<double, double> recentSpeed() const;
  std::optional<Eigen::Isometry2d> last_;  // the reading the last prediction ended at
  double last_unseen_ = 0;                 // |frame stamp - reading stamp| of the last frame [s]
  std::deque<Odometry2D> history_;         // the last distinct readings, oldest first
  bool seen_ = false;                      // a reading arrived once
  int frames_without_ = 0;                 // before the first reading
};

extern template class WheelOdometryModel<Space2D>;
extern template class WheelOdometryModel<Space3D>;

/// The 2D model: the robot frame is the odometry's base.
class WheelOdometry : public WheelOdometryModel<Space2D> {
 protected:
  Eigen::Isometry2d lift(const Eigen::Isometry2d& delta) const override { return delta; }
};

/// The 3D model: the planar delta lifted into SE3 (no height, roll or pitch change, which a
/// wheel encoder cannot measure) and moved into the robot frame through the base's mount:
/// mount * to3D(delta) * mount^-1. Its covariance is isotropic in translation and in rotation
/// (the planar sigmas), which the mount's rotation leaves as it is.
class WheelOdometry3D : public WheelOdometryModel<Space3D> {
 public:
  Param<std::vector<double>> mount = mountParam(this);

  void configure() override;

 protected:
  Eigen::Isometry3d lift(const Eigen::Isometry2d& delta) const override;

 private:
  Eigen::Isometry3d mount_ = Eigen::Isometry3d::Identity();
};

}  // namespace odometry
}  // namespace plugslam
