#pragma once
// io.RgbdFolder: numbered colour and depth images in two folders (color/N.png, depth/N.png) with
// an optional pose list, one "tx ty tz qx qy qz qw" line per frame (slambook's ICL-NUIM layout).
#include <string>
#include <vector>

#include "sources/rgbd_sequence_source.h"

namespace plugslam {
namespace io {

/// One frame per colour image number that has a depth image of the same number. The layout has
/// no times: frame k (in number order) is stamped k / rate. The pose list's line k is frame k's
/// camera in the world.
class RgbdFolderSource : public RgbdSequenceSource {
 public:
  Param<std::string> colour_folder{this, "colour_folder", "color", "",
                                   "folder of the colour images N.png / N.jpg, relative to path"};
  Param<std::string> depth_folder{this, "depth_folder", "depth", "",
                                  "folder of the 16-bit depth PNGs N.png, relative to path"};
  Param<std::string> colour_extension{this, "colour_extension", ".png", "",
                                      "file ending of the colour images",
                                      Choices{{".png", ".jpg", ".jpeg"}}};
  Param<std::string> poses{this, "poses", "pose.txt", "",
                           "pose list relative to path (one line per frame); none or a missing "
                           "file = no ground truth"};
  Param<double> rate{this, "rate", 30.0, "Hz",
                     "frame rate the synthetic timestamps assume (ICL-NUIM renders 30 Hz)",
                     Range{1e-3, 1e6}};

 protected:
  std::size_t index() override;
  std::optional<Eigen::Isometry3d> groundTruth(std::size_t i, double stamp) const override;
  std::string describe() const override;

 private:
  std::vector<Eigen::Isometry3d> poses_;
};

}  // namespace io
}  // namespace plugslam
