#include "plugslam/alignment_validator.h"

namespace plugslam {
inline namespace abi_v1 {

template <class S>
AlignmentValidator<S>::AlignmentValidator() = default;
template <class S>
AlignmentValidator<S>::~AlignmentValidator() = default;

template <class S>
bool AlignmentValidator<S>::validate(const LocalMap& candidate, const LocalMap& query,
                                     const Eigen::Isometry3d& guess, LoopClosure& closure,
                                     std::string& reason) {
  if (!aligner || aligner->slices.empty()) {
    reason = "the validator's aligner has no slices";
    return false;
  }
  // The query's scene plays the measurement: its cues have the names the slices bind to.
  Frame frame;
  frame.measurement = query.scene;
  const typename S::Pose g = S::from3D(guess);
  AlignResult<S> r = aligner->align(frame, candidate.scene, AlignContext<S>{g, g});
  if (!r.valid) {
    reason = "alignment failed (" + std::to_string(r.inliers) + " inliers; " +
             describeCues(r.cues) + ")";
    return false;
  }
  // Two different fractions: of the pairs the association made (a wrong pose pairs points too,
  // but few within the inlier band), and of all the query's elements (how much of the query the
  // candidate explains; known from the cues that count their candidates).
  const double ratio = r.inlierRatio();
  if (ratio < min_inlier_ratio()) {
    reason = "inlier ratio " + std::to_string(ratio) + " below " +
             std::to_string(min_inlier_ratio()) + " (" + describeCues(r.cues) + ")";
    return false;
  }
  const bool counted = r.candidates > 0;
  const double overlap = counted ? r.overlap() : ratio;
  if (counted && overlap < min_overlap()) {
    reason = "overlap " + std::to_string(overlap) + " below " + std::to_string(min_overlap()) +
             " (" + describeCues(r.cues) + ")";
    return false;
  }
  const double residual = r.inliers ? r.chi2 / r.inliers : 0;
  if (residual > max_residual()) {
    reason = "residual " + std::to_string(residual) + " above " + std::to_string(max_residual());
    return false;
  }
  const double correction = (S::to3D(r.pose).translation() - guess.translation()).norm();
  if (correction > max_correction()) {
    reason = "correction " + std::to_string(correction) + " m above " +
             std::to_string(max_correction());
    return false;
  }
  closure.edge.relative = S::to3D(r.pose);
  closure.edge.information = r.H;
  closure.overlap = overlap;
  closure.residual = residual;
  return true;
}

template class AlignmentValidator<Space2D>;
template class AlignmentValidator<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
