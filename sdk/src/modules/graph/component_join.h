#pragma once
// Joining graph components whose relative pose is unknown (SDK-private): a session mapped
// elsewhere, a run started anywhere, merged sessions. One validated loop between them may still
// be a look-alike place (a corridor of another building), so their loops are held until loops
// from different query maps put the two components in the same relative pose; then all of
// those join at once. A robot localizing from an unknown start is known to be inside the saved
// maps: the true place competes with any look-alike there, and one loop suffices.
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "plugslam/graph_edge.h"
#include "plugslam/loop_closure.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// When loops that join two components agree (GraphSlam's join_* parameters).
struct JoinRule {
  int agreeing = 2;             ///< loops from different query maps that must agree
  int agreeing_localizing = 1;  ///< the same while the view is `localizing` (into map 0's component)
  double translation = 0.5;     ///< [m] agreement of the components' relative pose...
  double rotation = 0.05;       ///< [rad] ...
  double drift = 0.05;          ///< ...grown by this fraction of the path between the queries
  double angular_drift = 0.01;  ///< [rad/m] ...and this per metre of it
  size_t max_held = 64;         ///< loops held per pair of components
};

/// Holds the loops that would join components until enough agree.
class ComponentJoin {
 public:
  /// Decides on validated loop `edge` (from = older map, to = query) seen in `view`: the loops
  /// to add now (none while it is held; it and the loops it agrees with once enough agree; it
  /// alone when both maps are in one component). `joined` lists the component pairs joined
  /// since `view` was taken, whose later loops pass at once.
  std::vector<GraphEdge> decide(const GraphView& view, const GraphEdge& edge, const JoinRule& rule,
                                std::vector<std::pair<int, int>>& joined);

 private:
  struct Held {
    GraphEdge edge;
    double travelled;           // path at its query map
    Eigen::Isometry3d query;    // its query map's origin, in the query's component's world
    Eigen::Isometry3d found;    // where the loop puts that origin in the other component's world
  };
  std::map<std::pair<int, int>, std::vector<Held>> held_;  // (query's, other) component
};

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
