#pragma once
// io.EurocSource: the EuRoC MAV (ASL) layout, mav0/cam0 + mav0/cam1 (data.csv, data/*.png,
// sensor.yaml), raw (distorted, unrectified) stereo pairs, with the ground truth when present.
#include <cstdint>
#include <string>
#include <vector>

#include "plugslam/trajectory.h"
#include "sources/camera_sequence_source.h"

namespace plugslam {
namespace io {

/// One frame per pair of images with the same timestamp: raw[left], raw[right] (grey Image,
/// as recorded: distorted), raw[camera] (CameraInfo: cam0's pinhole and distortion, baseline 0,
/// second = cam1's, second_pose = cam1 in cam0, mount = cam0's T_BS: the robot frame is EuRoC's
/// body frame) and raw[ground_truth] (the body in the world, interpolated at the image time).
/// Rectification is the stereo preprocessor's job.
class EurocSource : public StereoSequenceSource {
 public:
  Param<std::string> left_camera{this, "left_camera", "cam0", "",
                                 "sensor folder under mav0/ of the left camera"};
  Param<std::string> right_camera{this, "right_camera", "cam1", "",
                                  "sensor folder under mav0/ of the right camera"};
  Param<std::string> ground_truth_file{
      this, "ground_truth_file", "", "",
      "ground truth csv (t [ns], p xyz, q wxyz, ...); empty = "
      "mav0/state_groundtruth_estimate0/data.csv when present; none = no ground truth"};
  Param<double> ground_truth_max_gap{
      this,
      "ground_truth_max_gap",
      0.05,
      "s",
      "longest gap between ground-truth rows to interpolate across (a 50 ms linear "
      "interpolation errs < 2 mm at 5 m/s^2)",
      Range{0.0, 10.0}};

 protected:
  std::size_t index() override;
  void read(std::size_t i, Frame& frame) override;
  std::optional<Eigen::Isometry3d> groundTruth(std::size_t i, double stamp) const override;
  std::string describe() const override;

 private:
  struct Pair {
    std::int64_t stamp_ns;
    std::string left, right;  // file paths
  };
  std::vector<Pair> pairs_;
  Trajectory truth_;
};

}  // namespace io
}  // namespace plugslam
