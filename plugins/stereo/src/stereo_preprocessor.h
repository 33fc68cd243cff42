#pragma once
// stereo.StereoPreprocessor: a rectified (or raw, then rectified here) stereo pair -> the
// landmark cue's FeatureSet: grid-bucketed FAST + ORB in both images, matches along rows with a
// descriptor check and sub-pixel refinement, depth from disparity with its covariance.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "keypoint_preprocessor.h"
#include "rectifier.h"
#include "plugslam/landmarks/feature_set.h"
#include "plugslam/sensor_data.h"
#include "plugslam/statistics.h"
#include "stereo_matcher.h"

namespace plugslam {
namespace visual {

/// Keypoints with stereo depth from a left/right image pair.
class StereoPreprocessor final : public KeypointPreprocessor, public StatisticsSource {
 public:
  Input<Image> left{this, Container::raw, "left", "left", "the left image"};
  Input<Image> right{this, Container::raw, "right", "right", "the right image"};
  Input<CameraInfo> camera{this, Container::raw, "camera", "camera",
                           "the calibration: left intrinsics and baseline (rectified), or both "
                           "cameras (second, second_pose) of a raw pair to rectify"};
  Output<FeatureSet> output{this, Container::measurement, "output", "features",
                            "keypoints with stereo depth (rectified left camera's pinhole)"};
  Param<int> max_hamming{this, "max_hamming", 50, "bits",
                         "stereo descriptor check: larger distances are no match", Range{0, 256}};
  Param<int> row_tolerance{this, "row_tolerance", 2, "px",
                           "right keypoints this many rows off still match (rectification error)",
                           Range{0, 50}};
  Param<double> min_disparity{this, "min_disparity", 1.0, "px",
                              "keypoints with smaller disparity get no depth (too far to range)",
                              Range{0.05, 1000}};
  Param<double> min_depth{this, "min_depth", 0.5, "m",
                          "nearest depth searched: sets the largest disparity, fx b / min_depth",
                          Range{0.01, 1000}};
  Param<double> disparity_sigma{this, "disparity_sigma", 0.5, "px",
                                "noise of the refined disparity", Range{0.01, 100}};

  StereoPreprocessor();
  ~StereoPreprocessor() override;
  void configure() override;
  bool process(Frame& frame) override;

  /// frames, extraction_s, matching_s, per frame: keypoints (left image) and those with depth.
  std::vector<Statistic> statistics() const override;

 private:
  OrbExtractor right_extractor_;
  StereoRectifier rectifier_;
  cv::Mat rect_l_, rect_r_;
  std::vector<cv::KeyPoint> kl_, kr_;
  cv::Mat dl_, dr_;
  std::vector<double> disparity_;
  double extraction_s_ = 0, matching_s_ = 0;
  uint64_t frames_ = 0, keypoints_ = 0, with_depth_ = 0;
};

}  // namespace visual
}  // namespace plugslam
