#pragma once
// Depth in the colour camera's pixels. A driver that registers depth to colour (TUM's OpenNI,
// the simulator) needs nothing; a rig whose depth camera has its own intrinsics or sits apart
// from the colour camera (CameraInfo::second, second_pose) gets every depth pixel moved into the
// colour image, nearest surface first.
#include <vector>

#include "plugslam/sensor_data.h"

namespace plugslam {
namespace rgbd {

/// Maps depth images into the colour camera of a calibration.
class DepthRegistration {
 public:
  /// Prepares for `camera` (the colour camera, `second` = the depth camera): the depth pixels'
  /// bearings are computed once per calibration. Throws InputError when `second` is missing or
  /// a model is not one this supports.
  void prepare(const CameraInfo& camera);
  /// True when the depth image already is in the colour camera's pixels (same pinhole, size and
  /// distortion, identity pose): apply() then returns its input.
  bool identity() const { return identity_; }
  /// The depth image in the colour camera's pixels (z along the colour camera's axis). Colour
  /// pixels no depth pixel lands on have no reading; where several land, the nearest wins.
  const DepthImage& apply(const DepthImage& depth);

 private:
  bool sameCalibration(const CameraInfo& camera) const;

  CameraInfo camera_;
  bool prepared_ = false;
  bool identity_ = true;
  std::vector<float> bearings_;  // per depth pixel: (x/z, y/z) of its ray, undistorted
  DepthImage out_;
};

/// Pixel coordinates in `camera`'s raw (distorted) image moved to its ideal pinhole: the
/// identity when it has no distortion.
void undistortPixels(const CameraIntrinsics& camera, std::vector<double>& xy);

}  // namespace rgbd
}  // namespace plugslam
