// The stereo plugin's register function. The landmark cue's slices and writers are the SDK's
// (sdk.ReprojectionSlice3D, sdk.LandmarkMapSlice3D): this plugin adds what needs OpenCV.
#include "plugslam/plugin.h"

#include "stereo_preprocessor.h"

PLUGSLAM_PLUGIN("stereo", "1.0.0", "stereo cameras: FAST + ORB keypoints with stereo depth") {
  using namespace plugslam::visual;
  registrar.add<StereoPreprocessor>(
      "StereoPreprocessor",
      "stereo pair -> keypoints (grid-bucketed FAST + ORB) with depth from row matching");
}
