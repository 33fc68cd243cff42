#pragma once
// io.KittiRawSource: a KITTI raw drive, synced + rectified (image_00/data .. image_03/data,
// image_0N/timestamps.txt, calib_cam_to_cam.txt in the drive's folder or its date folder).
#include <string>
#include <vector>

#include "sources/camera_sequence_source.h"

namespace plugslam {
namespace io {

/// One frame per left image: raw[left], raw[right] (Image), raw[camera] (CameraInfo from
/// P_rect_00/01 or P_rect_02/03, size S_rect). The frame's time is the left camera's timestamp
/// (seconds since the epoch, read as UTC). KITTI raw comes with OXTS (GPS/IMU) rather than
/// camera poses, and this source emits no ground truth.
class KittiRawSource : public StereoSequenceSource {
 public:
  Param<std::string> cameras{
      this,     "cameras",
      "grey",   "",
      "grey: image_00/image_01 with P_rect_00/01; colour: image_02/image_03 with P_rect_02/03",
      Choices{{"grey", "colour"}}};

 protected:
  std::size_t index() override;
  void read(std::size_t i, Frame& frame) override;
  std::optional<Eigen::Isometry3d> groundTruth(std::size_t, double) const override {
    return std::nullopt;
  }
  std::string describe() const override;

 private:
  std::string left_dir_, right_dir_;
  std::vector<NumberedFile> images_;
  std::vector<double> times_;
};

}  // namespace io
}  // namespace plugslam
