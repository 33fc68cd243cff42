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
  Param<double> spacing{this, "spacing", 0.0, "m",
                        "candidates kept are at least this much path apart (spreads them over "
                        "the visits of a place; 0: the closest whatever their path)",
                        Range{0, 1e9}};
  std::vector<LoopCandidate> detect(const GraphView& view, const LocalMap& query) override;
};

/// Joins one local map's scene into another's frame; the cue plugin knows how (e.g.
/// "laser2d.CloudMerger"). Validators use it to look at a map's neighbourhood at once.
class SceneMerger : public Configurable {
 public:
  static constexpr const char* kKind = "SceneMerger";
  ~SceneMerger() override;
  /// Appends the cues of `from`, moved by `pose` (from's frame in into's frame), to the cues of
  /// the same names in `into` (adding those `into` lacks); cues it does not know are left alone.
  virtual void append(PropertyContainer& into, const PropertyContainer& from,
                      const Eigen::Isometry3d& pose) = 0;
};

/// Ids of the maps around map `id` along the path, nearest first: the maps of the same chain
/// (each split from the one before) whose path length differs from `id`'s by at most `length`,
/// older than `before`, and at least `min_gap` of path before map `before` (so that a query's
/// own recent path never enters its candidate's neighbourhood). `id` itself is not included.
std::vector<int64_t> pathNeighbours(const GraphView& view, int64_t id, double length,
                                    int64_t before, double min_gap);

/// Aligns the query map's scene to the candidate's and checks the result
/// ("sdk.AlignmentValidator2D/3D"). With `neighbourhood` set, the candidate's scene is joined with
/// those of the maps next to it along the path (placed by the current estimate), so that one
/// facade of a repetitive scene cannot pass for another: the query must fit the larger view.
template <class S>
class AlignmentValidator : public ViewLoopValidator {
 public:
  AlignmentValidator();
  ~AlignmentValidator() override;
  Slot<MultiAligner<S>> aligner{this, "aligner", std::string("sdk.MultiAligner") + S::kSuffix,
                                "aligns the query's scene (as measurement) to the candidate's"};
  Param<double> neighbourhood{
      this, "neighbourhood", 0.0, "m",
      "also align against the maps within this path length of the candidate (either way, "
      "placed by the current estimate, joined by `merger`); 0: the candidate's map alone",
      Range{0, 1e6}};
  Param<double> query_neighbourhood{
      this, "query_neighbourhood", 0.0, "m",
      "also join the query's older maps within this path length into the query (map-to-map; "
      "overlap is then over the larger query); 0: the query's map alone",
      Range{0, 1e6}};
  Slot<SceneMerger> merger{this, "merger", "",
                           "joins a neighbour's scene into the candidate's or query's; required "
                           "when a neighbourhood is set"};
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
  bool validateInView(const GraphView& view, const LocalMap& candidate, const LocalMap& query,
                      const Eigen::Isometry3d& guess, LoopClosure& closure,
                      std::string& reason) override;

 private:
  // The checks on two scenes (the candidate's and the query's, possibly widened).
  bool check(const PropertyContainer& candidate, const PropertyContainer& query,
             const Eigen::Isometry3d& guess, LoopClosure& closure, std::string& reason);
  // `map`'s scene joined with its neighbours' (`length` of path, older than `before`).
  PropertyContainer widened(const GraphView& view, const LocalMap& map, double length,
                            int64_t before, double min_gap);
};

extern template class AlignmentValidator<Space2D>;
extern template class AlignmentValidator<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
