#include "modules/graph/consistency_filter.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdint>
#include <functional>

#include "modules/graph/pose_graph.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

bool ConsistencyFilter::consistent(const PoseGraph& graph, const GraphEdge& a,
                                   const GraphEdge& b) const {
  // The cycle a.from -> a.to (loop a) -> b.to (estimate) -> b.from (loop b, inverted) ->
  // a.from (estimate) is the identity when both loops are right; the estimate's legs are short
  // when the loops close the same revisit, so their drift is small.
  const Eigen::Isometry3d cycle = a.relative * graph.relative(a.to, b.to) *
                                  b.relative.inverse() * graph.relative(b.from, a.from);
  // Maps of different components have no odometry between them: no evidence either way.
  const auto& components = graph.components();
  if (components[a.to] != components[b.to] || components[a.from] != components[b.from])
    return true;
  const auto& travelled = graph.travelled();
  const double path = std::abs(travelled[a.to] - travelled[b.to]) +
                      std::abs(travelled[a.from] - travelled[b.from]);
  // A leg through a tracking failure's weak edge holds that edge's error too: the tolerance
  // grows by its std. dev. (rotation, and the rotation's lever over the legs' path).
  const auto& weak_t = graph.weakVarianceT();
  const auto& weak_r = graph.weakVarianceR();
  const double var_t =
      std::abs(weak_t[a.to] - weak_t[b.to]) + std::abs(weak_t[a.from] - weak_t[b.from]);
  const double var_r =
      std::abs(weak_r[a.to] - weak_r[b.to]) + std::abs(weak_r[a.from] - weak_r[b.from]);
  if (var_t + var_r > 0 && weak_edge_sigmas() <= 0) return true;
  const double k = weak_edge_sigmas();
  const double t_err = cycle.translation().norm();
  const double r_err = Eigen::AngleAxisd(cycle.linear()).angle();
  return t_err <= translation() + drift() * path +
                      k * (std::sqrt(var_t) + std::sqrt(var_r) * path) &&
         r_err <= rotation() + drift() * path + k * std::sqrt(var_r);
}

void ConsistencyFilter::loopsAdded(PoseGraph& graph) {
  // The loops closed recently (within the window of travel before the newest) are re-decided
  // together: the largest set of mutually consistent ones is kept (pairwise consistency
  // maximization, solved exactly: the window holds few loops).
  std::vector<Loop>& loops = graph.loops();
  if (loops.empty()) return;
  const auto& travelled = graph.travelled();
  const double newest = travelled[loops.back().edge.to];
  std::vector<size_t> recent;
  for (size_t i = 0; i < loops.size(); ++i)
    if (!loops[i].vetoed && newest - travelled[loops[i].edge.to] <= window())
      recent.push_back(i);
  if (recent.size() > 24) recent.erase(recent.begin(), recent.end() - 24);
  const size_t n = recent.size();
  std::vector<uint32_t> adj(n, 0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      if (consistent(graph, loops[recent[i]].edge, loops[recent[j]].edge)) {
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
    Loop& l = loops[recent[i]];
    if (l.active != keep)
      spdlog::debug("loop {} -> {} {} by the consistency check", l.edge.to, l.edge.from,
                    keep ? "restored" : "rejected");
    l.active = keep;
  }
}

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
