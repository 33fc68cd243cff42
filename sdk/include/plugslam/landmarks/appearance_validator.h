#pragma once
// The landmark cue's geometric loop check: the two maps' landmark descriptors are matched
// all against all (no pose prior, so a drifted estimate does not matter) and a rigid transform is
// found by 3D-3D RANSAC (plugslam/landmarks/point_registration.h). Look-alike places (repeated
// brick or facade textures) match many descriptors but few of them agree on one rigid motion.
// Chain it before sdk.AlignmentValidator3D, which refines the pose with the cue's own factors.
#include <atomic>
#include <string>
#include <vector>

#include "plugslam/loop_closure.h"
#include "plugslam/statistics.h"

namespace plugslam {
inline namespace abi_v1 {

/// Accepts a loop when the maps' landmarks register by descriptor matches and rigid RANSAC
/// ("sdk.AppearanceValidator"); counts its rejections by reason (run.json statistics).
class AppearanceValidator : public LoopValidator, public StatisticsSource {
 public:
  Param<std::string> scene{this, "scene", "landmarks", "",
                           "scene entry of the landmark cue (LandmarkMap)"};
  Param<int> max_hamming{this, "max_hamming", 50, "bits",
                         "Hamming distance of a descriptor match (ORB's same-corner bound)",
                         Range{0, 4096}};
  Param<double> ratio{this, "ratio", 0.8, "",
                      "best / second-best match distance must stay below this (a corner of a "
                      "repeated texture matches several equally well: no match)",
                      Range{0, 1}};
  Param<int> min_inliers{this, "min_inliers", 20, "",
                         "landmarks that must agree on the rigid motion (three fix a pose; "
                         "twenty spread over a map make a chance agreement implausible)",
                         Range{3, 1000000}};
  Param<double> min_inlier_ratio{this, "min_inlier_ratio", 0.3, "",
                                 "fraction of the descriptor matches that must be inliers (a "
                                 "look-alike place matches many, of which few agree)",
                                 Range{0, 1}};
  Param<double> inlier_chi2{this, "inlier_chi2", 11.34, "",
                            "squared Mahalanobis distance of an inlier under both landmarks' "
                            "covariances (chi-square 99 % for 3 dof)",
                            Range{0, 1e12}};
  Param<int> iterations{this, "iterations", 2000, "", "RANSAC samples at most", Range{1, 1000000}};
  Param<double> max_correction{this, "max_correction", 0.0, "m",
                               "max distance between the estimate and the registered pose (0: "
                               "off; appearance finds loops whatever the drift)",
                               Range{0, 1e9}};

  bool validate(const LocalMap& candidate, const LocalMap& query, const Eigen::Isometry3d& guess,
                LoopClosure& closure, std::string& reason) override;
  /// Checks and rejections by reason: checked, accepted, rejected_no_landmarks,
  /// rejected_few_matches, rejected_few_inliers, rejected_inlier_ratio, rejected_correction.
  std::vector<Statistic> statistics() const override;

 private:
  enum Outcome { kAccepted, kNoLandmarks, kFewMatches, kFewInliers, kInlierRatio, kCorrection,
                 kOutcomes };
  bool count(Outcome o);
  std::atomic<uint64_t> counts_[kOutcomes] = {};  // validate() runs on the back-end thread
};

}  // namespace abi_v1
}  // namespace plugslam
