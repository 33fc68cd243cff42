#pragma once
// io.TumRgbd: the TUM RGB-D layout (rgb.txt, depth.txt, optional groundtruth.txt), colour and
// depth associated by timestamp. 7-Scenes folders indexed in this layout read the same way.
#include <string>
#include <vector>

#include "sources/ground_truth_file.h"
#include "sources/rgbd_sequence_source.h"

namespace plugslam {
namespace io {

/// One frame per colour image with a depth image within max_difference (TUM's associate.py:
/// closest pairs first, each image once); the frame's time is the colour image's.
/// raw[ground_truth] is the colour camera in the world, interpolated in groundtruth.txt.
class TumRgbdSource : public WithGroundTruthFile<RgbdSequenceSource> {
 public:
  TumRgbdSource()
      : WithGroundTruthFile(
            "TUM trajectory; empty = groundtruth.txt when present, none = no ground truth") {}

  Param<std::string> rgb_list{this, "rgb_list", "rgb.txt", "",
                              "colour index (timestamp filename), relative to path"};
  Param<std::string> depth_list{this, "depth_list", "depth.txt", "",
                                "depth index (timestamp filename), relative to path"};
  Param<double> max_difference{this,
                               "max_difference",
                               0.02,
                               "s",
                               "largest colour-depth time difference of a pair (TUM's "
                               "associate.py default: the Kinect's streams are unsynchronised "
                               "at 30 Hz, 33 ms apart)",
                               Range{0.0, 10.0}};

 protected:
  std::size_t index() override;
  std::optional<Eigen::Isometry3d> groundTruth(std::size_t i, double stamp) const override;
  std::string describe() const override;
};

}  // namespace io
}  // namespace plugslam
