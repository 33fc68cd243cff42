#include "global_match_detector.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "plugslam/pose_space.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {
namespace {

constexpr int kBlurCells = 2;  // gaussian of sigma = one cell, cut at two cells
constexpr int kMaxLevels = 7;  // pooled levels: more cost memory and prune little

int floorCell(double v) { return static_cast<int>(std::floor(v)); }

}  // namespace

MatchGrid rasterizeClouds(const std::vector<PlacedCloud>& clouds, double resolution, int levels,
                          uint8_t unknown) {
  const double r = resolution;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
  for (const auto& c : clouds) {
    lo = lo.cwiseMin(c.origin);
    hi = hi.cwiseMax(c.origin);
    for (const auto& p : c.points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  if ((lo.array() > hi.array()).any()) lo = hi = Eigen::Vector2d::Zero();
  const Eigen::Vector2d origin = lo - Eigen::Vector2d::Constant((kBlurCells + 1) * r);
  const int width = floorCell((hi.x() - origin.x()) / r) + kBlurCells + 2;
  const int height = floorCell((hi.y() - origin.y()) / r) + kBlurCells + 2;
  const size_t cells = static_cast<size_t>(width) * height;
  std::vector<uint8_t> observed(cells, 0), hit(cells, 0);
  const auto index = [&](const Eigen::Vector2d& q, size_t& i) {
    const int x = floorCell((q.x() - origin.x()) / r), y = floorCell((q.y() - origin.y()) / r);
    if (x < 0 || y < 0 || x >= width || y >= height) return false;
    i = static_cast<size_t>(y) * width + x;
    return true;
  };
  for (const auto& c : clouds) {
    for (size_t k = 0; k < c.points.size(); ++k) {
      const Eigen::Vector2d& p = c.points[k];
      // The ray from the map's origin to the point crossed free space; it stops a cell short
      // so a point's own cell stays a hit.
      const Eigen::Vector2d d = p - c.origin;
      const double length = d.norm() - r;
      const int steps = static_cast<int>(std::ceil(length / (0.5 * r)));
      size_t i = 0;
      for (int s = 0; s < steps; ++s)
        if (index(c.origin + d * (0.5 * r * s / (length + r)), i)) observed[i] = 1;
      // A point also covers one cell either side along its tangent (sparse far walls).
      const Eigen::Vector2d tangent =
          k < c.normals.size() ? Eigen::Vector2d(-c.normals[k].y(), c.normals[k].x())
                               : Eigen::Vector2d::Zero();
      for (int t = -2; t <= 2; ++t)
        if (index(p + (0.5 * r * t) * tangent, i)) observed[i] = hit[i] = 1;
    }
  }
  std::vector<uint8_t> base(cells);
  for (size_t i = 0; i < cells; ++i) base[i] = observed[i] ? 0 : unknown;
  uint8_t kernel[2 * kBlurCells + 1][2 * kBlurCells + 1];
  for (int dy = -kBlurCells; dy <= kBlurCells; ++dy)
    for (int dx = -kBlurCells; dx <= kBlurCells; ++dx)
      kernel[dy + kBlurCells][dx + kBlurCells] =
          static_cast<uint8_t>(std::lround(255 * std::exp(-0.5 * (dx * dx + dy * dy))));
  for (int cy = 0; cy < height; ++cy)
    for (int cx = 0; cx < width; ++cx) {
      if (!hit[static_cast<size_t>(cy) * width + cx]) continue;
      for (int y = std::max(cy - kBlurCells, 0); y <= std::min(cy + kBlurCells, height - 1); ++y)
        for (int x = std::max(cx - kBlurCells, 0); x <= std::min(cx + kBlurCells, width - 1);
             ++x) {
          uint8_t& v = base[static_cast<size_t>(y) * width + x];
          v = std::max(v, kernel[y - cy + kBlurCells][x - cx + kBlurCells]);
        }
    }
  MatchGrid out;
  out.grid = std::make_unique<CorrelativeGrid>(r, origin, width, height, std::move(base),
                                               std::clamp(levels, 0, kMaxLevels), unknown);
  out.observed = std::move(observed);
  return out;
}

std::vector<PlacedCloud> placeClouds(const GraphView& view, const Input<PointCloud2D>& scene,
                                     const std::vector<int64_t>& ids, double max_range,
                                     const std::function<SE2(int64_t)>& place) {
  std::vector<PlacedCloud> clouds;
  const double range2 = max_range * max_range;
  for (int64_t k : ids) {
    const auto* cloud = scene.find(view.maps[static_cast<size_t>(k)]->scene);
    if (!cloud) continue;
    const SE2 t = place(k);
    PlacedCloud placed;
    placed.origin = t.translation();
    for (size_t i = 0; i < cloud->size(); ++i) {
      if (cloud->points[i].squaredNorm() > range2) continue;
      placed.points.push_back(t * cloud->points[i]);
      if (i < cloud->normals.size()) placed.normals.push_back(t.linear() * cloud->normals[i]);
    }
    if (placed.normals.size() != placed.points.size()) placed.normals.clear();
    clouds.push_back(std::move(placed));
  }
  return clouds;
}

void GlobalMatchDetector::configure() {
  cache_.clear();
  last_query_ = -1e300;
}

std::shared_ptr<const MatchGrid> GlobalMatchDetector::gridOf(const GraphView& view, int64_t id,
                                                             int64_t before) {
  for (auto it = cache_.begin(); it != cache_.end(); ++it)
    if (it->id == id) {
      cache_.splice(cache_.begin(), cache_, it);
      return cache_.front().grid;
    }
  // The candidate and the maps next to it along the path, placed by the estimate (consecutive
  // maps agree closely: their relative poses are the tracker's).
  const double at = view.travelled[id];
  int64_t first = id, last = id;
  while (first > 0 && at - view.travelled[first - 1] <= neighbourhood()) --first;
  // Only maps older than the query: they are closed, nothing modifies them any more.
  while (last + 1 < before && view.travelled[last + 1] - at <= neighbourhood())
    ++last;
  std::vector<int64_t> ids;
  for (int64_t k = first; k <= last; ++k) ids.push_back(k);
  const std::vector<PlacedCloud> clouds = placeClouds(
      view, scene, ids, max_range(), [&](int64_t k) { return Space2D::from3D(view.relative(id, k)); });
  const double r = resolution();
  const int levels = correlativeLevels(max_radius(), r, kMaxLevels);
  auto grid = std::make_shared<const MatchGrid>(rasterizeClouds(
      clouds, r, levels, static_cast<uint8_t>(std::lround(255 * unknown_score()))));
  cache_.push_front(Cached{id, grid});
  while (cache_.size() > static_cast<size_t>(cache_size())) cache_.pop_back();
  return grid;
}

std::vector<LoopCandidate> GlobalMatchDetector::detect(const GraphView& view,
                                                       const LocalMap& query) {
  std::vector<LoopCandidate> out;
  const double here = view.travelled.at(query.id);
  if (here - last_query_ < query_spacing()) return out;
  if (after_loop() > 0 && view.last_loop_travelled >= 0 &&
      here - view.last_loop_travelled < after_loop())
    return out;
  const auto* query_cloud = scene.find(query.scene);
  if (!query_cloud || query_cloud->empty()) return out;

  const DriftGate gate{radius(), drift(), max_radius(), min_travel()};
  const auto chosen =
      spreadAlongPath(view, gate.near(view, query.id), max_candidates(), candidate_spacing());
  if (chosen.empty()) return out;
  last_query_ = here;

  const double r = resolution();
  const std::vector<Eigen::Vector2d> points = correlativeQuery(query_cloud->points, max_range(), r);
  if (points.empty()) return out;

  for (const auto& [distance, id] : chosen) {
    const double since = here - view.travelled[id];
    const auto grid = gridOf(view, id, query.id);
    CorrelativeOptions o;
    o.linear_window = gate.radiusAt(since);
    o.angular_window = std::min(max_angular_window(), angular_window() + angular_drift() * since);
    o.min_score = min_score();
    o.min_score_margin = min_score_margin();
    const SE2 guess = Space2D::from3D(view.relative(id, query.id));
    const CorrelativeMatch m = matchCorrelative(*grid->grid, points, guess, o);
    if (!m.found || m.ambiguous) {
      spdlog::debug("global match {} -> {}: {} (window {:.1f} m, {:.2f} rad, {} leaves)", query.id,
                    id,
                    m.found ? fmt::format("ambiguous, {:.3f} vs {:.3f}", m.score, m.second_score)
                            : "no pose scores enough",
                    o.linear_window, o.angular_window, m.leaves);
      continue;
    }
    // The score counts unobserved cells at `unknown_score`: the match must also overlap what the
    // candidate saw.
    int seen = 0;
    for (const auto& p : points) {
      const Eigen::Vector2d q = m.pose * p - grid->grid->origin();
      seen += grid->isObserved(floorCell(q.x() / r), floorCell(q.y() / r));
    }
    const double observed = static_cast<double>(seen) / static_cast<double>(points.size());
    const Eigen::Vector3d shift = toVector(guess.inverse() * m.pose);
    spdlog::debug("global match {} -> {}: score {:.3f}, observed {:.2f}, shift {:.2f} m {:.3f} rad",
                  query.id, id, m.score, observed, shift.head<2>().norm(), shift.z());
    if (observed < min_observed()) continue;
    LoopCandidate c;
    c.id = id;
    c.matched = true;
    c.relative = Space2D::to3D(m.pose);
    c.score = m.score;
    out.push_back(c);
  }
  return out;
}

}  // namespace laser2d
}  // namespace plugslam
