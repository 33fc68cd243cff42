#pragma once
// The consistency selection of loops (SDK-private type "sdk.ConsistencyFilter"): the loops
// closed within a window of travel are re-decided together, keeping the largest set of mutually
// consistent ones (pairwise consistency maximization).
#include "plugslam/graph_edge.h"
#include "modules/graph/loop_filter.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// Keeps the largest mutually consistent set of recent loops ("sdk.ConsistencyFilter").
class ConsistencyFilter : public LoopFilter {
 public:
  Param<double> translation{
      this, "translation", 0.3, "m",
      "two loops agree when the cycle they close with the odometry errs less than this...",
      Range{0, 1e6}};
  Param<double> rotation{this, "rotation", 0.1, "rad", "...and less than this in rotation",
                         Range{0, 10}};
  Param<double> drift{this, "drift", 0.02, "",
                      "plus this fraction of the odometry path inside the cycle", Range{0, 10}};
  Param<double> window{this, "window", 30.0, "m",
                       "loops closed within this much travel are checked against each other; "
                       "the largest mutually consistent set is kept",
                       Range{0, 1e9}};
  Param<double> weak_edge_sigmas{
      this, "weak_edge_sigmas", 3.0, "",
      "a cycle whose odometry legs run through weak edges (GraphSlam's weak_edge_ratio) may err "
      "by this many of their std. devs more (rotation; translation plus rotation times the "
      "legs' path); 0: such cycles are no evidence either way and their loops are not checked "
      "against each other",
      Range{0, 1e6}};

  void loopsAdded(PoseGraph& graph) override;
  /// True when loops `a` and `b` agree through the graph's current estimate.
  bool consistent(const PoseGraph& graph, const GraphEdge& a, const GraphEdge& b) const;
};

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
