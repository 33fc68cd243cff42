#pragma once
// Projective data association of the landmark cue, shared by its aligner slice (at every
// association round) and its tracker slice (at the final pose): each landmark is projected into
// the image and paired with the keypoint near its projection whose descriptor is closest, if it
// passes the descriptor check. A keypoint keeps only its best landmark. With pyramid keypoints
// the association respects scale: a landmark is expected at the scale its reference distance
// predicts from where the camera is, its search radius grows with that scale (a coarse keypoint
// is located that much less precisely), and keypoints of another scale are no match (a corner
// described at the wrong scale only matches by chance).
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "plugslam/landmarks/feature_set.h"
#include "plugslam/landmarks/landmark_map.h"

namespace plugslam {
inline namespace abi_v1 {

/// Limits of one association.
struct AssociationOptions {
  double radius = 10.0;  ///< search radius around a landmark's projection [px]
  int max_hamming = 50;  ///< larger descriptor distances are no match [bits]
  /// Best / second-best distance ratio a match must stay below (1: off); only keypoints inside
  /// the radius compete, so repeated texture far away does not reject a good match.
  double ratio = 1.0;
  double border = 0.0;   ///< projections closer to the image border are not searched [px]
  /// A keypoint whose pyramid scale differs from the landmark's predicted scale by more than this
  /// factor (either way) is no match (0: scale not checked). Landmarks of unknown reference
  /// distance are expected at full resolution; predictions are clamped to the scales searched.
  double scale_tolerance = 0.0;
  /// Per landmark (nullptr: none): how far its projection may be off because the camera's pose
  /// is uncertain [px], times `spread_scale`, added to the radius (which covers the keypoint's
  /// own error at its scale).
  const std::vector<double>* spread = nullptr;
  double spread_scale = 1.0;  ///< factor on `spread` (an association round narrows it)
};

/// The pyramid scale at which a landmark of reference distance `reference_distance` is expected
/// when seen from `distance`, clamped into [1, max_scale] (1 when either distance is unknown).
double predictedScale(double reference_distance, double distance, double max_scale);

/// One landmark-keypoint pair.
struct LandmarkMatch {
  int feature = -1;   ///< index in the FeatureSet
  int landmark = -1;  ///< index in the LandmarkMap
  int distance = 0;   ///< Hamming distance [bits]
};

/// Keypoints bucketed in square image cells, built once per frame, searched per landmark.
class FeatureGrid {
 public:
  /// Buckets the keypoints of `features` in cells of `cell` pixels (the set must outlive it).
  void build(const FeatureSet& features, double cell = 16.0);
  /// Pairs landmarks with keypoints for the camera at `camera_in_scene` (scene <- camera).
  /// `visible`, when given, receives each landmark's "projects into the image" flag.
  void associate(const LandmarkMap& map, const Eigen::Isometry3d& camera_in_scene,
                 const AssociationOptions& options, std::vector<LandmarkMatch>& matches,
                 std::vector<bool>* visible = nullptr) const;
  /// The feature set the grid was built from (nullptr before build()).
  const FeatureSet* features() const { return features_; }

 private:
  const FeatureSet* features_ = nullptr;
  double cell_ = 16.0;
  int cols_ = 0, rows_ = 0;
  std::vector<int> start_;  // CSR: keypoints of cell c are order_[start_[c] .. start_[c + 1])
  std::vector<int> order_;
  mutable std::vector<int> best_landmark_;  // per keypoint, during associate()
  mutable std::vector<int> best_distance_;
};

}  // namespace abi_v1
}  // namespace plugslam
