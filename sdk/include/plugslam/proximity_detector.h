#pragma once
// The SDK's generic loop detector: proximity in the current estimate, through the drift gate.
#include "plugslam/drift_gate.h"
#include "plugslam/loop_closure.h"

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

}  // namespace abi_v1
}  // namespace plugslam
