#pragma once
// The global optimizer of the pose graph (SDK-private): a snapshot of the graph (every map's
// origin, the edges, a weak anchor per later graph component) solved by Gauss-Newton or
// Levenberg-Marquardt, inline or on the back-end thread.
#include <Eigen/Geometry>
#include <future>
#include <string>
#include <vector>

#include "modules/graph/pose_graph.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// One optimization as the back-end applies it and the loop filters see it; poses are the pose
/// space's (2D poses embedded in 3D), by map id.
struct Solution {
  size_t nodes = 0;                     ///< maps in the snapshot
  std::vector<GraphEdge> edges;         ///< the edges it solved over
  std::vector<Eigen::Isometry3d> before;  ///< every map's origin it started from
  std::vector<Eigen::Isometry3d> after;   ///< and where it put them
  double seconds = 0, chi2 = 0;
  bool ok = false;
};

/// What the odometry audit may do with the graph: solve trials, adopt one, optimize.
class GraphOptimizer {
 public:
  virtual ~GraphOptimizer() = default;
  /// The current origins as the optimizer starts from them.
  virtual std::vector<Eigen::Isometry3d> estimate() const = 0;
  /// Solves the graph with `edges` instead of its own, from the current estimate, without
  /// applying the result (its time counts in the back-end's optimization time).
  virtual Solution trial(std::vector<GraphEdge> edges) = 0;
  /// Applies a trial as the graph's estimate (one optimization); true when a filter then
  /// rejected loops, so that the graph needs optimizing again.
  virtual bool adopt(const Solution& trial) = 0;
  /// Optimizes the graph now and applies it, again while filters reject loops.
  virtual void optimize() = 0;
};

/// Solver settings of the global optimization.
struct OptimizerSettings {
  std::string solver = "gn";        ///< "gn" or "lm"
  int iterations = 20;              ///< per optimization
  std::string loop_kernel = "none"; ///< robust kernel on loop edges
  double loop_kernel_scale = 1.0;
};

/// Builds and solves the pose graph of one pose space.
template <class S>
class GlobalOptimizer {
 public:
  using Pose = typename S::Pose;
  /// A snapshot of the graph to solve: the back-end thread never reads the live graph.
  struct Problem {
    OptimizerSettings settings;
    std::vector<size_t> anchors;  // first maps of later graph components (sessions, resets)
    std::vector<Pose> before;
    std::vector<GraphEdge> edges;
  };

  /// The snapshot of `graph` with `edges` (its own when not given).
  static Problem snapshot(const PoseGraph& graph, const OptimizerSettings& settings,
                          std::vector<GraphEdge> edges);
  /// Solves a snapshot (thread-safe: reads nothing else).
  static Solution solve(const Problem& problem);

  /// Starts solving on the back-end thread.
  void start(Problem problem);
  /// True while a solve started and was not collected.
  bool running() const { return running_.valid(); }
  /// True when the started solve has finished.
  bool ready() const;
  /// Waits for the started solve and returns it.
  Solution collect() { return running_.get(); }
  ~GlobalOptimizer();

 private:
  std::future<Solution> running_;
};

extern template class GlobalOptimizer<Space2D>;
extern template class GlobalOptimizer<Space3D>;

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
