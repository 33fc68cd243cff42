#include "modules/graph/residual_veto.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdint>
#include <utility>

#include "modules/graph/global_optimizer.h"
#include "modules/graph/pose_graph.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

bool ResidualVeto::optimized(PoseGraph& graph, const Solution& solution) {
  const double max_t = translation(), max_r = rotation();
  if (max_t <= 0 && max_r <= 0) return false;
  struct Bad {
    double ratio, t, r;
    int64_t from, to;
  };
  std::vector<Bad> bad;
  for (const GraphEdge& e : solution.edges) {
    if (!e.loop) continue;
    const Eigen::Isometry3d err = edgeError(e, solution.after[e.from], solution.after[e.to]);
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
  for (Loop& l : graph.loops()) {
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

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
