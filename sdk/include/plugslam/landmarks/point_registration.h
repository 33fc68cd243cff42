#pragma once
// Wide-baseline registration of two sets of described 3D points (the landmark cue's keypoints
// with depth, or a local map's landmarks): every descriptor of one set is matched against every
// descriptor of the other (no pose prior, the whole image), then a rigid transform is found by
// 3D-3D RANSAC on minimal samples of three matches, inliers judged by the Mahalanobis distance
// under both points' covariances, and refitted on its inliers. The tracker uses it to recover
// when projective tracking fails; loop validation uses it to check a candidate pair of maps.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "plugslam/landmarks/feature_set.h"
#include "plugslam/landmarks/landmark_map.h"

namespace plugslam {
inline namespace abi_v1 {

/// 3D points with binary descriptors and covariances, in one frame (a view made for matching).
struct DescribedPoints {
  std::vector<Eigen::Vector3d> points;       ///< [m]
  std::vector<Eigen::Matrix3d> covariances;  ///< of `points` [m^2] (empty: unit covariance)
  int descriptor_bytes = 32;                 ///< bytes per descriptor
  std::vector<uint8_t> descriptors;          ///< size() * descriptor_bytes, row by row
  std::vector<int> source_index;             ///< index of each point in the set it came from
  /// Number of points.
  size_t size() const { return points.size(); }
  /// Descriptor of point i.
  const uint8_t* descriptor(size_t i) const {
    return descriptors.data() + i * static_cast<size_t>(descriptor_bytes);
  }
};

/// The keypoints of `features` that have a depth, in the camera's optical frame.
DescribedPoints describedPoints(const FeatureSet& features);
/// The landmarks of `map`, in the local map's frame.
DescribedPoints describedPoints(const LandmarkMap& map);

/// Limits of the all-against-all descriptor matching.
struct DescriptorMatchOptions {
  int max_hamming = 64;  ///< larger Hamming distances are no match [bits]
  double ratio = 0.8;    ///< best / second-best distance must stay below this (1: off)
  bool mutual = true;    ///< keep a pair only when each is the other's best match
};

/// One pair of matched points: indices into the source and the target DescribedPoints.
struct PointMatch {
  int source = -1;    ///< index in the source set
  int target = -1;    ///< index in the target set
  int distance = 0;   ///< Hamming distance [bits]
};

/// Matches every source descriptor against every target descriptor (brute force).
std::vector<PointMatch> matchDescriptors(const DescribedPoints& source,
                                         const DescribedPoints& target,
                                         const DescriptorMatchOptions& options = {});

/// Limits of the rigid RANSAC.
struct RansacOptions {
  int max_iterations = 2000;  ///< minimal samples drawn at most
  double confidence = 0.999;  ///< stop once an all-inlier sample was drawn this surely
  /// A match is an inlier when its squared Mahalanobis distance under the summed covariances
  /// stays below this (default: chi-square 99 % for 3 dof).
  double inlier_chi2 = 11.34;
  int min_inliers = 12;       ///< fewer inliers make the registration invalid
  uint64_t seed = 1;          ///< of the sampler: a registration is repeatable
};

/// Outcome of a registration.
struct PointRegistration {
  bool valid = false;  ///< at least min_inliers inliers and a well-spread (non-planar-line) fit
  /// Maps source coordinates into the target frame (target <- source).
  Eigen::Isometry3d target_from_source = Eigen::Isometry3d::Identity();
  std::vector<PointMatch> inliers;  ///< the matches consistent with the transform
  size_t matches = 0;               ///< descriptor matches RANSAC chose from
  int iterations = 0;               ///< samples drawn
};

/// RANSAC on given matches (for callers with their own association).
PointRegistration registerMatches(const DescribedPoints& source, const DescribedPoints& target,
                                  const std::vector<PointMatch>& matches,
                                  const RansacOptions& options = {});
/// Descriptor matching, then registerMatches: target <- source without any prior.
PointRegistration registerPoints(const DescribedPoints& source, const DescribedPoints& target,
                                 const DescriptorMatchOptions& match = {},
                                 const RansacOptions& ransac = {});

}  // namespace abi_v1
}  // namespace plugslam
