#pragma once
// Rectification of a raw stereo pair (lens distortion, cameras not row-aligned: EuRoC) with
// OpenCV: stereoRectify and initUndistortRectifyMap once per calibration, remap per frame. The
// rectified left camera is an ideal pinhole with the right camera at +baseline along x; its mount
// is the raw left camera's, turned by the rectifying rotation.
#include <opencv2/core.hpp>

#include "plugslam/sensor_data.h"

namespace plugslam {
namespace visual {

/// Rectifying maps of one calibration.
class StereoRectifier {
 public:
  /// True when the calibration describes a raw pair: no baseline yet, and a second camera with
  /// its pose (a rectified pair has a baseline and no distortion).
  static bool needed(const CameraInfo& raw);
  /// Computes the maps for `raw` unless they were computed for the same calibration already.
  /// Throws InputError when the calibration cannot be rectified (no second camera, a bad
  /// distortion model, both cameras at one place).
  void prepare(const CameraInfo& raw);
  /// Rectified copies of a raw pair (grey or colour).
  void rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& left_out,
               cv::Mat& right_out) const;
  /// The rectified left camera: pinhole, size, baseline > 0 and mount; no distortion.
  const CameraInfo& rectified() const { return rectified_; }
  /// How many times maps were computed (once per calibration).
  int preparations() const { return preparations_; }

 private:
  bool same(const CameraInfo& raw) const;
  CameraInfo raw_, rectified_;
  cv::Mat map_l1_, map_l2_, map_r1_, map_r2_;
  bool ready_ = false;
  int preparations_ = 0;
};

}  // namespace visual
}  // namespace plugslam
