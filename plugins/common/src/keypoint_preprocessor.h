#pragma once
// What the landmark cue's camera preprocessors (the stereo and rgbd plugins') share: the
// keypoint parameters and the extractor they configure, so every camera describes its images
// the same way, and views of the SDK's images as OpenCV matrices.
#include <cstdint>
#include <opencv2/core.hpp>

#include "orb_features.h"
#include "plugslam/preprocessor.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace visual {

/// Base of the camera preprocessors: grid-bucketed FAST + ORB keypoints over an image pyramid,
/// their parameters.
class KeypointPreprocessor : public PreProcessor {
 public:
  Param<int> features{this, "features", 1200, "",
                      "target keypoints per image, spread over the image by bucketing",
                      Range{10, 100000}};
  Param<int> cell{this, "cell", 32, "px", "bucket side", Range{8, 4096}};
  Param<int> fast_threshold{this, "fast_threshold", 20, "grey levels", "FAST threshold",
                            Range{1, 255}};
  Param<int> min_fast_threshold{this, "min_fast_threshold", 7, "grey levels",
                                "FAST threshold retried in buckets left empty", Range{1, 255}};
  Param<bool> upright{this, "upright", true, "",
                      "descriptors without orientation (the camera rolls little between frames)"};
  Param<int> levels{this, "levels", 1, "",
                     "image pyramid levels; the coarsest, scale_factor^(levels-1), is the largest "
                     "scale change between two views that keypoints still match across. 1 (full "
                     "resolution only) by default: video-rate frames change little in scale, and "
                     "8 levels cost the stereo front-end half its rate (KITTI raw: 68.7 -> 31.1 "
                     "Hz, measured)",
                     Range{1, 16}};
  Param<double> scale_factor{this, "scale_factor", 1.2, "",
                             "scale between pyramid levels (a corner still matches one level "
                             "up or down)",
                             Range{1.05, 2.0}};
  Param<double> pixel_sigma{this, "pixel_sigma", 1.0, "px",
                            "keypoint position noise (u and v) at full resolution; a keypoint "
                            "of pyramid scale s has s times as much",
                            Range{0.01, 100}};

  ~KeypointPreprocessor() override;
  /// Checks the keypoint parameters and hands them to the extractor (cheap: call per frame to
  /// pick up parameters changed at run time).
  void configure() override;
  /// The extractor options the parameters say.
  OrbOptions orbOptions() const;
  /// Scale of a keypoint's pyramid level (its octave) against full resolution.
  double keypointScale(const cv::KeyPoint& keypoint) const;
  /// Scale of the coarsest level searched (1 without a pyramid).
  double maxScale() const;

 protected:
  OrbExtractor extractor_;
};

/// An SDK image as an OpenCV header over the same pixels (no copy).
cv::Mat asMat(const Image& image);
/// The image in grey (a view when it already is, a conversion otherwise).
cv::Mat greyOf(const Image& image);
/// The colour of pixel (x, y) as 0xRRGGBB (grey replicated).
uint32_t colourAt(const Image& image, int x, int y);

}  // namespace visual
}  // namespace plugslam
