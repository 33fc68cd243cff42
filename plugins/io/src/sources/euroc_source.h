#pragma once
// io.EurocSource: the EuRoC MAV (ASL) layout, mav0/cam0 + mav0/cam1 (data.csv, data/*.png,
// sensor.yaml), raw (distorted, unrectified) stereo pairs, with the ground truth when present.
#include <cstdint>
#include <string>
#include <vector>

#include "sources/camera_sequence_source.h"
#include "sources/ground_truth_file.h"

namespace plugslam {
namespace io {

/// One frame per pair of images with the same timestamp: raw[left], raw[right] (grey Image,
/// as recorded: distorted), raw[camera] (CameraInfo: cam0's pinhole and distortion, baseline 0,
/// second = cam1's, second_pose = cam1 in cam0, mount = cam0's T_BS: the robot frame is EuRoC's
/// body frame) and raw[ground_truth] (the body in the world, interpolated at the image time).
/// Rectification is the stereo preprocessor's job.
class EurocSource : public WithGroundTruthFile<StereoSequenceSource> {
 public:
  EurocSource()
      : WithGroundTruthFile("ground truth csv (t [ns], p xyz, q wxyz, ...); empty = "
                            "mav0/state_groundtruth_estimate0/data.csv when present; none = no "
                            "ground truth") {}

  Param<std::string> left_camera{this, "left_camera", "cam0", "",
                                 "sensor folder under mav0/ of the left camera"};
  Param<std::string> right_camera{this, "right_camera", "cam1", "",
                                  "sensor folder under mav0/ of the right camera"};

 protected:
  std::size_t index() override;
  void read(std::size_t i, Frame& frame) override;
  std::string describe() const override;

 private:
  struct Pair {
    std::int64_t stamp_ns;
    std::string left, right;  // file paths
  };
  std::vector<Pair> pairs_;
};

}  // namespace io
}  // namespace plugslam
