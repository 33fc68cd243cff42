#pragma once
// Loop closing's two contracts (seed, section III): a loop detector proposes older local maps
// that may show the same place as a newly closed one; loop validators, a chain, check each
// proposal on the data. GraphSlam runs them, inline or on its back-end thread.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/local_map.h"
#include "plugslam/graph_edge.h"

namespace plugslam {
inline namespace abi_v1 {

/// What a loop detector sees of the graph: every node with its origin when the view was taken.
/// Detectors may run on the back-end thread while the front-end moves the maps: they read the
/// origins here, never maps[i]->origin.
struct GraphView {
  std::vector<std::shared_ptr<const LocalMap>> maps;  ///< by id (maps[i]->id == i)
  std::vector<Eigen::Isometry3d> origins;  ///< each map's origin in the world, by id
  std::vector<double> travelled;  ///< path length from map 0 to each map's origin [m]
  /// Path length at the newest map that closed a loop so far (-1: none yet).
  double last_loop_travelled = -1;
  /// Each map's component: maps tied by odometry or by an active loop share one; a session or
  /// a tracker reset starts a new one, whose origins say nothing of where it lies in the others
  /// until a loop joins them. Empty: one component.
  std::vector<int> components;
  /// Set while a run localizes in restored maps from an unknown start (GraphBackend::relocalize):
  /// the query's place is among map 0's component, so a look-alike there must outscore the true
  /// place, and the caller searches only when the robot's view changed.
  bool localizing = false;
  /// The component of map `id`.
  int component(int64_t id) const {
    return components.empty() ? 0 : components[static_cast<size_t>(id)];
  }
  /// Origin of map `b` in map `a`'s frame, from the snapshot.
  Eigen::Isometry3d relative(int64_t a, int64_t b) const {
    return origins[static_cast<size_t>(a)].inverse() * origins[static_cast<size_t>(b)];
  }
};

/// A loop candidate proposed by a detector.
struct LoopCandidate {
  int64_t id = -1;  ///< the older map
  /// True when the detector matched the data and `relative` is its estimate; otherwise the
  /// validators start from the current estimate.
  bool matched = false;
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  ///< query origin in `id`'s frame
  double score = 0;  ///< the detector's own score (for logs)
  /// True when found without the estimate (place recognition): the only kind of candidate that
  /// may join graph components whose relative pose is unknown (GraphSlam's join_by_estimate).
  bool global = false;
};

/// Proposes older local maps that may show the same place as `query`.
class LoopDetector : public Configurable {
 public:
  static constexpr const char* kKind = "LoopDetector";
  ~LoopDetector() override;
  /// Candidates for `query` (which is view.maps[query.id]); may run on the back-end thread.
  virtual std::vector<LoopCandidate> detect(const GraphView& view, const LocalMap& query) = 0;
};

/// A checked loop closure.
struct LoopClosure {
  GraphEdge edge;        ///< from = candidate (older), to = query
  double overlap = 0;    ///< fraction of the query explained by the candidate
  double residual = 0;   ///< mean squared residual per inlier
};

/// Accepts or rejects a proposed closure by looking at the data.
class LoopValidator : public Configurable {
 public:
  static constexpr const char* kKind = "LoopValidator";
  ~LoopValidator() override;
  /// Checks `query` against `candidate` starting from `guess` (query origin in the candidate's
  /// frame). On success fills `closure` (its relative pose and information) and returns true;
  /// otherwise sets `reason`.
  virtual bool validate(const LocalMap& candidate, const LocalMap& query,
                        const Eigen::Isometry3d& guess, LoopClosure& closure,
                        std::string& reason) = 0;
};

}  // namespace abi_v1
}  // namespace plugslam
