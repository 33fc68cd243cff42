#pragma once
// io.KittiSource: the KITTI odometry layout (image_0 .. image_3, calib.txt, times.txt,
// poses/NN.txt), rectified stereo pairs.
#include <cstdint>
#include <string>
#include <vector>

#include "plugslam/trajectory.h"
#include "sources/camera_sequence_source.h"

namespace plugslam {
namespace io {

/// One frame per left image: raw[left], raw[right] (Image, grey or RGB as stored),
/// raw[camera] (CameraInfo: the rectified pair from calib.txt's P0/P1 or P2/P3) and
/// raw[ground_truth] (camera 0 in the world, from the poses file, when there is one). A folder
/// may hold a cut of a sequence: images are numbered from any index, and times.txt and the poses
/// file are indexed by the image's number.
class KittiSource : public StereoSequenceSource {
 public:
  Param<std::string> cameras{this,
                             "cameras",
                             "grey",
                             "",
                             "grey: image_0/image_1 with P0/P1; colour: image_2/image_3 with P2/P3",
                             Choices{{"grey", "colour"}}};
  Param<std::string> poses{this, "poses", "", "",
                           "ground-truth poses file (KITTI 3x4 rows); empty = poses/NN.txt in "
                           "the folder or in ../../poses (NN = the folder's name, or the only "
                           "file there); none = no ground truth"};

 protected:
  std::size_t index() override;
  void read(std::size_t i, Frame& frame) override;
  std::optional<Eigen::Isometry3d> groundTruth(std::size_t i, double stamp) const override;
  std::string describe() const override;

 private:
  std::string findPoses(const std::string& dir) const;

  std::string left_dir_, right_dir_;
  std::vector<NumberedFile> images_;
  std::vector<double> times_;
  std::vector<Eigen::Isometry3d> poses_;
};

}  // namespace io
}  // namespace plugslam
