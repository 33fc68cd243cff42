#pragma once
// The SDK's generic loop detector (proximity in the current estimate, gated by the drift the
// path since the candidate may have accumulated) and loop validator (align the two maps' scenes
// with a Multi-Aligner and check overlap and residual).
#include "plugslam/graph_slam.h"
#include "plugslam/multi_aligner.h"

namespace plugslam {
inline namespace abi_v1 {

/// Proposes maps whose origin is near the query's in the current estimate ("sdk.ProximityDetector").
class ProximityDetector : public LoopDetector {
 public:
  Param<double> radius{this, "radius", 2.0, "m", "search radius with no drift", Range{0, 1e6}};
  Param<double> drift{this, "drift", 0.05, "",
                      "radius grows by this fraction of the path travelled since the candidate",
                      Range{0, 10}};
  Param<double> max_radius{this, "max_radius", 10.0, "m", "cap on the grown radius", Range{0, 1e6}};
  Param<double> min_travel{this, "min_travel", 10.0, "m",
                           "ignore maps fewer metres back along the path", Range{0, 1e9}};
  Param<int> max_candidates{this, "max_candidates", 3, "", "closest candidates kept",
                            Range{1, 1000}};
  std::vector<LoopCandidate> detect(const GraphView& view, const LocalMap& query) override;
};

/// Aligns the query map's scene to the candidate's and checks the result
/// ("sdk.AlignmentValidator2D/3D").
template <class S>
class AlignmentValidator : public LoopValidator {
 public:
  AlignmentValidator();
  ~AlignmentValidator() override;
  Slot<MultiAligner<S>> aligner{this, "aligner", std::string("sdk.MultiAligner") + S::kSuffix,
                                "aligns the query's scene (as measurement) to the candidate's"};
  Param<double> min_overlap{this, "min_overlap", 0.5, "",
                            "fraction of the query's elements that must be inliers", Range{0, 1}};
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
