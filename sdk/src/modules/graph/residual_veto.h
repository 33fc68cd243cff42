#pragma once
// The residual veto (SDK-private type "sdk.ResidualVeto"): after each optimization, the loop
// that disagrees most with the optimized graph goes for good when its error is too large. A
// wrong loop alone in its consistency window has no other loop to disagree with, but the rest
// of the graph does.
#include "modules/graph/loop_filter.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// Rejects the loops the optimized graph disagrees with most ("sdk.ResidualVeto").
class ResidualVeto : public LoopFilter {
 public:
  Param<double> translation{
      this, "translation", 0.1, "m",
      "after each optimization the active loop that disagrees most with the optimized graph "
      "(and any at least 0.8 times as far off), if its error exceeds this (0: never)...",
      Range{0, 1e6}};
  Param<double> rotation{this, "rotation", 0.1, "rad",
                         "...or this in rotation (0: never), is rejected for good and the graph "
                         "re-optimized",
                         Range{0, 10}};

  bool optimized(PoseGraph& graph, const Solution& solution) override;
};

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
