#pragma once
// Loop filters: the checks a loop closure passes after validation, once it is part of the graph
// (one item of GraphSlam's `loop_filters` each): the pairwise-consistent selection of recent
// loops, the residual veto after each optimization, the odometry audit when the run ends.
#include <cstddef>

#include "plugslam/configurable.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {
class PoseGraph;
class GraphOptimizer;
struct Solution;
}  // namespace detail

/// A check on the loops of the pose graph. Filters work on the back-end's own state
/// (detail::PoseGraph), which the SDK keeps private, so this type is SDK-internal: its kinds
/// ("sdk.ConsistencyFilter", "sdk.ResidualVeto", "sdk.OdometryAudit") are chosen, ordered and
/// configured in YAML; a plugin cannot add one.
class LoopFilter : public Configurable {
 public:
  static constexpr const char* kKind = "LoopFilter";
  ~LoopFilter() override;
  /// The online loop search added loops (the newest last): may deactivate or restore loops.
  virtual void loopsAdded(detail::PoseGraph& graph);
  /// An optimization was applied to the graph: may reject loops for good; returns true when it
  /// did (the graph is then optimized again).
  virtual bool optimized(detail::PoseGraph& graph, const detail::Solution& solution);
  /// The run ends (after the final optimization, and after each final loop pass): may reject
  /// loops, optimizing through `optimizer`; returns the number of loops it rejected.
  virtual size_t runEnds(detail::PoseGraph& graph, detail::GraphOptimizer& optimizer);
};

}  // namespace abi_v1
}  // namespace plugslam
