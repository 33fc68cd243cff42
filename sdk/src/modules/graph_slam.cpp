#include "plugslam/graph_slam.h"

#include <spdlog/spdlog.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <tuple>

#include "plugslam/errors.h"
#include "plugslam/solver/graph_io.h"
#include "plugslam/solver/optimizer.h"
#include "plugslam/solver/pose_factors.h"
#include "plugslam/solver/robust_kernel.h"

namespace plugslam {
inline namespace abi_v1 {

GraphBackend::~GraphBackend() = default;

void GraphBackend::restore(const std::vector<std::shared_ptr<LocalMap>>&,
                           const std::vector<GraphEdge>&) {
  throw InputError("graph back-end '" + name() + "' (" + typeName() +
                   ") cannot restore a saved graph");
}

namespace {

// Path length put between graph components (sessions, tracker resets): their maps are never
// "recently travelled" from each other, and detectors use their widest search gate.
constexpr double kComponentGap = 1e6;
// Information of the weak prior tying a later component's first map to map 0 where the estimate
// has it; it only keeps the system non-singular until a loop joins the components.
constexpr double kAnchorInformation = 1e-8;

// The solver's variable and factor types of each pose space.
template <class S>
struct GraphTypes;
template <>
struct GraphTypes<Space2D> {
  using Variable = VariableSE2;
  using Between = BetweenFactorSE2;
  using Information = Eigen::Matrix3d;
};
template <>
struct GraphTypes<Space3D> {
  using Variable = VariableSE3;
  using Between = BetweenFactorSE3;
  using Information = Eigen::Matrix<double, 6, 6>;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A symmetric positive-definite version of an information matrix (tiny eigenvalues lifted), so
// a degenerate alignment cannot make the global system singular.
Eigen::MatrixXd conditioned(const Eigen::MatrixXd& h, int dof) {
  if (h.rows() != dof || h.cols() != dof || !h.allFinite())
    return Eigen::MatrixXd::Identity(dof, dof);
  Eigen::MatrixXd sym = 0.5 * (h + h.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(sym);
  Eigen::VectorXd ev = eig.eigenvalues();
  double floor = std::max(1e-6, 1e-6 * ev.maxCoeff());
  for (int i = 0; i < ev.size(); ++i) ev[i] = std::max(ev[i], floor);
  return eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
}

// The largest translation and rotation variances of an edge, from its information (identity
// when it has the wrong size).
std::pair<double, double> maxVariances(const Eigen::MatrixXd& information, int dof) {
  const Eigen::MatrixXd cov = information.rows() == dof && information.cols() == dof
                                  ? Eigen::MatrixXd(information.inverse())
                                  : Eigen::MatrixXd::Identity(dof, dof);
  const int first_rotation = dof == 3 ? 2 : 3;  // (x, y, theta) or (x, y, z, rotation)
  double var_t = 0, var_r = 0;
  for (int i = 0; i < first_rotation; ++i) var_t = std::max(var_t, cov(i, i));
  for (int i = first_rotation; i < dof; ++i) var_r = std::max(var_r, cov(i, i));
  return {var_t, var_r};
}

// How far an edge's measurement is from the relative pose of its two maps at `from` and `to`
// (identity when they agree).
Eigen::Isometry3d edgeError(const GraphEdge& e, const Eigen::Isometry3d& from,
                            const Eigen::Isometry3d& to) {
  return e.relative.inverse() * from.inverse() * to;
}

// Rounds of the odometry audit: each rejects the loops of one stretch of path.
constexpr int kAuditRounds = 10;

}  // namespace

template <class S>
GraphSlam<S>::GraphSlam() {
  addAction("optimize_now", "run the global optimization now and apply it",
            [this](const std::vector<std::string>&) {
              optimizeNow();
              return "optimized " + std::to_string(maps_.size()) + " nodes, " +
                     std::to_string(edges_.size()) + " edges";
            });
  addAction("save_graph", "write the pose graph as g2o: save_graph PATH",
            [this](const std::vector<std::string>& args) {
              if (args.size() != 1) throw InputError("save_graph expects one argument: PATH");
              saveGraph(args[0]);
              return "wrote " + std::to_string(maps_.size()) + " nodes to " + args[0];
            });
}

template <class S>
GraphSlam<S>::~GraphSlam() {
  if (searching_.valid()) searching_.wait();
  if (running_.valid()) running_.wait();
}

template <class S>
GraphStats GraphSlam<S>::stats() const {
  GraphStats s = stats_;
  s.nodes = maps_.size();
  s.edges = edges_.size();
  s.loops_accepted = 0;
  s.loops_rejected = validator_rejections_;
  for (const auto& l : loops_) (l.active ? s.loops_accepted : s.loops_rejected) += 1;
  s.edges += s.loops_accepted;
  return s;
}

template <class S>
std::vector<GraphEdge> GraphSlam<S>::edges() const {
  std::vector<GraphEdge> out = edges_;
  for (const auto& l : loops_)
    if (l.active) out.push_back(l.edge);
  return out;
}

template <class S>
bool GraphSlam<S>::consistent(const GraphEdge& a, const GraphEdge& b) const {
  // The cycle a.from -> a.to (loop a) -> b.to (estimate) -> b.from (loop b, inverted) ->
  // a.from (estimate) is the identity when both loops are right; the estimate's legs are short
  // when the loops close the same revisit, so their drift is small.
  auto est = [&](int64_t x, int64_t y) { return maps_[x]->origin.inverse() * maps_[y]->origin; };
  const Eigen::Isometry3d cycle =
      a.relative * est(a.to, b.to) * b.relative.inverse() * est(b.from, a.from);
  // Maps of different components have no odometry between them: no evidence either way.
  if (components_[a.to] != components_[b.to] || components_[a.from] != components_[b.from])
    return true;
  const double path = std::abs(travelled_[a.to] - travelled_[b.to]) +
                      std::abs(travelled_[a.from] - travelled_[b.from]);
  // A leg through a tracking failure's weak edge holds that edge's error too: the tolerance
  // grows by its std. dev. (rotation, and the rotation's lever over the legs' path).
  const double var_t = std::abs(weak_var_t_[a.to] - weak_var_t_[b.to]) +
                       std::abs(weak_var_t_[a.from] - weak_var_t_[b.from]);
  const double var_r = std::abs(weak_var_r_[a.to] - weak_var_r_[b.to]) +
                       std::abs(weak_var_r_[a.from] - weak_var_r_[b.from]);
  if (var_t + var_r > 0 && consistency_break_sigmas() <= 0) return true;
  const double k = consistency_break_sigmas();
  const double t_err = cycle.translation().norm();
  const double r_err = Eigen::AngleAxisd(cycle.linear()).angle();
  return t_err <= consistency_translation() + consistency_drift() * path +
                      k * (std::sqrt(var_t) + std::sqrt(var_r) * path) &&
         r_err <= consistency_rotation() + consistency_drift() * path + k * std::sqrt(var_r);
}

template <class S>
void GraphSlam<S>::addChain(int64_t previous, const GraphEdge* odometry) {
  if (previous < 0 || !odometry) {
    components_.push_back(components_.empty() ? 0 : components_.back() + 1);
    weak_var_t_.push_back(0);
    weak_var_r_.push_back(0);
    return;
  }
  double var_t = 0, var_r = 0;
  if (isBreak(*odometry)) std::tie(var_t, var_r) = maxVariances(odometry->information, S::kDof);
  components_.push_back(components_[previous]);
  weak_var_t_.push_back(weak_var_t_[previous] + var_t);
  weak_var_r_.push_back(weak_var_r_[previous] + var_r);
}

template <class S>
bool GraphSlam<S>::isBreak(const GraphEdge& e) {
  constexpr size_t kRecent = 200, kMinRecent = 10;
  if (e.information.rows() != S::kDof) return true;
  const Eigen::MatrixXd cov = e.information.inverse();
  double var = 0;
  const int first_rotation = S::kDof == 3 ? 2 : 3;  // (x, y, theta) or (x, y, z, rotation)
  for (int i = first_rotation; i < S::kDof; ++i) var = std::max(var, cov(i, i));
  const double sigma = std::sqrt(var);
  bool loose = false;
  if (recent_sigmas_.size() >= kMinRecent) {
    std::vector<double> sorted = recent_sigmas_;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    loose = sigma > consistency_break_ratio() * sorted[sorted.size() / 2];
  }
  // A break is not remembered: the median stays the median of the tracker's good edges.
  if (!loose) {
    if (recent_sigmas_.size() < kRecent) {
      recent_sigmas_.push_back(sigma);
    } else {
      recent_sigmas_[next_sigma_] = sigma;
      next_sigma_ = (next_sigma_ + 1) % kRecent;
    }
  }
  return loose;
}

template <class S>
void GraphSlam<S>::selectConsistentLoops() {
  // The loops closed recently (within the window of travel before the newest) are re-decided
  // together: the largest set of mutually consistent ones is kept (pairwise consistency
  // maximization, solved exactly: the window holds few loops).
  const double newest = travelled_[loops_.back().edge.to];
  std::vector<size_t> window;
  for (size_t i = 0; i < loops_.size(); ++i)
    if (!loops_[i].vetoed && newest - travelled_[loops_[i].edge.to] <= consistency_window())
      window.push_back(i);
  if (window.size() > 24) window.erase(window.begin(), window.end() - 24);
  const size_t n = window.size();
  std::vector<uint32_t> adj(n, 0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      if (consistent(loops_[window[i]].edge, loops_[window[j]].edge)) {
        adj[i] |= 1u << j;
        adj[j] |= 1u << i;
      }
  uint32_t best = 0;
  int best_size = 0;
  // Branch and bound over subsets, largest first; ties keep the earlier loops.
  std::function<void(uint32_t, uint32_t, int)> grow = [&](uint32_t clique, uint32_t cand, int size) {
    if (size + __builtin_popcount(cand) <= best_size) return;
    if (cand == 0) {
      best = clique;
      best_size = size;
      return;
    }
    const int v = __builtin_ctz(cand);
    grow(clique | (1u << v), cand & adj[v], size + 1);
    grow(clique, cand & ~(1u << v), size);
  };
  grow(0, n >= 32 ? ~0u : ((1u << n) - 1), 0);
  for (size_t i = 0; i < n; ++i) {
    const bool keep = best & (1u << i);
    Loop& l = loops_[window[i]];
    if (l.active != keep)
      spdlog::debug("loop {} -> {} {} by the consistency check", l.edge.to, l.edge.from,
                    keep ? "restored" : "rejected");
    l.active = keep;
  }
}

template <class S>
void GraphSlam<S>::mapStarted(const std::shared_ptr<LocalMap>& map) {
  if (map->id != static_cast<int64_t>(maps_.size()))
    throw Error("graph back-end: local map " + std::to_string(map->id) + " arrived out of order");
  double travelled = maps_.empty() ? 0.0 : travelled_.back() + kComponentGap;
  const GraphEdge* odometry = nullptr;
  if (map->previous >= 0) {
    if (map->previous >= static_cast<int64_t>(maps_.size()))
      throw Error("graph back-end: local map " + std::to_string(map->id) +
                  " follows an unknown map " + std::to_string(map->previous));
    travelled = travelled_[map->previous] + map->relative.translation().norm();
    GraphEdge e;
    e.from = map->previous;
    e.to = map->id;
    e.relative = map->relative;
    e.information = information_scale() * conditioned(map->information, S::kDof);
    edges_.push_back(std::move(e));
    odometry = &edges_.back();
  }
  addChain(map->previous, odometry);
  maps_.push_back(map);
  travelled_.push_back(travelled);
}

template <class S>
void GraphSlam<S>::mapClosed(const std::shared_ptr<LocalMap>& query) {
  if (loop_detectors.empty() || validators.empty()) return;
  queued_.push_back(query->id);
  if (deterministic()) {
    LoopJob job = makeLoopJob();
    runLoopJob(job);
    applyLoopJob(job);
    return;
  }
  // Back-pressure: a front-end far ahead of the search would close loops on a stale estimate.
  if (searching_.valid() && static_cast<int>(queued_.size()) > max_search_lag())
    applyLoopJob(searching_.get());
  if (!searching_.valid()) startLoopJob();
}

template <class S>
typename GraphSlam<S>::LoopJob GraphSlam<S>::makeLoopJob() {
  LoopJob job;
  job.queries.swap(queued_);
  job.view.maps.assign(maps_.begin(), maps_.end());
  job.view.origins.reserve(maps_.size());
  for (const auto& m : maps_) job.view.origins.push_back(m->origin);
  job.view.travelled = travelled_;
  for (const auto& l : loops_)
    if (l.active)
      job.view.last_loop_travelled =
          std::max(job.view.last_loop_travelled, travelled_[l.edge.to]);
  return job;
}

template <class S>
void GraphSlam<S>::runLoopJob(LoopJob& job) {
  const GraphView& view = job.view;
  for (int64_t query_id : job.queries) {
    const LocalMap& query = *view.maps[query_id];
    // A candidate is tried once from the estimate and once from a detector's match (which may
    // lie far from the estimate), and not again once it closed a loop.
    std::vector<std::pair<int64_t, bool>> tried;
    std::vector<int64_t> closed;
    for (auto& detector : job.final_pass ? final_detectors : loop_detectors) {
      const auto detect_start = std::chrono::steady_clock::now();
      const std::vector<LoopCandidate> candidates = detector->detect(view, query);
      job.detection_time += secondsSince(detect_start);
      for (const LoopCandidate& c : candidates) {
        const int64_t id = c.id;
        if (id < 0 || id >= static_cast<int64_t>(view.maps.size()) || id == query_id) continue;
        if (std::find(closed.begin(), closed.end(), id) != closed.end()) continue;
        if (std::find(tried.begin(), tried.end(), std::make_pair(id, c.matched)) != tried.end())
          continue;
        if (std::binary_search(job.linked.begin(), job.linked.end(),
                               std::make_pair(std::max(query_id, id), std::min(query_id, id))))
          continue;
        tried.emplace_back(id, c.matched);
        ++job.candidates;
        const LocalMap& candidate = *view.maps[id];
        LoopClosure closure;
        std::string reason;
        bool ok = true;
        // Validators form a chain: each starts from the pose the previous found, the first from
        // the detector's match when it made one (a global search finds closures far from the
        // estimate), else from the estimate.
        Eigen::Isometry3d current = c.matched ? c.relative : view.relative(id, query_id);
        const auto validate_start = std::chrono::steady_clock::now();
        for (auto& validator : validators) {
          if (!validator->validate(candidate, query, current, closure, reason)) {
            ok = false;
            break;
          }
          current = closure.edge.relative;
        }
        job.validation_time += secondsSince(validate_start);
        if (!ok) {
          ++job.rejections;
          spdlog::debug("loop {} -> {} rejected: {}", query_id, id, reason);
          continue;
        }
        closure.edge.from = id;
        closure.edge.to = query_id;
        closure.edge.loop = true;
        closure.edge.information =
            information_scale() * conditioned(closure.edge.information, S::kDof);
        job.closures.push_back(closure.edge);
        closed.push_back(id);
        job.view.last_loop_travelled = view.travelled[query_id];
        spdlog::debug("loop {} -> {} validated (overlap {:.2f}{})", query_id, id,
                      closure.overlap, c.matched ? ", found by global search" : "");
      }
    }
  }
}

template <class S>
void GraphSlam<S>::applyLoopJob(const LoopJob& job) {
  stats_.candidates += job.candidates;
  stats_.detection_time += job.detection_time;
  stats_.validation_time += job.validation_time;
  validator_rejections_ += job.rejections;
  if (job.closures.empty()) return;
  for (const GraphEdge& e : job.closures) loops_.push_back(Loop{e, true});
  if (job.final_pass) {
    // The consistency window re-decides recent loops; a final pass's span the whole run and
    // are judged by their residuals after this optimization.
    optimizeNow();
    return;
  }
  selectConsistentLoops();
  pending_ = true;
  if (deterministic()) {
    optimizeNow();
  } else if (!running_.valid()) {
    startJob();
  }
}

template <class S>
void GraphSlam<S>::startLoopJob() {
  auto job = std::make_shared<LoopJob>(makeLoopJob());
  searching_ = std::async(std::launch::async, [this, job] {
    runLoopJob(*job);
    return std::move(*job);
  });
}

template <class S>
void GraphSlam<S>::restore(const std::vector<std::shared_ptr<LocalMap>>& maps,
                           const std::vector<GraphEdge>& edges) {
  if (!maps_.empty()) throw InputError("a graph can only be restored into an empty back-end");
  for (const auto& m : maps) {
    if (m->dimension != S::kDim)
      throw InputError("saved local map " + std::to_string(m->id) + " is " +
                       std::to_string(m->dimension) + "D; this back-end is " +
                       std::to_string(S::kDim) + "D");
    if (m->id != static_cast<int64_t>(maps_.size()) || m->previous >= m->id)
      throw InputError("saved local maps must have ids 0, 1, 2, ... in order");
    // The same travelled distance mapStarted computed when the map was first added.
    double travelled = maps_.empty() ? 0.0 : travelled_.back() + kComponentGap;
    if (m->previous >= 0) travelled = travelled_[m->previous] + m->relative.translation().norm();
    maps_.push_back(m);
    travelled_.push_back(travelled);
  }
  for (const auto& e : edges) {
    if (e.from < 0 || e.to < 0 || e.from >= static_cast<int64_t>(maps_.size()) ||
        e.to >= static_cast<int64_t>(maps_.size()))
      throw InputError("saved edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                       " names a map that is not in the session");
    if (e.information.rows() != S::kDof || e.information.cols() != S::kDof)
      throw InputError("saved edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                       " has a " + std::to_string(e.information.rows()) + "x" +
                       std::to_string(e.information.cols()) + " information matrix, expected " +
                       std::to_string(S::kDof) + "x" + std::to_string(S::kDof));
    // Information was conditioned and scaled when the edge was first added: kept as saved.
    if (e.loop)
      loops_.push_back(Loop{e, true});
    else
      edges_.push_back(e);
  }
  // The chain's components and weak edges, as mapStarted found them when the maps were added.
  for (size_t i = 0; i < maps_.size(); ++i) {
    const int64_t prev = maps_[i]->previous;
    const GraphEdge* odometry = nullptr;
    for (const auto& e : edges_)
      if (e.to == static_cast<int64_t>(i) && e.from == prev) odometry = &e;
    addChain(prev, odometry);
  }
  stats_.optimizations = 0;
  restored_ = maps_.size();
}

template <class S>
void GraphSlam<S>::buildGraph(const Job& job, FactorGraph& graph, bool with_kernel) const {
  using T = GraphTypes<S>;
  std::shared_ptr<const RobustKernel> kernel;
  if (with_kernel && loop_kernel() != "none")
    kernel = makeRobustKernel(loop_kernel(), loop_kernel_scale());
  std::vector<typename T::Variable*> vars;
  vars.reserve(job.nodes);
  for (size_t i = 0; i < job.nodes; ++i)
    vars.push_back(
        &graph.addVariable<typename T::Variable>(static_cast<int64_t>(i), job.before[i]));
  if (!vars.empty()) vars[0]->setFixed(true);
  for (const GraphEdge& e : job.edges) {
    auto& f = graph.emplaceFactor<typename T::Between>(vars[e.from], vars[e.to],
                                                       S::from3D(e.relative),
                                                       typename T::Information(
                                                           betweenFactorInformation(e, S::kDim)));
    if (e.loop && kernel) f.setRobustKernel(kernel);
  }
  for (size_t a : job.anchors) {
    const typename S::Matrix info = S::Matrix::Identity() * kAnchorInformation;
    graph.emplaceFactor<typename T::Between>(vars[0], vars[a],
                                             S::normalized(job.before[0].inverse() * job.before[a]),
                                             typename T::Information(info));
  }
}

template <class S>
void GraphSlam<S>::saveGraph(const std::string& path) const {
  Job job = makeJob();
  job.anchors.clear();  // the file holds the graph's own edges only
  FactorGraph graph;
  buildGraph(job, graph, false);
  writeGraphFile(path, graph);
}

template <class S>
typename GraphSlam<S>::Job GraphSlam<S>::makeJob() const {
  Job job;
  job.nodes = maps_.size();
  for (size_t i = 1; i < maps_.size(); ++i)
    if (maps_[i]->previous < 0) job.anchors.push_back(i);
  job.edges = edges();
  job.before.reserve(job.nodes);
  for (const auto& m : maps_) job.before.push_back(S::from3D(m->origin));
  return job;
}

template <class S>
void GraphSlam<S>::runJob(Job& job) const {
  const auto start = std::chrono::steady_clock::now();
  OptimizerOptions options;
  options.algorithm =
      solver() == "lm" ? Algorithm::kLevenbergMarquardt : Algorithm::kGaussNewton;
  options.max_iterations = iterations();
  auto graph = std::make_unique<FactorGraph>();
  buildGraph(job, *graph, true);
  OptimizeResult r = Optimizer(options).optimize(*graph);
  if (options.algorithm == Algorithm::kGaussNewton && r.final_chi2 > r.initial_chi2) {
    // Gauss-Newton does not guarantee descent: far from the solution (a large correction,
    // loose tracking-failure edges) it can diverge and throw the map away. Levenberg-Marquardt
    // from the same start never increases the cost.
    spdlog::debug("global optimization: Gauss-Newton raised chi2 from {:.6g} to {:.6g}; "
                  "Levenberg-Marquardt instead",
                  r.initial_chi2, r.final_chi2);
    options.algorithm = Algorithm::kLevenbergMarquardt;
    graph = std::make_unique<FactorGraph>();
    buildGraph(job, *graph, true);
    r = Optimizer(options).optimize(*graph);
  }
  job.ok = r.ok();
  job.chi2 = r.final_chi2;
  using Variable = typename GraphTypes<S>::Variable;
  for (size_t i = 0; i < job.nodes; ++i)
    job.after.push_back(graph->get<Variable>(static_cast<int64_t>(i)).estimate());
  job.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <class S>
bool GraphSlam<S>::rejectWorstLoop(const Job& job) {
  const double max_t = residual_translation(), max_r = residual_rotation();
  if (max_t <= 0 && max_r <= 0) return false;
  struct Bad {
    double ratio, t, r;
    int64_t from, to;
  };
  std::vector<Bad> bad;
  for (const GraphEdge& e : job.edges) {
    if (!e.loop) continue;
    const Eigen::Isometry3d err =
        edgeError(e, S::to3D(job.after[e.from]), S::to3D(job.after[e.to]));
    const double t = err.translation().norm();
    const double r = Eigen::AngleAxisd(err.linear()).angle();
    const double ratio = std::max(max_t > 0 ? t / max_t : 0.0, max_r > 0 ? r / max_r : 0.0);
    if (ratio > 1.0) bad.push_back({ratio, t, r, e.from, e.to});
  }
  if (bad.empty()) return false;
  // The worst loop goes, and with it every loop at least 0.8 times as far off: one wrong loop
  // bends its neighbours' residuals by less than its own, so most stay for the next round, while
  // many loops off at once (thousands from a final pass) do not cost one optimization each.
  const double worst =
      std::max_element(bad.begin(), bad.end(), [](const Bad& a, const Bad& b) {
        return a.ratio < b.ratio;
      })->ratio;
  std::vector<Bad> going;
  for (const Bad& b : bad)
    if (b.ratio >= 0.8 * worst) going.push_back(b);
  const auto key = [](int64_t from, int64_t to) { return std::make_pair(from, to); };
  std::sort(going.begin(), going.end(),
            [&](const Bad& a, const Bad& b) { return key(a.from, a.to) < key(b.from, b.to); });
  bool rejected = false;
  for (Loop& l : loops_) {
    if (!l.active) continue;
    const auto it = std::lower_bound(
        going.begin(), going.end(), key(l.edge.from, l.edge.to),
        [&](const Bad& b, const std::pair<int64_t, int64_t>& k) { return key(b.from, b.to) < k; });
    if (it == going.end() || it->from != l.edge.from || it->to != l.edge.to) continue;
    l.active = false;
    l.vetoed = true;
    rejected = true;
    spdlog::debug("loop {} -> {} rejected by its residual ({:.3f} m, {:.3f} rad)", l.edge.to,
                  l.edge.from, it->t, it->r);
  }
  return rejected;
}

template <class S>
bool GraphSlam<S>::applyJob(const Job& job) {
  ++stats_.optimizations;
  stats_.optimization_time += job.seconds;
  stats_.final_chi2 = job.chi2;
  if (!job.ok || job.nodes == 0) {
    spdlog::warn("global optimization failed; the map keeps its previous estimate");
    return false;
  }
  // Maps added while the job ran move with the last map the job knew.
  const Eigen::Isometry3d correction =
      S::to3D(job.after.back()) * S::to3D(job.before.back()).inverse();
  for (size_t i = 0; i < maps_.size(); ++i)
    maps_[i]->origin = i < job.nodes ? S::to3D(job.after[i]) : correction * maps_[i]->origin;
  if (!rejectWorstLoop(job)) return false;
  pending_ = true;
  return true;
}

template <class S>
void GraphSlam<S>::startJob() {
  pending_ = false;
  auto job = std::make_shared<Job>(makeJob());
  running_ = std::async(std::launch::async, [this, job] {
    runJob(*job);
    return std::move(*job);
  });
}

template <class S>
bool GraphSlam<S>::poll() {
  if (searching_.valid() &&
      searching_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    applyLoopJob(searching_.get());
    if (!queued_.empty()) startLoopJob();
  }
  if (!running_.valid()) return false;
  if (running_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
  applyJob(running_.get());
  if (pending_) startJob();
  return true;
}

template <class S>
void GraphSlam<S>::optimizeNow() {
  if (running_.valid()) applyJob(running_.get());
  // Each round may reject one loop by its residual; the loops are finite.
  do {
    pending_ = false;
    Job job = makeJob();
    runJob(job);
    applyJob(job);
  } while (pending_);
}

template <class S>
void GraphSlam<S>::finish() {
  if (searching_.valid()) applyLoopJob(searching_.get());
  if (!queued_.empty()) {
    LoopJob job = makeLoopJob();
    runLoopJob(job);
    applyLoopJob(job);
  }
  if (running_.valid()) applyJob(running_.get());
  if (pending_ || stats_.optimizations > 0) optimizeNow();
  auditOdometry();
  // A restored session's maps were searched when they were made (and in localization they are
  // frozen): the final pass only queries the maps this run added.
  if (final_detectors.empty() || validators.empty() || maps_.size() < 2 ||
      maps_.size() <= restored_)
    return;
  for (int round = 0; round < final_rounds(); ++round) {
    if (finalPass() == 0) break;
    auditOdometry();
  }
}

template <class S>
std::vector<double> GraphSlam<S>::odometryStrain(const Job& job,
                                                 const std::vector<Pose>& estimate) const {
  std::vector<double> strain;
  const double k = audit_sigmas();
  for (const GraphEdge& e : job.edges) {
    if (e.loop) continue;
    const Eigen::Isometry3d err = edgeError(e, S::to3D(estimate[e.from]), S::to3D(estimate[e.to]));
    const auto [var_t, var_r] = maxVariances(e.information, S::kDof);
    double s = 0;
    if (audit_translation() > 0)
      s = err.translation().norm() / std::max(audit_translation(), k * std::sqrt(var_t));
    if (audit_rotation() > 0)
      s = std::max(s, Eigen::AngleAxisd(err.linear()).angle() /
                          std::max(audit_rotation(), k * std::sqrt(var_r)));
    strain.push_back(s);
  }
  return strain;
}

template <class S>
size_t GraphSlam<S>::auditOdometry() {
  if ((audit_translation() <= 0 && audit_rotation() <= 0) || loops_.empty()) return 0;
  // Stretches of path the front-end tied together: a tracking failure's weak edge (or a new
  // graph component) starts the next. Between stretches only the motion model's prediction
  // holds, so loops can bend the graph there; but wheel odometry between two maps does not err
  // by metres, and where the optimized graph says it did, the loops that pull a stretch there are
  // what is wrong (on freiburg-campus, a stretch tied 15 m along a repeating facade).
  const size_t n = maps_.size();
  std::vector<size_t> stretch(n), length;
  size_t stretches = 0;
  for (size_t i = 0; i < n; ++i) {
    const int64_t p = maps_[i]->previous;
    const bool starts = p < 0 || components_[i] != components_[p] ||
                        weak_var_t_[i] != weak_var_t_[p] || weak_var_r_[i] != weak_var_r_[p];
    stretch[i] = starts ? stretches++ : stretch[p];
    if (starts) length.push_back(0);
    ++length[stretch[i]];
  }
  // How far the odometry is bent overall: strains below the bound count too, so that a side whose
  // removal only moves the stretch to another edge (short of its bound) is not taken for a fix.
  const auto total = [](const std::vector<double>& strain) {
    double t = 0;
    for (double s : strain) t += s * s;
    return t;
  };
  // Edges between stretches that no side explains; edges inside a stretch are the tracker's own
  // (no loops' choice of stretch explains them) and edges between restored maps were the
  // restored session's.
  std::vector<char> settled(edges_.size(), 0);
  for (size_t j = 0; j < edges_.size(); ++j)
    settled[j] = stretch[edges_[j].from] == stretch[edges_[j].to] ||
                 edges_[j].to < static_cast<int64_t>(restored_);
  size_t rejected = 0;
  for (int round = 0; round < kAuditRounds; ++round) {
    const Job job = makeJob();
    const std::vector<double> strain = odometryStrain(job, job.before);  // one per edges_
    size_t worst = edges_.size();
    for (size_t j = 0; j < strain.size(); ++j)
      if (!settled[j] && strain[j] > 1 && (worst == edges_.size() || strain[j] > strain[worst]))
        worst = j;
    if (worst == edges_.size()) break;
    // The active loops joining each stretch to another (loops among restored maps belong to
    // their own session).
    std::vector<std::vector<size_t>> joining(stretches);
    for (size_t i = 0; i < loops_.size(); ++i) {
      const GraphEdge& e = loops_[i].edge;
      if (!loops_[i].active || stretch[e.from] == stretch[e.to]) continue;
      if (std::max(e.from, e.to) < static_cast<int64_t>(restored_)) continue;
      joining[stretch[e.from]].push_back(i);
      joining[stretch[e.to]].push_back(i);
    }
    // The nearest stretch with such loops on either side of the stretched edge (stretches of
    // one failed frame each, between consecutive failures, hold none).
    const GraphEdge& edge = edges_[worst];
    std::vector<size_t> sides;
    for (int64_t m = edge.from; m >= 0; m = maps_[m]->previous)
      if (!joining[stretch[m]].empty()) {
        sides.push_back(stretch[m]);
        break;
      }
    for (int64_t m = edge.to; m < static_cast<int64_t>(n);) {
      if (!joining[stretch[m]].empty()) {
        // Both sides may hold the same loops (the other side's only ones are to this one): then
        // they are tried once, named by the shorter stretch.
        if (sides.empty() || joining[sides[0]] != joining[stretch[m]])
          sides.push_back(stretch[m]);
        else if (length[stretch[m]] < length[sides[0]])
          sides[0] = stretch[m];
        break;
      }
      if (m + 1 >= static_cast<int64_t>(n) || maps_[m + 1]->previous != m) break;
      ++m;
    }
    // Without one side's loops, does the edge hold, with no other edge pushed past its bound?
    // Of the sides for which it does, the one whose removal leaves the odometry least bent goes
    // (the other side's loops, right, only carry the stretch along to its next edge); on a tie,
    // the one with fewer loops.
    const double before = total(strain);
    size_t best = stretches;
    double best_total = before;
    Job best_trial;
    for (size_t side : sides) {
      std::vector<char> drop(loops_.size(), 0);
      for (size_t i : joining[side]) drop[i] = 1;
      Job trial;
      trial.nodes = job.nodes;
      trial.anchors = job.anchors;
      trial.before = job.before;
      trial.edges = edges_;
      for (size_t i = 0; i < loops_.size(); ++i)
        if (loops_[i].active && !drop[i]) trial.edges.push_back(loops_[i].edge);
      runJob(trial);
      // Trials are optimizations too: their time counts (the one applied is counted when it is).
      stats_.optimization_time += trial.seconds;
      if (!trial.ok) continue;
      const std::vector<double> after = odometryStrain(trial, trial.after);
      const double after_total = total(after);
      if (!(after[worst] <= 1) || !(after_total < before)) continue;
      bool moved = false;  // the stretch only moved to another edge
      for (size_t j = 0; j < after.size() && !moved; ++j)
        moved = j != worst && after[j] > 1 && !(strain[j] > 1);
      if (moved) continue;
      if (best == stretches || after_total < best_total ||
          (after_total == best_total && joining[side].size() <= joining[best].size())) {
        best = side;
        best_total = after_total;
        best_trial = std::move(trial);
      }
    }
    const Eigen::Isometry3d err = edgeError(edge, maps_[edge.from]->origin, maps_[edge.to]->origin);
    if (best == stretches) {
      spdlog::info("odometry audit: the graph stretches odometry edge {} -> {} by {:.2f} m, "
                   "{:.3f} rad; no side's loops explain it, kept",
                   edge.from, edge.to, err.translation().norm(),
                   Eigen::AngleAxisd(err.linear()).angle());
      settled[worst] = 1;
      continue;
    }
    for (size_t i : joining[best]) {
      loops_[i].active = false;
      loops_[i].vetoed = true;
      loops_[i].audited = true;
    }
    // The trial is the graph without them: apply it rather than solve it again. Those of them
    // that agree with the corrected graph (a stretch's right loops next to its wrong ones)
    // come back.
    pending_ = false;
    stats_.optimization_time -= best_trial.seconds;  // applyJob counts it
    applyJob(best_trial);
    size_t reinstated = 0;
    const double max_t = residual_translation(), max_r = residual_rotation();
    if (max_t > 0 || max_r > 0)
      for (size_t i : joining[best]) {
        const GraphEdge& e = loops_[i].edge;
        const Eigen::Isometry3d r = edgeError(e, maps_[e.from]->origin, maps_[e.to]->origin);
        if ((max_t > 0 && !(r.translation().norm() <= max_t)) ||
            (max_r > 0 && !(Eigen::AngleAxisd(r.linear()).angle() <= max_r)))
          continue;
        loops_[i].active = true;
        loops_[i].vetoed = false;
        loops_[i].audited = false;
        ++reinstated;
      }
    if (pending_ || reinstated > 0) optimizeNow();
    rejected += joining[best].size() - reinstated;
    int64_t first = -1, last = -1;
    for (size_t i = 0; i < n; ++i)
      if (stretch[i] == best) {
        if (first < 0) first = static_cast<int64_t>(i);
        last = static_cast<int64_t>(i);
      }
    spdlog::info("odometry audit: the graph stretched odometry edge {} -> {} by {:.2f} m, "
                 "{:.3f} rad; rejected {} of the {} loops joining maps {}-{} to the rest",
                 edge.from, edge.to, err.translation().norm(),
                 Eigen::AngleAxisd(err.linear()).angle(), joining[best].size() - reinstated,
                 joining[best].size(), first, last);
  }
  return rejected;
}

template <class S>
size_t GraphSlam<S>::finalPass() {
  // Online, a detector's gate must allow for the drift since the candidate; once the loops are
  // closed the estimate is good everywhere, so maps that overlap but were never close enough to
  // be proposed (or were proposed under drift and failed) can be tied now. Many such ties make
  // the map consistent between revisits, not only at the loop closures.
  LoopJob job = makeLoopJob();
  job.final_pass = true;
  job.queries.clear();
  for (size_t id = restored_; id < maps_.size(); ++id)
    job.queries.push_back(static_cast<int64_t>(id));
  // Pairs ever closed, kept or rejected, newer map first (a detector may propose either order);
  // but a pair the odometry audit rejected may be proposed again: validated from the corrected
  // estimate, it closes where its maps now are, not where the wrong loops had put them.
  for (const auto& l : loops_)
    if (!l.audited)
      job.linked.emplace_back(std::max(l.edge.to, l.edge.from), std::min(l.edge.to, l.edge.from));
  std::sort(job.linked.begin(), job.linked.end());
  runLoopJob(job);
  spdlog::info("final loop pass: {} closures from {} candidates", job.closures.size(),
               job.candidates);
  applyLoopJob(job);
  return job.closures.size();
}

template class GraphSlam<Space2D>;
template class GraphSlam<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
