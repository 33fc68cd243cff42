#pragma once
// odometry.WheelOdometry: motion prediction from the wheel odometry in the raw frame.
#include <optional>
#include <string>

#include "plugslam/motion_model.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace odometry {

/// Predicts the motion since the previous reading as last_odom^-1 * odom (in the previous robot
/// frame). A frame without the entry predicts nothing and keeps the last reading, so the next
/// prediction spans the gap.
class WheelOdometry : public MotionModel<Space2D> {
 public:
  Input<Odometry2D> input{this, Container::raw, "input", "odom", "wheel odometry to read"};

  void configure() override;
  std::optional<Eigen::Isometry2d> predict(const Frame& frame) override;
  void reset() override;

 private:
  static constexpr int kSayLaserOnlyAfter = 10;  // frames without a reading
  std::optional<Eigen::Isometry2d> last_;
  bool seen_ = false;       // a reading arrived once
  int frames_without_ = 0;  // before the first reading
};

}  // namespace odometry
}  // namespace plugslam
