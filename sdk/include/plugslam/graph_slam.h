#pragma once
// The graph back-end (seed, section III): local maps are pose-graph nodes, consecutive maps are
// joined by the tracker's relative pose, loop detectors propose closures between maps, loop
// validators check them by aligning the maps' scenes, and a global optimizer corrects every map
// origin. Generic over 2D and 3D through the pose space, like the tracker.
#include <Eigen/Core>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/local_map.h"
#include "plugslam/loop_closure.h"
#include "plugslam/graph_edge.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

class FactorGraph;

/// Counters of the back-end.
struct GraphStats {
  uint64_t nodes = 0, edges = 0;
  uint64_t candidates = 0;         ///< proposals by the detectors
  uint64_t loops_accepted = 0;     ///< validated and kept by the optimizer
  uint64_t loops_rejected = 0;     ///< refused by a validator or by the consistency check
  uint64_t optimizations = 0;
  double optimization_time = 0;    ///< seconds, summed
  double detection_time = 0;       ///< seconds in the loop detectors, summed
  double validation_time = 0;      ///< seconds in the loop validators, summed
  double final_chi2 = 0;
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
};

/// Pose-graph SLAM over local maps ("sdk.GraphSlam2D/3D"). Loop detection and validation, and
/// the optimization, run on back-end threads (results are applied at a later frame) unless
/// `deterministic` is set.
template <class S>
class GraphSlam : public GraphBackend {
 public:
  using Pose = typename S::Pose;
  GraphSlam();
  ~GraphSlam() override;

  SlotList<LoopDetector> loop_detectors{this, "loop_detectors", "propose loop candidates"};
  SlotList<LoopValidator> validators{
      this, "validators",
      "every validator must accept a candidate; each starts from the pose the previous found"};
  SlotList<LoopDetector> final_detectors{
      this, "final_detectors",
      "run once over every map this run added when it ends, on the optimized estimate (e.g. a "
      "wider proximity search than drift allows online); their validated closures join the "
      "graph (guarded by the validators and the residual check, not the consistency window) "
      "before a last optimization"};
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
  Param<std::string> solver{this, "solver", "gn", "", "global optimizer", Choices{{"gn", "lm"}}};
  Param<int> iterations{this, "iterations", 20, "", "max iterations per optimization",
                        Range{1, 1000}};
  Param<std::string> loop_kernel{this, "loop_kernel", "none", "",
                                 "robust kernel on loop edges (the consistency check below "
                                 "removes loops the others disagree with in any case)",
                                 Choices{{"none", "huber", "cauchy", "tukey", "dcs"}}};
  Param<double> loop_kernel_scale{this, "loop_kernel_scale", 1.0, "", "scale of the loop kernel",
                                  Range{1e-6, 1e6}};
  Param<double> information_scale{this, "information_scale", 1.0, "",
                                  "scales the information of tracker and loop edges",
                                  Range{1e-9, 1e9}};
  Param<double> consistency_translation{
      this, "consistency_translation", 0.3, "m",
      "two loops agree when the cycle they close with the odometry errs less than this...",
      Range{0, 1e6}};
  Param<double> consistency_rotation{this, "consistency_rotation", 0.1, "rad",
                                     "...and less than this in rotation", Range{0, 10}};
  Param<double> consistency_drift{this, "consistency_drift", 0.02, "",
                                  "plus this fraction of the odometry path inside the cycle",
                                  Range{0, 10}};
  Param<double> consistency_window{
      this, "consistency_window", 30.0, "m",
      "loops closed within this much travel are checked against each other; the largest "
      "mutually consistent set is kept",
      Range{0, 1e9}};

  Param<double> consistency_break_ratio{
      this, "consistency_break_ratio", 10.0, "",
      "an odometry edge whose rotation std. dev. is this many times the median of the recent "
      "ones is weak (a tracking failure's fallback edge): see consistency_break_sigmas",
      Range{1, 1e12}};
  Param<double> consistency_break_sigmas{
      this, "consistency_break_sigmas", 3.0, "",
      "a cycle whose odometry legs run through weak edges may err by this many of their std. "
      "devs more (rotation; translation plus rotation times the legs' path); 0: such cycles are "
      "no evidence either way and their loops are not checked against each other",
      Range{0, 1e6}};
  Param<double> residual_translation{
      this, "residual_translation", 0.1, "m",
      "after each optimization the active loop that disagrees most with the optimized graph "
      "(and any at least 0.8 times as far off), if its error exceeds this (0: never)...",
      Range{0, 1e6}};
  Param<double> residual_rotation{
      this, "residual_rotation", 0.1, "rad",
      "...or this in rotation (0: never), is rejected for good and the graph re-optimized (a "
      "wrong loop alone in its consistency window has no other loop to disagree with)",
      Range{0, 10}};

  Param<double> audit_translation{
      this, "audit_translation", 2.0, "m",
      "when the run ends, an odometry edge the optimized graph stretches by more than this (and "
      "audit_sigmas of its std. dev.) is evidence of wrong loops: the loops joining the "
      "stretch of path on one side of it (between tracking failures) to the rest are rejected "
      "when without them the edge holds; of the two sides, the one whose removal leaves the "
      "odometry least bent (0 here and in audit_rotation: no audit; turn it off for data where "
      "the robot was carried, or a log jumps, between two maps)",
      Range{0, 1e6}};
  Param<double> audit_rotation{this, "audit_rotation", 0.5, "rad",
                               "...or turns it by more than this (0: rotation not audited)",
                               Range{0, 10}};
  Param<double> audit_sigmas{this, "audit_sigmas", 5.0, "",
                             "...and by more than this many of the edge's std. devs",
                             Range{0, 1e6}};

  int dimension() const override { return S::kDim; }
  void mapStarted(const std::shared_ptr<LocalMap>& map) override;
  void mapClosed(const std::shared_ptr<LocalMap>& map) override;
  bool poll() override;
  void finish() override;
  std::vector<GraphEdge> edges() const override;
  GraphStats stats() const override;

  void restore(const std::vector<std::shared_ptr<LocalMap>>& maps,
               const std::vector<GraphEdge>& edges) override;

  /// Optimizes now (inline), whatever the mode; the action "optimize_now".
  void optimizeNow();
  /// Writes the graph as g2o (vertices: map origins, map 0 fixed; edges: edges()), atomically;
  /// the action "save_graph PATH".
  void saveGraph(const std::string& path) const;

 private:
  struct Job {
    size_t nodes = 0;
    std::vector<size_t> anchors;    // first maps of later graph components (sessions, resets)
    std::vector<Pose> before, after;
    std::vector<GraphEdge> edges;   // snapshot: the back-end thread never reads edges_
    double seconds = 0, chi2 = 0;
    bool ok = false;
  };
  // Loop search over closed maps (detectors, then validators), on a snapshot of the graph.
  struct LoopJob {
    GraphView view;
    std::vector<int64_t> queries;
    std::vector<GraphEdge> closures;  // validated, in order
    bool final_pass = false;          // final_detectors over every map (see finish())
    std::vector<std::pair<int64_t, int64_t>> linked;  // (query, candidate) pairs to skip, sorted
    uint64_t candidates = 0, rejections = 0;
    double detection_time = 0, validation_time = 0;  // seconds
  };
  LoopJob makeLoopJob();
  void runLoopJob(LoopJob& job);  // the only user of the detectors and validators
  void applyLoopJob(const LoopJob& job);
  void startLoopJob();
  // A final pass: final_detectors over every map on the optimized estimate, then optimize;
  // returns the number of closures it added.
  size_t finalPass();
  // Odometry audit (see audit_translation): rejects the loops that stretch odometry edges
  // beyond what odometry can err, re-optimizing after each rejection; returns the loops rejected.
  size_t auditOdometry();
  // Strain of each odometry edge of `job` at `estimate`: its error over its audit bound (> 1:
  // the edge is stretched beyond the bound), in the order of job.edges' odometry edges.
  std::vector<double> odometryStrain(const Job& job, const std::vector<Pose>& estimate) const;

  Job makeJob() const;
  void runJob(Job& job) const;
  // Fills `graph` with the job's variables (the first fixed) and between factors.
  void buildGraph(const Job& job, FactorGraph& graph, bool with_kernel) const;
  // Applies the job's estimate; true when it rejected a loop by its residual (see
  // residual_translation), so that the graph needs another optimization.
  bool applyJob(const Job& job);
  // The active loop of `job` whose residual at the job's solution is largest relative to the
  // residual bounds, if any exceeds them, and every loop at least 0.8 times as far off:
  // rejected for good.
  bool rejectWorstLoop(const Job& job);
  void startJob();

  bool consistent(const GraphEdge& a, const GraphEdge& b) const;
  // True when an odometry edge is far looser in rotation than the recent ones; remembers it.
  bool isBreak(const GraphEdge& odometry);
  // Appends the next map's graph component and weak-edge variances (from `previous`, joined to
  // it by `odometry` when that is not null).
  void addChain(int64_t previous, const GraphEdge* odometry);
  void selectConsistentLoops();

  std::vector<std::shared_ptr<LocalMap>> maps_;
  size_t restored_ = 0;  // maps from restore(): the final pass does not query them
  std::vector<double> travelled_;
  // Per map: its graph component (sessions, tracker resets), and the summed translation and
  // rotation variances of the weak odometry edges from its component's first map to it (the
  // maps of a component form one chain, so a leg's variance is a difference of two sums).
  std::vector<int> components_;
  std::vector<double> weak_var_t_, weak_var_r_;
  std::vector<double> recent_sigmas_;  // rotation std. dev. of the last odometry edges (a ring)
  size_t next_sigma_ = 0;
  std::vector<GraphEdge> edges_;  // odometry edges, then the active loops
  struct Loop {
    GraphEdge edge;
    bool active = true;
    bool vetoed = false;  // rejected by its residual after an optimization: never restored
    bool audited = false;  // rejected by the odometry audit: the final pass may close its pair
  };
  std::vector<Loop> loops_;       // every validated loop, active or rejected by consistency
  uint64_t validator_rejections_ = 0;
  GraphStats stats_;
  std::future<Job> running_;
  bool pending_ = false;
  std::vector<int64_t> queued_;  // closed maps waiting for the loop search
  std::future<LoopJob> searching_;
};

extern template class GraphSlam<Space2D>;
extern template class GraphSlam<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
