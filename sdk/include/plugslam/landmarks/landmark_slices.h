#pragma once
// The slices of the generic landmark cue (stereo, RGB-D and any camera plugin that fills a
// FeatureSet): an aligner slice adding one reprojection factor (u, v, 1/z) per associated
// landmark, and a tracker slice keeping the local map's LandmarkMap. Both work in 2D and 3D
// pipelines: the camera's mount takes a robot pose to the camera, so a camera can share the
// robot's one pose with a planar laser.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "plugslam/aligner_slice.h"
#include "plugslam/landmarks/association.h"
#include "plugslam/landmarks/local_bundle.h"
#include "plugslam/solver/robust_kernel.h"
#include "plugslam/statistics.h"
#include "plugslam/tracker_slice.h"

namespace plugslam {
inline namespace abi_v1 {

/// One observation (u, v, 1/z) of a mapped landmark by a camera on the aligner's pose: the
/// reprojection slice's typed factor (observationError; the Jacobian is restricted to the pose
/// space's tangent). It does not apply while the landmark is behind the camera.
template <class S>
struct LandmarkReprojection {
  using Space = S;                                     ///< the pose space of T
  static constexpr int kErrorDim = 3;                  ///< (u, v, 1/z)
  using Error = Eigen::Matrix<double, 3, 1>;           ///< predicted - measured
  using Jacobian = Eigen::Matrix<double, 3, S::kDof>;  ///< de / dx
  const Eigen::Isometry3d& mount;                      ///< camera in the robot frame
  const PinholeCamera& camera;                         ///< its intrinsics
  const Eigen::Vector3d& point;                        ///< the landmark, scene frame
  Eigen::Vector3d measured;                            ///< (u, v, 1/z); 1/z = 0 without depth
  /// The error at T (zero while the landmark is behind the camera).
  Error error(const typename S::Pose& t) const;
  /// The error and its Jacobian at T; false while the landmark is behind the camera.
  bool errorAndJacobian(const typename S::Pose& t, Error& e, Jacobian& j) const;
};

/// "sdk.ReprojectionSlice2D/3D": projective association + descriptor check, robust factors.
template <class S>
class ReprojectionSlice final : public AlignerSlice<S>,
                                public RecoverableSlice<S>,
                                public StatisticsSource {
 public:
  using Pose = typename S::Pose;
  Input<FeatureSet> measurement{this, Container::measurement, "measurement", "features",
                                "keypoints to align"};
  Input<LandmarkMap> scene{this, Container::scene, "scene", "landmarks",
                           "local map's landmarks to align to"};
  // The search window of each landmark is where the prediction's covariance lets its
  // projection be: a near point moves far in the image for the same uncertain step, a far one
  // barely. refine_radius covers the keypoint's own error.
  Param<double> refine_radius{this, "refine_radius", 4.0, "px",
                              "association radius at a pose known to a pixel: the keypoint's "
                              "error and the landmark's; each round halves what the pose's "
                              "uncertainty adds to it",
                              Range{0.5, 1000}};
  Param<double> search_radius{this, "search_radius", 20.0, "px",
                              "association radius of the first round when the prediction has no "
                              "covariance (a loop's validation)",
                              Range{0.5, 1000}};
  // A wider window holds a large share of the image: a descriptor meets its look-alikes there
  // more often than its landmark, and projecting stops being a search.
  Param<double> max_search_radius{this, "max_search_radius", 100.0, "px",
                                  "largest window around a landmark's projection; when the "
                                  "prediction's covariance spreads most visible landmarks wider, "
                                  "the frame is placed by descriptor matching without the "
                                  "prediction first",
                                  Range{0.5, 1e5}};
  Param<int> max_hamming{this, "max_hamming", 50, "bits",
                         "descriptor check: larger Hamming distances are no match", Range{0, 4096}};
  Param<double> ratio{this, "ratio", 1.0, "",
                      "a match's distance must be below this times the second best within the "
                      "radius (1: off)",
                      Range{0.1, 1.0}};
  Param<double> scale_tolerance{this, "scale_tolerance", 1.5, "",
                                "pyramid keypoints: a keypoint's scale may differ from the "
                                "landmark's predicted one by this factor either way (a corner "
                                "fires at neighbouring levels, 1.2 apart, and the prediction "
                                "carries the depth's error); 0: not checked",
                                Range{0, 100}};
  Param<bool> use_depth{this, "use_depth", true, "",
                        "add the inverse-depth residual of keypoints with depth"};
  Param<bool> landmark_uncertainty{
      this, "landmark_uncertainty", false, "",
      "weigh each residual by the landmark's position covariance projected into the image as "
      "well as by the keypoint's own noise (a map landmark triangulated from one noisy depth is "
      "not an exact point: without it, hundreds of correlated landmark errors outweigh a "
      "second cue)"};
  Param<std::string> kernel{this, "kernel", "cauchy", "", "robust kernel",
                            Choices{{"none", "huber", "cauchy", "tukey"}}};
  Param<double> kernel_scale{this, "kernel_scale", 2.0, "sigma",
                             "kernel scale in units of each residual's standard deviation",
                             Range{1e-3, 1e3}};

  Param<int> recover_max_hamming{this, "recover_max_hamming", 64, "bits",
                                 "recovery (all-against-all matching of keypoints with depth and "
                                 "landmarks): larger Hamming distances are no match",
                                 Range{0, 4096}};
  Param<double> recover_ratio{this, "recover_ratio", 0.8, "",
                              "recovery: a match's distance must be below this times the second "
                              "best over the whole map (1: off)",
                              Range{0.1, 1.0}};
  Param<int> recover_min_inliers{this, "recover_min_inliers", 12, "",
                                 "recovery: fewer 3D-3D RANSAC inliers propose no pose",
                                 Range{3, 1000000}};

  ReprojectionSlice();
  ~ReprojectionSlice() override;
  void configure() override;
  void beginSolve() override { round_ = 0; }
  void associate(const Pose& t) override;
  void linearize(const Pose& t, NormalEquations<S>& eq) const override;
  /// False when the prediction's covariance spreads most visible landmarks' projections beyond
  /// max_search_radius.
  bool priorCovered() const override { return prior_covered_; }
  /// Wide-baseline recovery: descriptor matching of the keypoints with depth against the whole
  /// landmark map, 3D-3D RANSAC (point_registration.h); the robot pose it implies, or none.
  std::optional<Pose> recoverPose() override;

  /// The pairs of the last association.
  const std::vector<LandmarkMatch>& matches() const { return matches_; }
  /// frames, alignment_s (association and factors), matches_per_frame (at the solution),
  /// recoveries_tried, recoveries (a pose proposed) and recovery_s.
  std::vector<Statistic> statistics() const override;

 protected:
  bool prepare(const AlignContext<S>& context) override;

 private:
  // Each landmark's window beyond refine_radius at the prediction [px].
  void spreadWindows(const AlignContext<S>& context);
  FeatureGrid grid_;
  std::vector<LandmarkMatch> matches_;
  std::vector<double> spread_;
  bool prior_covered_ = true;
  std::unique_ptr<RobustKernel> kernel_;
  std::string made_kernel_;
  double made_scale_ = -1;
  int round_ = 0;
  uint64_t frames_ = 0, matched_ = 0, recoveries_tried_ = 0, recoveries_ = 0;
  mutable double time_s_ = 0;
  double recovery_s_ = 0;
};

/// "sdk.LandmarkMapSlice2D/3D": merges a FeatureSet into the local map's LandmarkMap: matched
/// landmarks are refined (information-weighted fusion of the positions) and take the newest
/// descriptor, unmatched keypoints with depth become landmarks with a new track id, landmarks
/// found in too few of the frames they projected into are pruned. Each landmark keeps the
/// reference distance of its last observation (distance times the keypoint's pyramid scale).
template <class S>
class LandmarkMapSlice final : public TrackerSlice<S>,
                               public HandoverSlice<S>,
                               public RefiningSlice<S>,
                               public StatisticsSource {
 public:
  using Pose = typename S::Pose;
  Input<FeatureSet> measurement{this, Container::measurement, "measurement", "features",
                                "keypoints to merge"};
  Output<LandmarkMap> scene{this, Container::scene, "scene", "landmarks",
                            "local map's landmarks to merge into"};
  Param<double> match_radius{this, "match_radius", 3.0, "px",
                             "association radius at the aligned pose", Range{0.5, 1000}};
  Param<int> max_hamming{this, "max_hamming", 50, "bits",
                         "descriptor check: larger Hamming distances are no match", Range{0, 4096}};
  Param<double> scale_tolerance{this, "scale_tolerance", 1.5, "",
                                "pyramid keypoints: as the reprojection slice's (0: not checked)",
                                Range{0, 100}};
  Param<double> fusion_gate{this, "fusion_gate", 11.34, "chi2",
                            "a matched point farther than this squared Mahalanobis distance from "
                            "its landmark is not fused (default: chi-square 99 % for 3 dof)",
                            Range{0, 1e9}};
  Param<double> max_depth{this, "max_depth", 0.0, "m",
                          "keypoints farther than this make no new landmark (0: any depth)",
                          Range{0, 1e6}};
  Param<int> prune_after{this, "prune_after", 4, "frames",
                         "a landmark is judged once it projected into this many frames",
                         Range{1, 1000000}};
  Param<double> min_found_ratio{this, "min_found_ratio", 0.3, "",
                                "judged landmarks matched in fewer of the frames they projected "
                                "into are pruned",
                                Range{0, 1}};
  Param<int> bundle_frames{this, "bundle_frames", 0, "frames",
                           "a local bundle adjustment refines the landmarks the map's last this "
                           "many frames observed and those frames' poses, the frame just "
                           "merged's included, with the observations of the twice as many "
                           "frames before (fixed; a planar robot's poses stay as tracked); 0: "
                           "none",
                           Range{0, 1000}};
  Param<int> bundle_every{this, "bundle_every", 5, "frames",
                          "frames between two bundle adjustments", Range{1, 1000000}};

  /// On a split: the landmarks frame `seq` matched or created (their fused positions,
  /// covariances, track ids and counters) move into the new map's frame.
  void handOver(const PropertyContainer& previous, PropertyContainer& next, const Pose& origin,
                uint64_t seq) override;

  /// After a bundle adjustment, the frame just merged as the bundle placed it.
  std::optional<Pose> refinedPose() const override { return refined_; }

  /// Counters of the last merge: matched landmarks, new landmarks, pruned landmarks.
  size_t lastMatched() const { return last_matched_; }
  size_t lastCreated() const { return last_created_; }
  size_t lastPruned() const { return last_pruned_; }
  /// frames, merge_s, per frame: matched, created, pruned and the local map's landmarks.
  std::vector<Statistic> statistics() const override;

 protected:
  void integrate(const MergeContext<S>& context) override;

 private:
  // Records the frame's observations (keypoint, landmark track id) and adjusts the bundle.
  void bundle(const MergeContext<S>& context, const FeatureSet& f, LandmarkMap& map,
              const std::vector<std::pair<size_t, uint64_t>>& observed);
  FeatureGrid grid_;
  std::vector<LandmarkMatch> matches_;
  std::vector<bool> visible_;
  // The frames a bundle keeps, in windows: the last window's poses move, the older stay.
  static constexpr size_t kBundleHistory = 3;
  std::vector<BundleFrame> bundle_;          // the current map's last frames
  const LandmarkMap* bundle_map_ = nullptr;  // the map they belong to
  uint64_t bundle_revision_ = 0;             // its revision when this slice last changed it
  std::optional<Pose> refined_;              // the last frame as the last bundle placed it
  uint64_t bundles_ = 0;
  double bundle_s_ = 0;
  uint64_t next_id_ = 0;
  size_t last_matched_ = 0, last_created_ = 0, last_pruned_ = 0;
  uint64_t frames_ = 0, matched_ = 0, created_ = 0, pruned_ = 0, landmarks_ = 0;
  double time_s_ = 0;
};

extern template struct LandmarkReprojection<Space2D>;
extern template struct LandmarkReprojection<Space3D>;
extern template class ReprojectionSlice<Space2D>;
extern template class ReprojectionSlice<Space3D>;
extern template class LandmarkMapSlice<Space2D>;
extern template class LandmarkMapSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
