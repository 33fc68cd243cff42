// The rgbd plugin's register function. The landmark cue's slices and writers are the SDK's
// (sdk.ReprojectionSlice3D, sdk.LandmarkMapSlice3D): this plugin adds what needs OpenCV, and the
// dense depth cue.
#include "plugslam/plugin.h"

#include "depth_slices.h"
#include "rgbd_preprocessor.h"

PLUGSLAM_PLUGIN("rgbd", "1.0.0", "RGB-D cameras: keypoints with depth, and the dense depth cue") {
  using namespace plugslam::rgbd;
  registrar.addValueType<DepthKeyframe>("DepthKeyframe");
  registrar.add<RgbdPreprocessor>(
      "RgbdPreprocessor",
      "colour + depth -> keypoints (grid-bucketed FAST + ORB) with depth and its noise");
  registrar.addBothSpaces<DepthSlice>(
      "DepthSlice", "dense depth: point-to-plane factors against the map's depth keyframe");
  registrar.addBothSpaces<DepthKeyframeSlice>(
      "DepthKeyframeSlice", "keeps the local map's depth keyframe for the dense depth cue");
}
