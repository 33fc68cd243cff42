// The odometry plugin: wheel-odometry motion prediction and the odometry prior slice.
#include "plugslam/plugin.h"

#include "prior_slice.h"
#include "wheel_odometry.h"

PLUGSLAM_PLUGIN("odometry", "1.0.0", "wheel odometry: motion prediction and prior factor") {
  using namespace plugslam::odometry;
  registrar.add<WheelOdometry>("WheelOdometry", "predicts the motion from raw Odometry2D");
  registrar.add<PriorSlice>("PriorSlice",
                            "aligner factor on the relative pose from the odometry delta");
}
