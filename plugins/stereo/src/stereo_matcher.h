#pragma once
// Matching keypoints of a rectified stereo pair along image rows: a descriptor check picks the
// right keypoint, a zero-mean SAD search along the row refines the disparity to a fraction of a
// pixel (parabola through the best cost and its neighbours).
#include <opencv2/core.hpp>
#include <vector>

namespace plugslam {
namespace visual {

/// Limits of stereo matching.
struct StereoMatchOptions {
  double min_disparity = 1.0;    ///< smaller disparities are too far to range [px]
  double max_disparity = 200.0;  ///< larger disparities are nearer than the rig ranges [px]
  int row_tolerance = 2;         ///< right keypoints this many rows off still compete [px]
  int max_hamming = 50;          ///< descriptor check [bits]
  int window = 5;                ///< half side of the SAD window [px]
  int search = 3;                ///< SAD search either side of the matched keypoint [px]
  /// Pyramid scale between levels: a keypoint of level l (its octave) gets row_tolerance times
  /// scale_factor^l rows, and partners only from levels l-1 .. l+1.
  double scale_factor = 1.2;
};

/// One left keypoint's disparity (uL - uR), or a negative value when unmatched.
struct StereoMatcher {
  /// Disparities for each left keypoint; unmatched ones get -1.
  static void match(const cv::Mat& left, const cv::Mat& right,
                    const std::vector<cv::KeyPoint>& left_kps, const cv::Mat& left_desc,
                    const std::vector<cv::KeyPoint>& right_kps, const cv::Mat& right_desc,
                    const StereoMatchOptions& options, std::vector<double>& disparity);
  /// Sub-pixel right column for left pixel (ul, v) near right column ur0, by zero-mean SAD; NaN
  /// when the minimum lies on the search border or the window leaves an image.
  static double refine(const cv::Mat& left, const cv::Mat& right, int ul, int v, int ur0,
                       int window, int search);
};

}  // namespace visual
}  // namespace plugslam
