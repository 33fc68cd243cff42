#include "plugslam/drift_gate.h"

#include <algorithm>
#include <cmath>

namespace plugslam {
inline namespace abi_v1 {

double DriftGate::radiusAt(double since) const { return std::min(max_radius, radius + drift * since); }

std::vector<std::pair<double, int64_t>> DriftGate::near(const GraphView& view,
                                                        int64_t query) const {
  std::vector<std::pair<double, int64_t>> found;
  const Eigen::Vector3d at = view.origins.at(query).translation();
  const double here = view.travelled.at(query);
  for (int64_t id = 0; id < query; ++id) {
    const double since = here - view.travelled[id];
    if (since < min_travel) continue;
    const double d = (view.origins[id].translation() - at).norm();
    if (d <= radiusAt(since)) found.emplace_back(d, id);
  }
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<std::pair<double, int64_t>> spreadAlongPath(
    const GraphView& view, const std::vector<std::pair<double, int64_t>>& near, int max_count,
    double spacing) {
  std::vector<std::pair<double, int64_t>> kept;
  for (const auto& candidate : near) {
    if (static_cast<int>(kept.size()) >= max_count) break;
    const bool crowded = std::any_of(kept.begin(), kept.end(), [&](const auto& k) {
      return std::abs(view.travelled[k.second] - view.travelled[candidate.second]) < spacing;
    });
    if (!crowded) kept.push_back(candidate);
  }
  return kept;
}

}  // namespace abi_v1
}  // namespace plugslam
