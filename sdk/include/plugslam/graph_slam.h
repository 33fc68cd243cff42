#pragma once
// The graph back-end (seed, section III): local maps are pose-graph nodes, consecutive maps are
// joined by the tracker's relative pose, loop detectors propose closures between maps, loop
// validators check them by aligning the maps' scenes, loop filters keep the loops the graph
// agrees with, and a global optimizer corrects every map origin. Generic over 2D and 3D through
// the pose space, like the tracker. GraphSlam is a coordinator: its parts (pose graph, loop
// search, global optimizer) live in sdk/src/modules/graph/, out of this header.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/graph_edge.h"
#include "plugslam/local_map.h"
#include "plugslam/loop_closure.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

// The checks a loop passes once it is in the graph (sdk.ConsistencyFilter, sdk.ResidualVeto,
// sdk.OdometryAudit): internal to the SDK, since they work on the back-end's private state.
// YAML chooses and orders them through `loop_filters`; a plugin cannot add a kind.
class LoopFilter;

/// Counters of the back-end.
struct GraphStats {
  uint64_t nodes = 0, edges = 0;
  uint64_t candidates = 0;         ///< proposals by the detectors
  uint64_t loops_accepted = 0;     ///< this run's loops, validated and kept
  uint64_t loops_rejected = 0;     ///< refused this run by a validator or a loop filter
  uint64_t optimizations = 0;
  double optimization_time = 0;    ///< seconds, summed
  double detection_time = 0;       ///< seconds in the loop detectors, summed
  double validation_time = 0;      ///< seconds in the loop validators, summed
  double final_chi2 = 0;
  uint64_t loops_restored = 0;     ///< a restored session's loops still kept (not this run's)
};

/// The dimension-agnostic face of the back-end that the pipeline drives.
class GraphBackend : public Configurable {
 public:
  static constexpr const char* kKind = "GraphBackend";
  ~GraphBackend() override;
  /// 2 or 3.
  virtual int dimension() const = 0;
  /// A new local map started (its node and the edge from its predecessor are added).
  virtual void mapStarted(const std::shared_ptr<LocalMap>& map) = 0;
  /// A local map is complete: look for loops from it.
  virtual void mapClosed(const std::shared_ptr<LocalMap>& map) = 0;
  /// Applies finished back-end work to the maps' origins; true when origins moved.
  virtual bool poll() = 0;
  /// Waits for the back-end, optimizes once more and applies the result.
  virtual void finish() = 0;
  /// Every edge of the graph.
  virtual std::vector<GraphEdge> edges() const = 0;
  /// Counters so far.
  virtual GraphStats stats() const = 0;
  /// Restores a saved graph into an empty back-end: the maps (ids 0..n-1, in order, with their
  /// origins) and the edges exactly as edges() returned them. The default throws InputError.
  virtual void restore(const std::vector<std::shared_ptr<LocalMap>>& maps,
                       const std::vector<GraphEdge>& edges);
  /// Optimizes now, inline, and applies the result, e.g. before reading a pose a new loop
  /// changed. The default does nothing (a back-end whose estimate is always current).
  virtual void optimizeNow();
  /// Searches loops from restored maps `first`.. now, one map at a time, each search on the
  /// estimate the closures before it optimized (sessions restored together, to be merged);
  /// finish()'s final pass then queries them as this run's maps. The default throws InputError.
  virtual void searchRestored(int64_t first);
  /// Localization from an unknown start: searches loops from map `query` (the tracker's open
  /// map, its scene as it stands) inline, the view marked `localizing`, and applies and
  /// optimizes what it finds; returns the loops added. The default finds none.
  virtual size_t relocalize(int64_t query);
};

/// Pose-graph SLAM over local maps ("sdk.GraphSlam2D/3D"). Loop detection and validation, and
/// the optimization, run on back-end threads unless `deterministic` is set; their results are
/// applied at the first frame they are ready, or with `lockstep` at fixed map closings.
template <class S>
class GraphSlam : public GraphBackend {
 public:
  GraphSlam();
  ~GraphSlam() override;

  SlotList<LoopDetector> loop_detectors{this, "loop_detectors", "propose loop candidates"};
  SlotList<LoopValidator> validators{
      this, "validators",
      "every validator must accept a candidate; each starts from the pose the previous found"};
  SlotList<LoopFilter> loop_filters{
      this, "loop_filters",
      "checks on the validated loops once they are in the graph, in order (omitted: the three "
      "below; [] : none)",
      {"sdk.ConsistencyFilter", "sdk.ResidualVeto", "sdk.OdometryAudit"}};
  SlotList<LoopDetector> final_detectors{
      this, "final_detectors",
      "run once over every map this run added when it ends, on the optimized estimate (e.g. a "
      "wider proximity search than drift allows online); their validated closures join the "
      "graph (guarded by the validators and the filters' residual checks, not the consistency "
      "window) before a last optimization"};
  Param<int> final_rounds{this, "final_rounds", 1, "",
                          "final_detectors passes; each runs on the estimate the previous one "
                          "optimized (pairs its drift kept apart now align) and adds only new pairs",
                          Range{1, 100}};
  Param<bool> deterministic{this, "deterministic", false, "",
                            "search loops and optimize inline on the front-end thread "
                            "(bit-identical replays)"};
  Param<int> max_search_lag{this, "max_search_lag", 0, "",
                            "closed maps that may wait for the back-end's loop search; beyond "
                            "this the front-end waits for it (0: a map waits only while the "
                            "previous map's search still runs; larger lags search, and correct "
                            "large drift, on staler estimates when data comes faster than real "
                            "time)",
                            Range{0, 1000000}};
  Param<bool> join_by_estimate{
      this, "join_by_estimate", true, "",
      "graph components (a restored session and this run, a tracker reset) are assumed to lie "
      "where the estimate puts them (the run started where the session did): any detector may "
      "join them. false: their relative pose is unknown (a run started anywhere, merged "
      "sessions) and only candidates found without the estimate (place recognition) join them"};
  Param<int> join_agreeing{
      this, "join_agreeing", 2, "",
      "with join_by_estimate false, validated loops from this many query maps must put two "
      "components in the same relative pose before they join: one look-alike place must not "
      "weld two buildings together",
      Range{1, 100}};
  Param<int> join_agreeing_localizing{
      this, "join_agreeing_localizing", 1, "",
      "join_agreeing for a robot localizing from an unknown start (relocalize): it is among the "
      "saved maps, so a look-alike must outscore the true place in the detector's search",
      Range{1, 100}};
  Param<std::vector<double>> join_agreement{
      this, "join_agreement", {0.5, 0.05}, "m, rad",
      "two such loops agree when the components' relative pose one implies puts the other's "
      "query map within this of where that loop found it (a few grid cells)"};
  Param<double> join_drift{this, "join_drift", 0.05, "",
                           "the agreement's translation tolerance grows by this fraction of the "
                           "path between the two query maps: the tracker's drift between them",
                           Range{0, 1}};
  Param<double> join_angular_drift{
      this, "join_angular_drift", 0.01, "rad/m",
      "the agreement's rotation tolerance grows by this per metre of path between the two query "
      "maps: a tracker's heading drift (well under a degree per metre); looser lets look-alikes "
      "agree",
      Range{0, 1}};
  Param<std::string> solver{this, "solver", "gn", "", "global optimizer", Choices{{"gn", "lm"}}};
  Param<int> iterations{this, "iterations", 20, "", "max iterations per optimization",
                        Range{1, 1000}};
  Param<std::string> loop_kernel{this, "loop_kernel", "none", "",
                                 "robust kernel on loop edges (the loop filters remove loops the "
                                 "others disagree with in any case)",
                                 Choices{{"none", "huber", "cauchy", "tukey", "dcs"}}};
  Param<double> loop_kernel_scale{this, "loop_kernel_scale", 1.0, "", "scale of the loop kernel",
                                  Range{1e-6, 1e6}};
  Param<double> information_scale{this, "information_scale", 1.0, "",
                                  "scales the information of tracker and loop edges",
                                  Range{1e-9, 1e9}};
  Param<double> weak_edge_ratio{
      this, "weak_edge_ratio", 10.0, "",
      "an odometry edge whose rotation std. dev. is this many times the median of the recent "
      "ones is weak (a tracking failure's fallback edge): the consistency filter widens its "
      "tolerance over it, the odometry audit splits the path there",
      Range{1, 1e12}};
  Param<int> lockstep{
      this, "lockstep", 0, "local maps",
      "threaded back-end whose results join only at map closings: a loop search started at one "
      "closing is applied at the next, an optimization this many closings after it started (0: "
      "as soon as each is ready, which depends on the machine's load). Runs are bit-identical; "
      "at a closing the front-end waits for work not yet done",
      Range{0, 1000}};

  void configure() override;
  int dimension() const override { return S::kDim; }
  void mapStarted(const std::shared_ptr<LocalMap>& map) override;
  void mapClosed(const std::shared_ptr<LocalMap>& map) override;
  bool poll() override;
  void finish() override;
  std::vector<GraphEdge> edges() const override;
  GraphStats stats() const override;

  void restore(const std::vector<std::shared_ptr<LocalMap>>& maps,
               const std::vector<GraphEdge>& edges) override;
  void searchRestored(int64_t first) override;
  size_t relocalize(int64_t query) override;

  /// Optimizes now (inline), whatever the mode; the action "optimize_now".
  void optimizeNow() override;
  /// Writes the graph as g2o (vertices: map origins, map 0 fixed; edges: edges()), atomically;
  /// the action "save_graph PATH".
  void saveGraph(const std::string& path) const;

 private:
  struct State;  // the parts and the scheduling (sdk/src/modules/graph/graph_slam.cpp)
  std::unique_ptr<State> state_;
};

extern template class GraphSlam<Space2D>;
extern template class GraphSlam<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
