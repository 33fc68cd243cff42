#pragma once
// rgbd.RgbdPreprocessor: a colour + depth image pair -> the landmark cue's FeatureSet: the
// stereo plugin's grid-bucketed FAST + ORB keypoints in the colour image, each with the depth
// under it (registered to colour when the depth camera differs) and that depth's noise.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "depth_model.h"
#include "depth_registration.h"
#include "keypoint_preprocessor.h"
#include "plugslam/landmarks/feature_set.h"

namespace plugslam {
namespace rgbd {

/// Keypoints with depth from an RGB-D frame.
class RgbdPreprocessor final : public visual::KeypointPreprocessor {
 public:
  Input<Image> rgb{this, Container::raw, "rgb", "rgb", "the colour image"};
  Input<DepthImage> depth{this, Container::raw, "depth", "depth",
                          "the depth image (metres, 0 = no reading)"};
  Input<CameraInfo> camera{this, Container::raw, "camera", "camera",
                           "the calibration: colour camera; second = depth camera, second_pose = "
                           "its pose in the colour frame"};
  Output<FeatureSet> output{this, Container::measurement, "output", "features",
                            "keypoints with depth (colour camera's ideal pinhole)"};
  DepthNoiseParams depth_sigma{this};  ///< depth_sigma_a, _b, _z0
  Param<double> max_incidence{this, "max_incidence", 80.0, "deg",
                              "steepest surface ranged: larger depth steps between neighbouring "
                              "pixels are occlusion edges, where a keypoint gets no depth",
                              Range{1, 89.9}};

  RgbdPreprocessor();
  ~RgbdPreprocessor() override;
  void configure() override;
  bool process(Frame& frame) override;

  /// Time spent extracting keypoints, and reading (registering, sampling) depth, summed [s].
  double extractionTime() const { return extraction_s_; }
  double depthTime() const { return depth_s_; }

 private:
  DepthRegistration registration_;
  std::vector<cv::KeyPoint> keypoints_;
  cv::Mat descriptors_;
  std::vector<double> xy_;
  double extraction_s_ = 0, depth_s_ = 0;
};

}  // namespace rgbd
}  // namespace plugslam
