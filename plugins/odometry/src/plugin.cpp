// The odometry plugin: wheel-odometry motion prediction and the odometry prior slice, for 2D
// pipelines and (lifted into the robot frame) 3D ones.
#include "plugslam/plugin.h"

#include "prior_slice.h"
#include "wheel_odometry.h"

PLUGSLAM_PLUGIN("odometry", "1.0.0", "wheel odometry: motion prediction and prior factor") {
  using namespace plugslam::odometry;
  registrar.add<WheelOdometry>("WheelOdometry", "predicts the motion from raw Odometry2D");
  registrar.add<PriorSlice>("PriorSlice",
                            "aligner factor on the relative pose from the odometry delta");
  registrar.add<WheelOdometry3D>(
      "WheelOdometry3D", "predicts the 3D motion from raw Odometry2D, lifted into the robot frame");
  registrar.add<PriorSlice3D>(
      "PriorSlice3D",
      "aligner factor on the 3D relative pose from the planar odometry delta (x, y, yaw)");
}
