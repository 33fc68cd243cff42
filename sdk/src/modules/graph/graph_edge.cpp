#include "plugslam/graph_edge.h"

#include <algorithm>

namespace plugslam {
inline namespace abi_v1 {

Eigen::MatrixXd betweenFactorInformation(const GraphEdge& edge, int dimension) {
  if (dimension == 2) return edge.information;
  // The tracker's information is over the rotation vector; the factor's rotation error is half
  // of it, so the rotation block scales by 2 on each side.
  Eigen::Matrix<double, 6, 1> d;
  d << 1, 1, 1, 2, 2, 2;
  return d.asDiagonal() * edge.information * d.asDiagonal();
}

std::vector<int64_t> graphComponents(size_t maps, const std::vector<GraphEdge>& edges) {
  // Union-find; the lower root wins, so a component is named by its first map.
  std::vector<int64_t> parent(maps);
  for (size_t i = 0; i < maps; ++i) parent[i] = static_cast<int64_t>(i);
  const auto root = [&parent](int64_t c) {
    while (parent[static_cast<size_t>(c)] != c)
      c = parent[static_cast<size_t>(c)] = parent[static_cast<size_t>(parent[static_cast<size_t>(c)])];
    return c;
  };
  const auto valid = [maps](int64_t id) { return id >= 0 && static_cast<size_t>(id) < maps; };
  for (const auto& e : edges) {
    if (!valid(e.from) || !valid(e.to)) continue;
    const int64_t a = root(e.from), b = root(e.to);
    parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
  }
  for (size_t i = 0; i < maps; ++i) parent[i] = root(static_cast<int64_t>(i));
  return parent;
}

}  // namespace abi_v1
}  // namespace plugslam
