#include "modules/graph/component_join.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

std::vector<GraphEdge> ComponentJoin::decide(const GraphView& view, const GraphEdge& edge,
                                             const JoinRule& rule,
                                             std::vector<std::pair<int, int>>& joined) {
  const int own = view.component(edge.to), other = view.component(edge.from);
  const auto pair = std::make_pair(std::min(own, other), std::max(own, other));
  if (own == other || std::find(joined.begin(), joined.end(), pair) != joined.end())
    return {edge};
  const Eigen::Isometry3d query = view.origins[static_cast<size_t>(edge.to)];
  const Eigen::Isometry3d found = view.origins[static_cast<size_t>(edge.from)] * edge.relative;
  const double here = view.travelled[static_cast<size_t>(edge.to)];
  // The components' relative pose this loop implies (own world -> other's) must put each held
  // loop's query where that loop found it.
  const Eigen::Isometry3d offset = found * query.inverse();
  auto& held = held_[{own, other}];
  std::vector<GraphEdge> out{edge};
  std::vector<int64_t> places{edge.to};
  for (const Held& h : held) {
    const double path = std::abs(here - h.travelled);
    const Eigen::Isometry3d d = (offset * h.query).inverse() * h.found;
    if (d.translation().norm() > rule.translation + rule.drift * path ||
        Eigen::AngleAxisd(d.rotation()).angle() > rule.rotation + rule.angular_drift * path)
      continue;
    out.push_back(h.edge);
    if (std::find(places.begin(), places.end(), h.edge.to) == places.end())
      places.push_back(h.edge.to);
  }
  const int needed =
      view.localizing && other == view.component(0) ? rule.agreeing_localizing : rule.agreeing;
  if (static_cast<int>(places.size()) < needed) {
    held.push_back(Held{edge, here, query, found});
    if (held.size() > rule.max_held) held.erase(held.begin());
    spdlog::debug("loop {} -> {} would join components {} and {}: held, {} of {} places agree",
                  edge.to, edge.from, own, other, places.size(), needed);
    return {};
  }
  spdlog::info("components {} and {} joined: {} loops from {} places agree", own, other,
               out.size(), places.size());
  held.clear();
  joined.push_back(pair);
  return out;
}

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
