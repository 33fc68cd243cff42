#pragma once
// The loop search (SDK-private): which closed maps wait for it, the detector -> validator chain
// on a snapshot of the graph, and the back-end thread it may run on.
#include <functional>
#include <future>
#include <utility>
#include <vector>

#include "modules/graph/component_join.h"
#include "modules/graph/pose_graph.h"
#include "plugslam/configurable.h"
#include "plugslam/loop_closure.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// One search: queries against a snapshot of the graph, and what it found.
struct LoopJob {
  GraphView view;
  std::vector<int64_t> queries;
  bool final_pass = false;  // the final detectors over every map this run added
  bool join_by_estimate = true;  // candidates from the estimate may join components
  // When set, each map's chain (session) component: only pairs of different chains are tried
  // (sessions restored together already hold their own loops).
  std::vector<int> chains;
  std::vector<std::pair<int64_t, int64_t>> linked;  // (newer, older) pairs to skip, sorted
  JoinRule join;  // when loops join components whose relative pose is unknown
  std::vector<std::pair<int, int>> joined;  // component pairs this job joined
  int dof = 3;                     // of the closures' information
  double information_scale = 1.0;  // applied to the closures' information
  std::vector<GraphEdge> closures;  // validated, in order
  uint64_t candidates = 0, rejections = 0;
  double detection_time = 0, validation_time = 0;  // seconds
};

/// Runs the loop detectors and the chain of validators over closed maps.
class LoopSearch {
 public:
  LoopSearch(const SlotList<LoopDetector>& online, const SlotList<LoopDetector>& final_detectors,
             const SlotList<LoopValidator>& validators, const Param<bool>& join_by_estimate,
             std::function<JoinRule()> join_rule);
  ~LoopSearch();

  /// A closed map waits for the search.
  void enqueue(int64_t query) { queued_.push_back(query); }
  /// Closed maps waiting.
  size_t queued() const { return queued_.size(); }
  /// A job for every waiting map (the queue empties) on a snapshot of `graph`.
  LoopJob take(const PoseGraph& graph, double information_scale);
  /// The pairs `graph`'s loops ever closed, newer map first, sorted (a job's `linked`); those
  /// the odometry audit rejected only with `audited`.
  static std::vector<std::pair<int64_t, int64_t>> linkedPairs(const PoseGraph& graph,
                                                              bool audited);
  /// A job for the final detectors over every map this run added, on the current estimate,
  /// skipping the pairs ever closed (but those the odometry audit rejected).
  LoopJob finalPass(const PoseGraph& graph, double information_scale) const;
  /// Runs the detectors (online or final) and the validators over the job's queries: the only
  /// user of them. Loops joining components of unknown relative pose wait for agreement
  /// (ComponentJoin) across jobs; jobs run one at a time.
  void run(LoopJob& job);

  /// Starts a job on the back-end thread.
  void start(LoopJob job);
  /// True while a started job was not collected.
  bool running() const { return searching_.valid(); }
  /// True when the started job has finished.
  bool ready() const;
  /// Waits for the started job and returns it.
  LoopJob collect() { return searching_.get(); }

 private:
  const SlotList<LoopDetector>& online_;
  const SlotList<LoopDetector>& final_;
  const SlotList<LoopValidator>& validators_;
  const Param<bool>& join_by_estimate_;
  std::function<JoinRule()> join_rule_;
  ComponentJoin joins_;
  std::vector<int64_t> queued_;
  std::future<LoopJob> searching_;
};

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
