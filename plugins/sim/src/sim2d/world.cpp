#include "sim2d/world.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  return u.x() * v.y() - u.y() * v.x();
}

// Liang-Barsky: does any part of segment a-b lie inside the box [lo, hi]?
bool segmentTouchesBox(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector2d d = b - a;
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

double pointSegmentDistance(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d e = s.b - s.a;
  const double len2 = e.squaredNorm();
  double u = len2 > 0.0 ? (p - s.a).dot(e) / len2 : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  return (s.a + u * e - p).norm();
}

}  // namespace

World::World(std::vector<Segment> segments, double cell_size) : segments_(std::move(segments)) {
  if (segments_.empty()) throw InputError("sim2d world: expected at least one wall segment");
  for (const Segment& s : segments_) {
    if (!s.a.allFinite() || !s.b.allFinite()) {
      throw InputError("sim2d world: segment end points must be finite numbers");
    }
  }
  min_ = max_ = segments_.front().a;
  for (const Segment& s : segments_) {
    min_ = min_.cwiseMin(s.a).cwiseMin(s.b);
    max_ = max_.cwiseMax(s.a).cwiseMax(s.b);
  }
  const Eigen::Vector2d extent = max_ - min_;
  if (cell_size <= 0.0) {
    // About two segments per occupied cell on office plans; bounded so huge maps stay small.
    cell_size = std::max({1.0, extent.x() / 1024.0, extent.y() / 1024.0});
  }
  cell_ = cell_size;
  grid_origin_ = min_ - Eigen::Vector2d::Constant(0.5 * cell_);
  nx_ = std::max(1, static_cast<int>(std::ceil((extent.x() + cell_) / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((extent.y() + cell_) / cell_)));

  // Conservative indexing (cells grown by eps) so a hit on a cell border is seen from both sides.
  const double eps = 1e-6 * cell_;
  std::vector<std::vector<uint32_t>> cells(static_cast<size_t>(nx_) * ny_);
  for (size_t i = 0; i < segments_.size(); ++i) {
    const Segment& s = segments_[i];
    const Eigen::Vector2d lo = s.a.cwiseMin(s.b), hi = s.a.cwiseMax(s.b);
    const int x0 =
        std::max(0, static_cast<int>(std::floor((lo.x() - grid_origin_.x() - eps) / cell_)));
    const int y0 =
        std::max(0, static_cast<int>(std::floor((lo.y() - grid_origin_.y() - eps) / cell_)));
    const int x1 =
        std::min(nx_ - 1, static_cast<int>(std::floor((hi.x() - grid_origin_.x() + eps) / cell_)));
    const int y1 =
        std::min(ny_ - 1, static_cast<int>(std::floor((hi.y() - grid_origin_.y() + eps) / cell_)));
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        const Eigen::Vector2d clo = grid_origin_ + cell_ * Eigen::Vector2d(cx, cy);
        const Eigen::Vector2d chi = clo + Eigen::Vector2d::Constant(cell_);
        if (segmentTouchesBox(s.a, s.b, clo - Eigen::Vector2d::Constant(eps),
                              chi + Eigen::Vector2d::Constant(eps))) {
          cells[cellIndex(cx, cy)].push_back(static_cast<uint32_t>(i));
        }
      }
    }
  }
  cell_start_.assign(cells.size() + 1, 0);
  for (size_t c = 0; c < cells.size(); ++c) cell_start_[c + 1] = cell_start_[c] + cells[c].size();
  cell_items_.reserve(cell_start_.back());
  for (const auto& c : cells) cell_items_.insert(cell_items_.end(), c.begin(), c.end());
}

double World::intersect(size_t i, const Eigen::Vector2d& o, const Eigen::Vector2d& d) const {
  const Segment& s = segments_[i];
  const Eigen::Vector2d e = s.b - s.a;
  const double denom = cross(d, e);
  if (denom == 0.0) return kInf;
  const Eigen::Vector2d ao = s.a - o;
  const double t = cross(ao, e) / denom;
  const double u = cross(ao, d) / denom;
  if (t < 0.0 || u < 0.0 || u > 1.0) return kInf;
  return t;
}

double World::castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                      double max_range) const {
  if (!(max_range > 0.0)) return kInf;
  // Clip the ray to the grid box (slab method).
  const Eigen::Vector2d gmin = grid_origin_;
  const Eigen::Vector2d gmax = grid_origin_ + cell_ * Eigen::Vector2d(nx_, ny_);
  double t0 = 0.0, t1 = max_range;
  for (int k = 0; k < 2; ++k) {
    if (direction[k] == 0.0) {
      if (origin[k] < gmin[k] || origin[k] > gmax[k]) return kInf;
      continue;
    }
    double ta = (gmin[k] - origin[k]) / direction[k], tb = (gmax[k] - origin[k]) / direction[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return kInf;

  const Eigen::Vector2d p = origin + t0 * direction;
  int cx = std::clamp(static_cast<int>(std::floor((p.x() - gmin.x()) / cell_)), 0, nx_ - 1);
  int cy = std::clamp(static_cast<int>(std::floor((p.y() - gmin.y()) / cell_)), 0, ny_ - 1);
  const int step_x = direction.x() > 0.0 ? 1 : -1;
  const int step_y = direction.y() > 0.0 ? 1 : -1;
  double t_max_x = kInf, t_max_y = kInf, t_delta_x = kInf, t_delta_y = kInf;
  if (direction.x() != 0.0) {
    const double bx = gmin.x() + cell_ * (cx + (step_x > 0 ? 1 : 0));
    t_max_x = (bx - origin.x()) / direction.x();
    t_delta_x = cell_ / std::abs(direction.x());
  }
  if (direction.y() != 0.0) {
    const double by = gmin.y() + cell_ * (cy + (step_y > 0 ? 1 : 0));
    t_max_y = (by - origin.y()) / direction.y();
    t_delta_y = cell_ / std::abs(direction.y());
  }

  double best = kInf;
  while (true) {
    const int c = cellIndex(cx, cy);
    for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      best = std::min(best, intersect(cell_items_[k], origin, direction));
    }
    const double t_exit = std::min(t_max_x, t_max_y);
    // Every hit before t_exit lies in a cell already visited, so the nearest is final.
    if (best <= t_exit || t_exit > t1) break;
    if (t_max_x < t_max_y) {
      cx += step_x;
      t_max_x += t_delta_x;
      if (cx < 0 || cx >= nx_) break;
    } else {
      cy += step_y;
      t_max_y += t_delta_y;
      if (cy < 0 || cy >= ny_) break;
    }
  }
  return best <= max_range ? best : kInf;
}

bool World::crosses(const Eigen::Vector2d& p, const Eigen::Vector2d& q) const {
  const double len = (q - p).norm();
  if (len == 0.0) return clearance(p, 1e-12) < 1e-12;
  return std::isfinite(castRay(p, (q - p) / len, len));
}

double World::clearance(const Eigen::Vector2d& p, double max_distance) const {
  const int x0 =
      std::max(0, static_cast<int>(std::floor((p.x() - max_distance - grid_origin_.x()) / cell_)));
  const int y0 =
      std::max(0, static_cast<int>(std::floor((p.y() - max_distance - grid_origin_.y()) / cell_)));
  const int x1 = std::min(
      nx_ - 1, static_cast<int>(std::floor((p.x() + max_distance - grid_origin_.x()) / cell_)));
  const int y1 = std::min(
      ny_ - 1, static_cast<int>(std::floor((p.y() + max_distance - grid_origin_.y()) / cell_)));
  double best = max_distance;
  for (int cy = y0; cy <= y1; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      const int c = cellIndex(cx, cy);
      for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        best = std::min(best, pointSegmentDistance(p, segments_[cell_items_[k]]));
      }
    }
  }
  return best;
}

void World::saveSegments(const std::string& path) const {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "# plugslam sim2d segment list: x1 y1 x2 y2 (metres) per line\n";
    out.precision(17);
    for (const Segment& s : segments_) {
      out << s.a.x() << ' ' << s.a.y() << ' ' << s.b.x() << ' ' << s.b.y() << '\n';
    }
  });
}

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
