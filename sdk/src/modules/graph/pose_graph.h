#pragma once
// The back-end's pose graph (SDK-private): local maps as nodes with their path length and graph
// component, the tracker's odometry edges with the weak ones (tracking failures) marked, and every
// validated loop with what the loop filters decided about it.
#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "plugslam/graph_edge.h"
#include "plugslam/local_map.h"
#include "plugslam/loop_closure.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// A validated loop closure and the filters' verdict on it.
struct Loop {
  GraphEdge edge;
  bool active = true;
  bool vetoed = false;   ///< rejected for good (residual veto, odometry audit): never restored
  bool audited = false;  ///< rejected by the odometry audit: a final pass may close its pair again
};

/// A symmetric positive-definite version of an information matrix (tiny eigenvalues lifted), so
/// a degenerate alignment cannot make the global system singular; identity when malformed.
Eigen::MatrixXd conditionedInformation(const Eigen::MatrixXd& h, int dof);
/// The largest translation and rotation variances of an edge, from its information (identity
/// when it has the wrong size).
std::pair<double, double> maxVariances(const Eigen::MatrixXd& information, int dof);
/// How far an edge's measurement is from the relative pose of its two maps at `from` and `to`
/// (identity when they agree).
Eigen::Isometry3d edgeError(const GraphEdge& e, const Eigen::Isometry3d& from,
                            const Eigen::Isometry3d& to);

/// Nodes, edges and loops of the back-end. The maps are shared with the pipeline; the graph
/// owns their origins.
class PoseGraph {
 public:
  /// `dimension` 2 or 3; an odometry edge whose rotation std. dev. is `weak_edge_ratio` times
  /// the median of the recent ones is weak.
  PoseGraph(int dimension, double weak_edge_ratio);

  int dimension() const { return dimension_; }
  /// Tangent-space size of an edge's information (3 or 6).
  int dof() const { return dimension_ == 2 ? 3 : 6; }
  /// Sets the weak-edge ratio for edges added from now on.
  void setWeakEdgeRatio(double ratio) { weak_edge_ratio_ = ratio; }

  /// Adds a new local map and the odometry edge from its predecessor (information conditioned
  /// and scaled by `information_scale`). Throws Error when maps arrive out of order.
  void addMap(const std::shared_ptr<LocalMap>& map, double information_scale);
  /// Restores a saved graph into an empty one (see GraphBackend::restore).
  void restore(const std::vector<std::shared_ptr<LocalMap>>& maps,
               const std::vector<GraphEdge>& edges);
  /// Adds a validated loop, active.
  void addLoop(const GraphEdge& edge) { loops_.push_back(Loop{edge, true}); }

  size_t size() const { return maps_.size(); }
  const std::vector<std::shared_ptr<LocalMap>>& maps() const { return maps_; }
  /// Maps that came from restore() (ids below it): the restored session's.
  size_t restoredMaps() const { return restored_maps_; }
  /// Restored maps from `first` on count as this run's (the final pass queries them).
  void treatAsNew(size_t first) { restored_maps_ = std::min(restored_maps_, first); }
  /// Loops that came from restore() (the first ones of loops()).
  size_t restoredLoops() const { return restored_loops_; }
  /// Path length from map 0 to each map's origin (graph components apart by a large gap).
  const std::vector<double>& travelled() const { return travelled_; }
  /// Graph component of each map (sessions, tracker resets start new ones).
  const std::vector<int>& components() const { return components_; }
  /// Summed translation / rotation variances of the weak odometry edges from each map's
  /// component's first map to it (a leg's variance is a difference of two sums).
  const std::vector<double>& weakVarianceT() const { return weak_var_t_; }
  const std::vector<double>& weakVarianceR() const { return weak_var_r_; }
  /// The odometry edges, in the order their maps were added.
  const std::vector<GraphEdge>& odometry() const { return odometry_; }
  /// Every validated loop, active or not, in the order they were added.
  std::vector<Loop>& loops() { return loops_; }
  const std::vector<Loop>& loops() const { return loops_; }
  /// The odometry edges, then the active loops.
  std::vector<GraphEdge> edges() const;
  /// Origin of map `b` in map `a`'s frame at the current estimate.
  Eigen::Isometry3d relative(int64_t a, int64_t b) const {
    return maps_[a]->origin.inverse() * maps_[b]->origin;
  }
  /// A snapshot for the loop detectors.
  GraphView view() const;

 private:
  // Appends the next map's component and weak-edge variances (from `previous`, joined to it by
  // `odometry` when that is not null).
  void addChain(int64_t previous, const GraphEdge* odometry);
  // True when an odometry edge is far looser in rotation than the recent ones; remembers it.
  bool isWeak(const GraphEdge& odometry);

  int dimension_;
  double weak_edge_ratio_;
  std::vector<std::shared_ptr<LocalMap>> maps_;
  size_t restored_maps_ = 0, restored_loops_ = 0;
  std::vector<double> travelled_;
  std::vector<int> components_;
  std::vector<double> weak_var_t_, weak_var_r_;
  std::vector<double> recent_sigmas_;  // rotation std. dev. of the last odometry edges (a ring)
  size_t next_sigma_ = 0;
  std::vector<GraphEdge> odometry_;
  std::vector<Loop> loops_;
};

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
