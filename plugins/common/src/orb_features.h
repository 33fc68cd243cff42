#pragma once
// Grid-bucketed FAST corners with ORB descriptors (OpenCV features2d) over an image pyramid: the
// keypoints of the landmark cue's camera preprocessors (the stereo and rgbd plugins').
// Bucketing spreads the keypoints over the whole image, so the pose is constrained by every part
// of the view, not only by its most textured corner. The pyramid makes them scale-invariant: a
// corner seen from twice as near looks twice as large, and is found and described again at the
// level where it has the size it had before (ORB-SLAM's scheme: FAST per level, descriptors at
// the keypoint's level).
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

namespace plugslam {
namespace visual {

/// How many keypoints, where, and how strong.
struct OrbOptions {
  int features = 1500;         ///< target number of keypoints over the image
  int cell = 32;               ///< bucket side [px]; each bucket keeps its strongest corners
  int fast_threshold = 20;     ///< FAST intensity threshold [grey levels]
  int min_fast_threshold = 7;  ///< retried in buckets that got no corner at fast_threshold
  /// Descriptors at angle 0 (no intensity-centroid orientation): more distinctive when the
  /// camera does not roll much between the frames it matches, which holds at video rates.
  bool upright = true;
  /// Pyramid levels (1: full resolution only). Level l is the image shrunk by scale_factor^l.
  int levels = 1;
  /// Scale between neighbouring levels: small enough that a corner's FAST response and ORB
  /// patch still match one level up or down (1.2 as ORB-SLAM).
  double scale_factor = 1.2;
};

/// Detects grid-bucketed FAST corners and computes their ORB descriptors.
class OrbExtractor {
 public:
  OrbExtractor();
  /// Sets the options (rebuilds the ORB object only when needed).
  void setOptions(const OrbOptions& options);
  const OrbOptions& options() const { return options_; }
  /// Keypoints of an 8-bit grey image and their descriptors (one 32-byte row each), in
  /// full-resolution pixels; `octave` is the pyramid level a keypoint was found and described
  /// at, `size` its patch diameter there in full-resolution pixels. Keypoints lie at least
  /// border() level pixels inside their level's image, where the descriptor pattern fits.
  void extract(const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);
  /// Scale of pyramid level `level` against full resolution (scale_factor^level).
  double levelScale(int level) const;
  /// Keypoints the options ask of level `level` (the per-level share of `features`).
  int levelFeatures(int level) const;
  /// Distance of keypoints from the image border [px].
  static constexpr int border() { return 16; }
  /// Seconds spent so far finding corners (FAST and bucketing) and describing them (ORB).
  double detectionSeconds() const { return detection_s_; }
  double descriptionSeconds() const { return description_s_; }

 private:
  // Grid-bucketed FAST on one image: keypoints in its pixels, octave 0, angle unset.
  void detect(const cv::Mat& image, int features, std::vector<cv::KeyPoint>& out);

  OrbOptions options_;
  cv::Ptr<cv::ORB> orb_;
  std::vector<cv::Mat> pyramid_;
  std::vector<cv::KeyPoint> strong_, weak_, level_kps_;
  cv::Mat level_desc_;
  std::vector<std::vector<int>> cells_;
  double detection_s_ = 0, description_s_ = 0;
};

}  // namespace visual
}  // namespace plugslam
