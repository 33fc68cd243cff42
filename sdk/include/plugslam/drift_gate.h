#pragma once
// The drift gate that loop detectors share: the current estimate is trusted only as far as the
// path since a candidate may have drifted, so the search radius grows with that path.
#include <cstdint>
#include <utility>
#include <vector>

#include "plugslam/loop_closure.h"

namespace plugslam {
inline namespace abi_v1 {

/// Older maps near a query in the current estimate: at least `min_travel` of path back, with
/// their origin within `radius + drift * path since them` (capped at `max_radius`) of the query's.
struct DriftGate {
  double radius = 0;      ///< search radius with no drift [m]
  double drift = 0;       ///< growth of the radius per metre of path since the candidate
  double max_radius = 0;  ///< cap on the grown radius [m]
  double min_travel = 0;  ///< a candidate lies at least this much path back [m]

  /// The radius for a candidate `since` metres of path back.
  double radiusAt(double since) const;
  /// The maps inside the gate of map `query` as (distance, id), nearest first.
  std::vector<std::pair<double, int64_t>> near(const GraphView& view, int64_t query) const;
};

/// The first `max_count` of `near` (nearest first, as DriftGate::near gives them) that lie at
/// least `spacing` of path from every one kept before (spacing 0: the nearest whatever their path).
std::vector<std::pair<double, int64_t>> spreadAlongPath(
    const GraphView& view, const std::vector<std::pair<double, int64_t>>& near, int max_count,
    double spacing);

}  // namespace abi_v1
}  // namespace plugslam
