// GraphSlam, the coordinator: it hands new maps to the pose graph, closed maps to the loop
// search, the search's loops to the loop filters and the graph to the global optimizer, inline
// or on the back-end threads, and applies what comes back.
#include "plugslam/graph_slam.h"

#include <spdlog/spdlog.h>

#include "modules/graph/global_optimizer.h"
#include "modules/graph/loop_filter.h"
#include "modules/graph/loop_search.h"
#include "modules/graph/pose_graph.h"
#include "plugslam/errors.h"
#include "plugslam/graph_writer.h"
#include "plugslam/registry.h"

namespace plugslam {
inline namespace abi_v1 {

GraphBackend::~GraphBackend() = default;

void GraphBackend::restore(const std::vector<std::shared_ptr<LocalMap>>&,
                           const std::vector<GraphEdge>&) {
  throw InputError("graph back-end '" + name() + "' (" + typeName() +
                   ") cannot restore a saved graph");
}

void GraphBackend::optimizeNow() {}

void GraphBackend::searchRestored(int64_t) {
  throw InputError("graph back-end '" + name() + "' (" + typeName() +
                   ") cannot search loops between restored sessions");
}

size_t GraphBackend::relocalize(int64_t) { return 0; }

LoopFilter::~LoopFilter() = default;
void LoopFilter::loopsAdded(detail::PoseGraph&) {}
bool LoopFilter::optimized(detail::PoseGraph&, const detail::Solution&) { return false; }
size_t LoopFilter::runEnds(detail::PoseGraph&, detail::GraphOptimizer&) { return 0; }

namespace {
template <class S>
detail::JoinRule joinRuleOf(const GraphSlam<S>& g) {
  detail::JoinRule r;
  r.agreeing = g.join_agreeing();
  r.agreeing_localizing = g.join_agreeing_localizing();
  if (g.join_agreement().size() == 2) {
    r.translation = g.join_agreement()[0];
    r.rotation = g.join_agreement()[1];
  }
  r.drift = g.join_drift();
  r.angular_drift = g.join_angular_drift();
  return r;
}
}  // namespace

template <class S>
struct GraphSlam<S>::State final : detail::GraphOptimizer {
  using Optimizer = detail::GlobalOptimizer<S>;

  GraphSlam& owner;
  detail::PoseGraph graph;
  detail::LoopSearch search;
  Optimizer optimizer;
  GraphStats stats;
  uint64_t validator_rejections = 0;
  bool pending = false;  // the graph changed since the last optimization started
  // The map the tracker started last and has not closed: when the run ends it is final, and is
  // searched like any closed map (a run that ends where it began closes its loop there).
  int64_t open_map = -1;
  // lockstep: closings seen, and the closing at which the running optimization started.
  int64_t closings = 0, optimization_started = 0;

  explicit State(GraphSlam& o)
      : owner(o),
        graph(S::kDim, o.weak_edge_ratio()),
        search(o.loop_detectors, o.final_detectors, o.validators, o.join_by_estimate,
               [&o] { return joinRuleOf(o); }) {}

  detail::OptimizerSettings settings() const {
    return {owner.solver(), owner.iterations(), owner.loop_kernel(), owner.loop_kernel_scale()};
  }
  typename Optimizer::Problem snapshot(std::vector<GraphEdge> edges) const {
    return Optimizer::snapshot(graph, settings(), std::move(edges));
  }

  // Applies an optimization to the maps' origins, then lets the filters judge it; true when one
  // rejected loops, so that the graph needs another optimization.
  bool apply(const detail::Solution& s, bool count_time = true) {
    ++stats.optimizations;
    if (count_time) stats.optimization_time += s.seconds;
    stats.final_chi2 = s.chi2;
    if (!s.ok || s.nodes == 0) {
      spdlog::warn("global optimization failed; the map keeps its previous estimate");
      return false;
    }
    // Maps added while the optimization ran move with the last map it knew.
    const Eigen::Isometry3d correction = s.after.back() * s.before.back().inverse();
    const auto& maps = graph.maps();
    for (size_t i = 0; i < maps.size(); ++i)
      maps[i]->origin = i < s.nodes ? s.after[i] : correction * maps[i]->origin;
    bool rejected = false;
    for (auto& filter : owner.loop_filters) rejected = filter->optimized(graph, s) || rejected;
    if (!rejected) return false;
    pending = true;
    return true;
  }

  void startOptimization() {
    pending = false;
    optimization_started = closings;
    optimizer.start(snapshot(graph.edges()));
  }

  void optimizeNow() {
    if (optimizer.running()) apply(optimizer.collect());
    // Each round may reject loops; the loops are finite.
    do {
      pending = false;
      apply(Optimizer::solve(snapshot(graph.edges())));
    } while (pending);
  }

  // `optimize_inline`: optimize now, whatever the mode (the next search needs the estimate).
  void applyLoops(const detail::LoopJob& job, bool optimize_inline = false) {
    stats.candidates += job.candidates;
    stats.detection_time += job.detection_time;
    stats.validation_time += job.validation_time;
    validator_rejections += job.rejections;
    if (job.closures.empty()) return;
    for (const GraphEdge& e : job.closures) graph.addLoop(e);
    if (job.final_pass) {
      // The filters' online selection re-decides recent loops; a final pass's span the whole run
      // and are judged after this optimization.
      optimizeNow();
      return;
    }
    for (auto& filter : owner.loop_filters) filter->loopsAdded(graph);
    pending = true;
    if (owner.deterministic() || optimize_inline) {
      optimizeNow();
    } else if (!optimizer.running()) {
      startOptimization();
    }
  }

  void searchInline() {
    detail::LoopJob job = search.take(graph, owner.information_scale());
    search.run(job);
    applyLoops(job);
  }

  // The final detectors over every map this run added, then an optimization; returns the
  // number of closures added.
  size_t finalPass() {
    // Online, a detector's gate must allow for the drift since the candidate; once the loops are
    // closed the estimate is good everywhere, so maps that overlap but were never close enough to
    // be proposed (or were proposed under drift and failed) can be tied now. Many such ties make
    // the map consistent between revisits, not only at the loop closures.
    detail::LoopJob job = search.finalPass(graph, owner.information_scale());
    search.run(job);
    spdlog::info("final loop pass: {} closures from {} candidates", job.closures.size(),
                 job.candidates);
    applyLoops(job);
    return job.closures.size();
  }

  void runEnds() {
    for (auto& filter : owner.loop_filters) filter->runEnds(graph, *this);
  }

  // detail::GraphOptimizer, for the filters that optimize when the run ends.
  std::vector<Eigen::Isometry3d> estimate() const override {
    std::vector<Eigen::Isometry3d> out;
    out.reserve(graph.size());
    for (const auto& m : graph.maps()) out.push_back(S::to3D(S::from3D(m->origin)));
    return out;
  }
  detail::Solution trial(std::vector<GraphEdge> edges) override {
    detail::Solution s = Optimizer::solve(snapshot(std::move(edges)));
    stats.optimization_time += s.seconds;  // trials are optimizations too
    return s;
  }
  bool adopt(const detail::Solution& trial) override {
    pending = false;
    apply(trial, false);  // its time was counted by trial()
    return pending;
  }
  void optimize() override { optimizeNow(); }
};

template <class S>
GraphSlam<S>::GraphSlam() : state_(std::make_unique<State>(*this)) {
  // Built from code (not YAML), the back-end has the same filters as one built from a config
  // that omits `loop_filters`.
  for (const auto& type : loop_filters.defaultTypes())
    loop_filters.assign(Registry::instance().create(type));
  addAction("optimize_now", "run the global optimization now and apply it",
            [this](const std::vector<std::string>&) {
              optimizeNow();
              return "optimized " + std::to_string(state_->graph.size()) + " nodes, " +
                     std::to_string(state_->graph.odometry().size()) + " edges";
            });
  addAction("save_graph", "write the pose graph as g2o: save_graph PATH",
            [this](const std::vector<std::string>& args) {
              if (args.size() != 1) throw InputError("save_graph expects one argument: PATH");
              saveGraph(args[0]);
              return "wrote " + std::to_string(state_->graph.size()) + " nodes to " + args[0];
            });
}

template <class S>
GraphSlam<S>::~GraphSlam() = default;

template <class S>
void GraphSlam<S>::configure() {
  if (join_agreement().size() != 2 || !(join_agreement()[0] > 0) || !(join_agreement()[1] > 0))
    throw ParamError("join_agreement", "expected 2 values > 0 (translation m, rotation rad)");
}


template <class S>
GraphStats GraphSlam<S>::stats() const {
  GraphStats s = state_->stats;
  s.nodes = state_->graph.size();
  s.edges = state_->graph.odometry().size();
  s.loops_accepted = s.loops_restored = 0;
  s.loops_rejected = state_->validator_rejections;
  // A restored session's loops are not this run's closures; one this run rejects is its verdict.
  const auto& loops = state_->graph.loops();
  for (size_t i = 0; i < loops.size(); ++i) {
    const bool restored = i < state_->graph.restoredLoops();
    (loops[i].active ? (restored ? s.loops_restored : s.loops_accepted) : s.loops_rejected) += 1;
  }
  s.edges += s.loops_accepted + s.loops_restored;
  return s;
}

template <class S>
std::vector<GraphEdge> GraphSlam<S>::edges() const {
  return state_->graph.edges();
}

template <class S>
void GraphSlam<S>::mapStarted(const std::shared_ptr<LocalMap>& map) {
  state_->graph.setWeakEdgeRatio(weak_edge_ratio());
  state_->graph.addMap(map, information_scale());
  state_->open_map = map->id;
}

template <class S>
void GraphSlam<S>::mapClosed(const std::shared_ptr<LocalMap>& query) {
  State& st = *state_;
  if (query->id == st.open_map) st.open_map = -1;
  if (loop_detectors.empty() || validators.empty()) return;
  st.search.enqueue(query->id);
  if (deterministic()) {
    st.searchInline();
    return;
  }
  if (lockstep() > 0) {
    // Results join at closings only, so what each frame sees does not depend on thread timing.
    ++st.closings;
    if (st.optimizer.running() && st.closings - st.optimization_started >= lockstep()) {
      st.apply(st.optimizer.collect());
      if (st.pending) st.startOptimization();
    }
    if (st.search.running()) st.applyLoops(st.search.collect());
    st.search.start(st.search.take(st.graph, information_scale()));
    return;
  }
  // Back-pressure: a front-end far ahead of the search would close loops on a stale estimate.
  if (st.search.running() && static_cast<int>(st.search.queued()) > max_search_lag())
    st.applyLoops(st.search.collect());
  if (!st.search.running()) st.search.start(st.search.take(st.graph, information_scale()));
}

template <class S>
bool GraphSlam<S>::poll() {
  State& st = *state_;
  if (lockstep() > 0 && !deterministic()) return false;  // joined at closings (mapClosed)
  if (st.search.ready()) {
    st.applyLoops(st.search.collect());
    if (st.search.queued() > 0) st.search.start(st.search.take(st.graph, information_scale()));
  }
  if (!st.optimizer.ready()) return false;
  st.apply(st.optimizer.collect());
  if (st.pending) st.startOptimization();
  return true;
}

template <class S>
void GraphSlam<S>::optimizeNow() {
  state_->optimizeNow();
}

template <class S>
void GraphSlam<S>::finish() {
  State& st = *state_;
  if (st.search.running()) st.applyLoops(st.search.collect());
  if (st.open_map >= 0 && !loop_detectors.empty() && !validators.empty())
    st.search.enqueue(st.open_map);
  st.open_map = -1;
  if (st.search.queued() > 0) st.searchInline();
  if (st.optimizer.running()) st.apply(st.optimizer.collect());
  if (st.pending || st.stats.optimizations > 0) st.optimizeNow();
  st.runEnds();
  // A restored session's maps were searched when they were made (and in localization they are
  // frozen): the final pass only queries the maps this run added.
  if (final_detectors.empty() || validators.empty() || st.graph.size() < 2 ||
      st.graph.size() <= st.graph.restoredMaps())
    return;
  for (int round = 0; round < final_rounds(); ++round) {
    if (st.finalPass() == 0) break;
    st.runEnds();
  }
}

template <class S>
void GraphSlam<S>::restore(const std::vector<std::shared_ptr<LocalMap>>& maps,
                           const std::vector<GraphEdge>& edges) {
  state_->graph.setWeakEdgeRatio(weak_edge_ratio());
  state_->graph.restore(maps, edges);
  state_->stats.optimizations = 0;
}

template <class S>
void GraphSlam<S>::searchRestored(int64_t first) {
  State& st = *state_;
  const auto n = static_cast<int64_t>(st.graph.size());
  if (first < 0 || first > n)
    throw InputError("searchRestored: map " + std::to_string(first) + " is not restored (" +
                     std::to_string(n) + " maps)");
  st.graph.treatAsNew(static_cast<size_t>(first));
  if (loop_detectors.empty() || validators.empty()) return;
  for (int64_t id = first; id < n; ++id) {
    st.search.enqueue(id);
    detail::LoopJob job = st.search.take(st.graph, information_scale());
    // The restored sessions' own loops are in the graph already: only pairs across sessions.
    job.linked = detail::LoopSearch::linkedPairs(st.graph, true);
    job.chains = st.graph.components();
    st.search.run(job);
    st.applyLoops(job, true);
  }
}

template <class S>
size_t GraphSlam<S>::relocalize(int64_t query) {
  State& st = *state_;
  const auto n = static_cast<int64_t>(st.graph.size());
  if (query < 0 || query >= n)
    throw InputError("relocalize: no map " + std::to_string(query) + " (" + std::to_string(n) +
                     " maps)");
  if (loop_detectors.empty() || validators.empty()) return 0;
  // Searched on the estimate of every loop so far; maps waiting for the search go along.
  if (st.search.running()) st.applyLoops(st.search.collect());
  st.search.enqueue(query);
  detail::LoopJob job = st.search.take(st.graph, information_scale());
  job.view.localizing = true;
  st.search.run(job);
  const size_t found = job.closures.size();
  st.applyLoops(job, true);
  return found;
}

template <class S>
void GraphSlam<S>::saveGraph(const std::string& path) const {
  const auto& maps = state_->graph.maps();
  writeGraphG2o(path, {maps.begin(), maps.end()}, state_->graph.edges());
}

template class GraphSlam<Space2D>;
template class GraphSlam<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
