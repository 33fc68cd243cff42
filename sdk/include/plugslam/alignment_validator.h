#pragma once
// The SDK's generic loop validator: align the two maps' scenes with a Multi-Aligner and check
// overlap, residual and correction.
#include "plugslam/loop_closure.h"
#include "plugslam/multi_aligner.h"

namespace plugslam {
inline namespace abi_v1 {

/// Aligns the query map's scene to the candidate's and checks the result
/// ("sdk.AlignmentValidator2D/3D").
template <class S>
class AlignmentValidator : public LoopValidator {
 public:
  AlignmentValidator();
  ~AlignmentValidator() override;
  Slot<MultiAligner<S>> aligner{this, "aligner", std::string("sdk.MultiAligner") + S::kSuffix,
                                "aligns the query's scene (as measurement) to the candidate's"};
  Param<double> min_inlier_ratio{this, "min_inlier_ratio", 0.5, "",
                                 "fraction of the associated pairs (factors) that must be inliers",
                                 Range{0, 1}};
  Param<double> min_overlap{this, "min_overlap", 0.0, "",
                            "fraction of the query's elements that must be inliers, over the "
                            "cues that count them (0: off)",
                            Range{0, 1}};
  Param<double> max_residual{this, "max_residual", 1.0, "",
                             "max robust chi2 per inlier at the solution", Range{0, 1e12}};
  Param<double> max_correction{this, "max_correction", 5.0, "m",
                               "max distance between the guess and the solution", Range{0, 1e6}};
  bool validate(const LocalMap& candidate, const LocalMap& query, const Eigen::Isometry3d& guess,
                LoopClosure& closure, std::string& reason) override;
};

extern template class AlignmentValidator<Space2D>;
extern template class AlignmentValidator<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
