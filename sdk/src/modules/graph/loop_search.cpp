#include "modules/graph/loop_search.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

namespace {
double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

LoopSearch::LoopSearch(const SlotList<LoopDetector>& online,
                       const SlotList<LoopDetector>& final_detectors,
                       const SlotList<LoopValidator>& validators,
                       const Param<bool>& join_by_estimate,
                       std::function<JoinRule()> join_rule)
    : online_(online),
      final_(final_detectors),
      validators_(validators),
      join_by_estimate_(join_by_estimate),
      join_rule_(std::move(join_rule)) {}

LoopSearch::~LoopSearch() {
  if (searching_.valid()) searching_.wait();
}

LoopJob LoopSearch::take(const PoseGraph& graph, double information_scale) {
  LoopJob job;
  job.queries.swap(queued_);
  job.join_by_estimate = join_by_estimate_();
  job.join = join_rule_();
  job.view = graph.view();
  job.dof = graph.dof();
  job.information_scale = information_scale;
  return job;
}

LoopJob LoopSearch::finalPass(const PoseGraph& graph, double information_scale) const {
  LoopJob job;
  job.view = graph.view();
  job.dof = graph.dof();
  job.information_scale = information_scale;
  job.final_pass = true;
  job.join_by_estimate = join_by_estimate_();
  job.join = join_rule_();
  for (size_t id = graph.restoredMaps(); id < graph.size(); ++id)
    job.queries.push_back(static_cast<int64_t>(id));
  // Pairs ever closed, kept or rejected (a detector may propose either order); but a pair the
  // odometry audit rejected may be proposed again: validated from the corrected estimate, it
  // closes where its maps now are, not where the wrong loops had put them.
  job.linked = linkedPairs(graph, false);
  return job;
}

std::vector<std::pair<int64_t, int64_t>> LoopSearch::linkedPairs(const PoseGraph& graph,
                                                                 bool audited) {
  std::vector<std::pair<int64_t, int64_t>> linked;
  for (const auto& l : graph.loops())
    if (audited || !l.audited)
      linked.emplace_back(std::max(l.edge.to, l.edge.from), std::min(l.edge.to, l.edge.from));
  std::sort(linked.begin(), linked.end());
  return linked;
}

void LoopSearch::run(LoopJob& job) {
  const GraphView& view = job.view;
  for (int64_t query_id : job.queries) {
    const LocalMap& query = *view.maps[query_id];
    // A candidate is tried once from the estimate and once from a detector's match (which may
    // lie far from the estimate), and not again once it closed a loop.
    std::vector<std::pair<int64_t, bool>> tried;
    std::vector<int64_t> closed;
    for (auto& detector : job.final_pass ? final_ : online_) {
      const auto detect_start = std::chrono::steady_clock::now();
      const std::vector<LoopCandidate> candidates = detector->detect(view, query);
      job.detection_time += secondsSince(detect_start);
      for (const LoopCandidate& c : candidates) {
        const int64_t id = c.id;
        if (id < 0 || id >= static_cast<int64_t>(view.maps.size()) || id == query_id) continue;
        if (!job.chains.empty() && job.chains[static_cast<size_t>(id)] ==
                                       job.chains[static_cast<size_t>(query_id)])
          continue;
        // Components whose relative pose is unknown: the estimate relates nothing between them.
        if (!job.join_by_estimate && !c.global && view.component(id) != view.component(query_id))
          continue;
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
        for (auto& validator : validators_) {
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
            job.information_scale * conditionedInformation(closure.edge.information, job.dof);
        spdlog::debug("loop {} -> {} validated (overlap {:.2f}{})", query_id, id,
                      closure.overlap, c.matched ? ", found by global search" : "");
        // Components whose relative pose is unknown join only once loops agree on it.
        const std::vector<GraphEdge> add =
            job.join_by_estimate ? std::vector<GraphEdge>{closure.edge}
                                 : joins_.decide(view, closure.edge, job.join, job.joined);
        if (add.empty()) continue;
        job.closures.insert(job.closures.end(), add.begin(), add.end());
        closed.push_back(id);
        job.view.last_loop_travelled = view.travelled[query_id];
      }
    }
  }
}

void LoopSearch::start(LoopJob job) {
  auto shared = std::make_shared<LoopJob>(std::move(job));
  searching_ = std::async(std::launch::async, [this, shared] {
    run(*shared);
    return std::move(*shared);
  });
}

bool LoopSearch::ready() const {
  return searching_.valid() &&
         searching_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
