#pragma once
// The odometry audit (SDK-private type "sdk.OdometryAudit"): when the run ends, an odometry edge
// the optimized graph stretches beyond what odometry can err is evidence of wrong loops; the
// loops that pull one side of it (a stretch of path between tracking failures) away from the
// rest are rejected when without them the edge holds.
#include <vector>

#include "plugslam/graph_edge.h"
#include "modules/graph/loop_filter.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// Rejects the loops that stretch odometry edges beyond their bounds ("sdk.OdometryAudit").
class OdometryAudit : public LoopFilter {
 public:
  Param<double> translation{
      this, "translation", 2.0, "m",
      "when the run ends, an odometry edge the optimized graph stretches by more than this (and "
      "`sigmas` of its std. dev.) is evidence of wrong loops: the loops joining the stretch of "
      "path on one side of it (between tracking failures) to the rest are rejected when without "
      "them the edge holds; of the two sides, the one whose removal leaves the odometry least "
      "bent (0 here and in rotation: no audit; remove the audit for data where the robot was "
      "carried, or a log jumps, between two maps)",
      Range{0, 1e6}};
  Param<double> rotation{this, "rotation", 0.5, "rad",
                         "...or turns it by more than this (0: rotation not audited)",
                         Range{0, 10}};
  Param<double> sigmas{this, "sigmas", 5.0, "",
                       "...and by more than this many of the edge's std. devs", Range{0, 1e6}};
  Param<double> reinstate_translation{
      this, "reinstate_translation", 0.1, "m",
      "a rejected loop whose error at the corrected graph is within this (a stretch's right "
      "loops next to its wrong ones)...",
      Range{0, 1e6}};
  Param<double> reinstate_rotation{
      this, "reinstate_rotation", 0.1, "rad",
      "...and this in rotation comes back (0 in both: none comes back; 0 in one: that one is "
      "not checked)",
      Range{0, 10}};

  size_t runEnds(PoseGraph& graph, GraphOptimizer& optimizer) override;

 private:
  // Strain of each of `odometry`'s edges at `estimate`: its error over its audit bound (> 1:
  // the edge is stretched beyond the bound).
  std::vector<double> strain(const std::vector<GraphEdge>& odometry,
                             const std::vector<Eigen::Isometry3d>& estimate, int dof) const;
};

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
