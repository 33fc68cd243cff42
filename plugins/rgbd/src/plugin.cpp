// The rgbd plugin's register function. The landmark cue's slices and writers are the SDK's
// (sdk.ReprojectionSlice3D, sdk.LandmarkMapSlice3D): this plugin adds what needs OpenCV.
#include "plugslam/plugin.h"

#include "rgbd_preprocessor.h"

PLUGSLAM_PLUGIN("rgbd", "1.0.0", "RGB-D cameras: FAST + ORB keypoints with depth from the depth image") {
  registrar.add<plugslam::rgbd::RgbdPreprocessor>(
      "RgbdPreprocessor",
      "colour + depth -> keypoints (grid-bucketed FAST + ORB) with depth and its noise");
}
