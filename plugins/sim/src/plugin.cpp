// The sim plugin: the built-in simulator worlds as frame sources with exact ground truth.
#include "plugslam/plugin.h"

#include "simulator2d_source.h"
#include "simulator3d_source.h"
#include "simulator_mixed_source.h"

PLUGSLAM_PLUGIN("sim", "1.0.0", "simulated worlds: 2D office, 3D living room and street") {
  using namespace plugslam::sim;
  registrar.add<Simulator2DSource>(
      "Simulator2D", "simulated office with lasers, wheel odometry and exact ground truth");
  registrar.add<Simulator3DSource>(
      "Simulator3D",
      "rendered stereo pairs or RGB-D frames (living room, street) with ground truth");
  registrar.add<SimulatorMixedSource>(
      "SimulatorMixed",
      "robot with a planar laser, wheel odometry and RGB-D in the 3D living room");
}
