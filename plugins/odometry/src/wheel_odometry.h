#pragma once
// odometry.WheelOdometry / odometry.WheelOdometry3D: motion prediction from the wheel odometry in
// the raw frame, for a 2D pipeline and (lifted into the robot frame) for a 3D one.
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "odometry_calibration.h"
#include "plugslam/motion_model.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace odometry {

/// Predicts the motion since the previous reading as last_odom^-1 * odom (in the previous base
/// frame), turned into the pipeline's pose space by lift(). A frame without the entry predicts
/// nothing and keeps the last reading, so the next prediction spans the gap.
///
/// A frame given the previous frame's reading again (the odometry arrives less often than the
/// scans: the reading's stamp is its own, older than the frame's) learns nothing of its step
/// from it, and taking it as the pose at the frame predicts "no motion". The model carries it on
/// with the odometry's recent velocity (its readings over a span at least as long as the time
/// carried) from where the previous frame's prediction left off, and says which part it
/// extrapolated (ExtrapolatingMotionModel), so the tracker's gate and the prior widen by it.
/// The next reading's delta starts from the extrapolated pose, so the deltas still compose to
/// the readings.
///
/// With `calibration_distance`, each delta is corrected by the wheels' scale, wheel base and
/// heading drift learnt from the motions the tracker solved (OdometryCalibration,
/// CalibratingMotionModel), from the steps the readings measured whole.
template <class S>
class WheelOdometryModel : public MotionModel<S>,
                           public ExtrapolatingMotionModel<S>,
                           public CalibratingMotionModel<S> {
 public:
  using Pose = typename S::Pose;
  Input<Odometry2D> input{this, Container::raw, "input", "odom", "wheel odometry to read"};
  // A robot's velocity changes within about a second (its acceleration limit), so the last
  // velocity says little beyond that; farther, the prediction stays where it got to.
  Param<double> max_extrapolation{
      this, "max_extrapolation", 1.0, "s",
      "a frame given the previous frame's odometry reading again is predicted by carrying that "
      "reading on with the odometry's recent velocity, up to this long after it (0: never; the "
      "reading is then taken as the pose at the frame)",
      Range{0, 3600}};
  Param<double> calibration_distance{
      this, "calibration_distance", 0.0, "m",
      "learn the wheels' scale, wheel base and heading drift per metre from the motions the "
      "tracker solves, over about this distance driven, and correct every delta by them (0: "
      "the odometry as it reads)",
      Range{0, 1e6}};

  void configure() override;
  std::optional<Pose> predict(const Frame& frame) override;
  void reset() override;
  std::optional<Pose> extrapolated() const override { return extrapolated_; }
  void solved(const Pose& motion) override;
  /// The calibration learnt so far.
  const OdometryCalibration& calibration() const { return calibration_; }

 protected:
  /// The planar delta (in the previous base frame) as a motion of the robot frame.
  virtual Pose lift(const Eigen::Isometry2d& delta) const = 0;
  /// A motion of the robot frame as the base's planar motion (lift's inverse on the plane).
  virtual Eigen::Isometry2d planar(const Pose& motion) const = 0;

 private:
  static constexpr int kSayLaserOnlyAfter = 10;  // frames without a reading
  static constexpr size_t kHistory = 8;          // readings kept for the velocity
  static constexpr double kSayCalibrationEvery = 50.0;  // metres learnt from, in the debug log
  // The motion that carries the reading `odom` on by `time` seconds at the recent velocity
  // (empty: no velocity known).
  std::optional<Eigen::Isometry2d> extrapolation(const Odometry2D& odom, double time) const;
  std::optional<Pose> extrapolated_;  // of the last prediction
  std::optional<Odometry2D> previous_reading_;  // the last frame's reading
  std::optional<double> previous_stamp_;    // the last frame's stamp
  double covered_ = 0;                      // time last_carried_ carries its reading on
  std::optional<Eigen::Isometry2d> last_carried_;  // the extrapolation last_ ends with
  std::optional<Eigen::Isometry2d> last_unseen_;   // what the last frame's reading did not see
  // The odometry pose the last prediction ended at (the reading, extrapolated when stale).
  std::optional<Eigen::Isometry2d> last_;
  std::deque<Odometry2D> history_;  // the last distinct readings, oldest first
  OdometryCalibration calibration_;
  // The last prediction's delta as the readings measured it, before calibration; empty when part
  // of it was extrapolated (its error is not the wheels').
  std::optional<Eigen::Isometry2d> raw_delta_;
  bool seen_ = false;       // a reading arrived once
  int frames_without_ = 0;  // before the first reading
};

extern template class WheelOdometryModel<Space2D>;
extern template class WheelOdometryModel<Space3D>;

/// The 2D model: the robot frame is the odometry's base.
class WheelOdometry : public WheelOdometryModel<Space2D> {
 protected:
  Eigen::Isometry2d lift(const Eigen::Isometry2d& delta) const override { return delta; }
  Eigen::Isometry2d planar(const Eigen::Isometry2d& motion) const override { return motion; }
};

/// The 3D model: the planar delta lifted into SE3 (no height, roll or pitch change, which a
/// wheel encoder cannot measure) and moved into the robot frame through the base's mount:
/// mount * to3D(delta) * mount^-1.
class WheelOdometry3D : public WheelOdometryModel<Space3D> {
 public:
  Param<std::vector<double>> mount{
      this,
      "mount",
      {},
      "m, rad",
      "the odometry's base frame (x forward, y left, z up) in the robot frame [x y z rx ry rz] "
      "(rotation vector); empty = the robot frame is the base"};

  void configure() override;

 protected:
  Eigen::Isometry3d lift(const Eigen::Isometry2d& delta) const override;
  Eigen::Isometry2d planar(const Eigen::Isometry3d& motion) const override;

 private:
  Eigen::Isometry3d mount_ = Eigen::Isometry3d::Identity();
};

}  // namespace odometry
}  // namespace plugslam
