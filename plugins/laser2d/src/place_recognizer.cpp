#include "place_recognizer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "correlative_matcher.h"
#include "plugslam/pose_space.h"

namespace plugslam {
namespace laser2d {
namespace {

constexpr int kMaxLevels = 7;  // as the global match detector's grids
constexpr size_t kCachedGrids = 4;

int floorCell(double v) { return static_cast<int>(std::floor(v)); }

}  // namespace

void PlaceRecognizer::configure() {
  cache_.clear();
  last_query_.clear();
}

std::shared_ptr<const MatchGrid> PlaceRecognizer::gridOf(const GraphView& view, int component,
                                                         int64_t before) {
  std::vector<int64_t> ids;
  double checksum = 0;
  for (int64_t k = 0; k < before; ++k)
    if (view.component(k) == component) {
      ids.push_back(k);
      const Eigen::Vector3d v = toVector(Space2D::from3D(view.origins[static_cast<size_t>(k)]));
      checksum += v.x() + v.y() + v.z();
    }
  for (auto it = cache_.begin(); it != cache_.end(); ++it)
    if (it->component == component && it->maps == ids.size() && it->checksum == checksum) {
      cache_.splice(cache_.begin(), cache_, it);
      return cache_.front().grid;
    }
  const auto clouds = placeClouds(view, scene, ids, max_range(), [&](int64_t k) {
    return Space2D::from3D(view.origins[static_cast<size_t>(k)]);
  });
  auto grid = std::make_shared<const MatchGrid>(
      rasterizeClouds(clouds, resolution(), kMaxLevels,
                      static_cast<uint8_t>(std::lround(255 * unknown_score()))));
  cache_.push_front(Cached{component, ids.size(), checksum, grid});
  while (cache_.size() > kCachedGrids) cache_.pop_back();
  return grid;
}

std::vector<LoopCandidate> PlaceRecognizer::detect(const GraphView& view, const LocalMap& query) {
  std::vector<LoopCandidate> out;
  const int64_t q = query.id;
  const int own = view.component(q);
  // The other components among the older maps: nothing to do in a graph of one.
  std::set<int> others;
  for (int64_t k = 0; k < q; ++k)
    if (view.component(k) != own) others.insert(view.component(k));
  if (others.empty()) return out;
  const double here = view.travelled.at(static_cast<size_t>(q));
  const auto last = last_query_.find(own);
  if (!view.localizing && last != last_query_.end() && here - last->second < query_spacing())
    return out;
  last_query_[own] = here;

  // The query's place: its map and the maps of its component just before it, in its frame.
  std::vector<int64_t> place;
  for (int64_t k = q; k >= 0 && view.component(k) == own &&
                      here - view.travelled[static_cast<size_t>(k)] <= query_path();
       --k)
    place.push_back(k);
  const auto clouds = placeClouds(view, scene, place, max_range(), [&](int64_t k) {
    return Space2D::from3D(view.relative(q, k));
  });
  std::vector<Eigen::Vector2d> all;
  for (const auto& c : clouds) all.insert(all.end(), c.points.begin(), c.points.end());
  const double r = resolution();
  const std::vector<Eigen::Vector2d> points =
      correlativeQuery(all, max_range() + query_path(), std::max(r, query_voxel()));
  if (points.empty()) return out;

  for (int other : others) {
    const auto grid = gridOf(view, other, q);
    const CorrelativeGrid& g = *grid->grid;
    // The whole component: every translation of its grid, a full turn.
    const Eigen::Vector2d half = 0.5 * r * Eigen::Vector2d(g.width(), g.height());
    CorrelativeOptions o;
    o.linear_window = half.maxCoeff();
    o.angular_window = M_PI;
    o.min_score = min_score();
    o.min_score_margin = min_score_margin();
    const SE2 center = se2(g.origin().x() + half.x(), g.origin().y() + half.y(), 0);
    const CorrelativeMatch m = matchCorrelative(g, points, center, o);
    if (!m.found || m.ambiguous) {
      const Eigen::Vector3d apart = toVector(m.pose.inverse() * m.second_pose);
      spdlog::debug("place recognition {} -> component {}: {} ({} leaves)", q, other,
                    m.found ? fmt::format("ambiguous, {:.3f} vs {:.3f} at {:.2f} m, {:.2f} rad",
                                          m.score, m.second_score, apart.head<2>().norm(),
                                          apart.z())
                            : "no pose scores enough",
                    m.leaves);
      continue;
    }
    int seen = 0;
    for (const auto& p : points) {
      const Eigen::Vector2d c = m.pose * p - g.origin();
      seen += grid->isObserved(floorCell(c.x() / r), floorCell(c.y() / r));
    }
    const double observed = static_cast<double>(seen) / static_cast<double>(points.size());
    if (observed < min_observed()) {
      spdlog::debug("place recognition {} -> component {}: score {:.3f} but observed {:.2f}", q,
                    other, m.score, observed);
      continue;
    }
    // Proposed against the other component's maps nearest where the query was found: a local
    // map holds a metre of scans, so the nearest may face elsewhere; the validators decide.
    std::vector<std::pair<double, int64_t>> near;
    for (int64_t k = 0; k < q; ++k)
      if (view.component(k) == other)
        near.emplace_back(
            (view.origins[static_cast<size_t>(k)].translation().head<2>() - m.pose.translation())
                .squaredNorm(),
            k);
    const size_t n = std::min(near.size(), static_cast<size_t>(max_candidates()));
    std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(n), near.end());
    for (size_t i = 0; i < n; ++i) {
      LoopCandidate c;
      c.id = near[i].second;
      c.matched = true;
      c.global = true;
      c.relative = view.origins[static_cast<size_t>(c.id)].inverse() * Space2D::to3D(m.pose);
      c.score = m.score;
      out.push_back(c);
    }
    spdlog::debug("place recognized: map {} is in component {} (near map {}), score {:.2f}, "
                  "observed {:.2f}",
                  q, other, n > 0 ? near[0].second : -1, m.score, observed);
  }
  return out;
}

}  // namespace laser2d
}  // namespace plugslam
