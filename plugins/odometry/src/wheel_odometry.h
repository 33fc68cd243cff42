#pragma once
// odometry.WheelOdometry / odometry.WheelOdometry3D: motion prediction from the wheel odometry in
// the raw frame, for a 2D pipeline and (lifted into the robot frame) for a 3D one.
#include <optional>
#include <string>
#include <vector>

#include "plugslam/motion_model.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace odometry {

/// Predicts the motion since the previous reading as last_odom^-1 * odom (in the previous base
/// frame), turned into the pipeline's pose space by lift(). A frame without the entry predicts
/// nothing and keeps the last reading, so the next prediction spans the gap.
template <class S>
class WheelOdometryModel : public MotionModel<S> {
 public:
  using Pose = typename S::Pose;
  Input<Odometry2D> input{this, Container::raw, "input", "odom", "wheel odometry to read"};

  void configure() override;
  std::optional<Pose> predict(const Frame& frame) override;
  void reset() override;

 protected:
  /// The planar delta (in the previous base frame) as a motion of the robot frame.
  virtual Pose lift(const Eigen::Isometry2d& delta) const = 0;

 private:
  static constexpr int kSayLaserOnlyAfter = 10;  // frames without a reading
  std::optional<Eigen::Isometry2d> last_;
  bool seen_ = false;       // a reading arrived once
  int frames_without_ = 0;  // before the first reading
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

 private:
  Eigen::Isometry3d mount_ = Eigen::Isometry3d::Identity();
};

}  // namespace odometry
}  // namespace plugslam
