#include "point_map_slice.h"

#include <cmath>
#include <limits>

namespace plugslam {
namespace laser2d {

void PointMapSlice::integrate(const MergeContext<Space2D>& context) {
  const Pose& t = context.pose;
  const PointCloud2D* measured = measurement.get();
  if (measured->empty()) return;
  measured->checkConsistent();
  PointCloud2D* map = &scene.getOrInsert();
  map->checkConsistent();
  const Eigen::Vector2d robot = t.translation();

  // Clip: compact the arrays in place, keeping the order of the surviving points.
  if (clip_radius() > 0) {
    const double clip2 = clip_radius() * clip_radius();
    size_t kept = 0;
    for (size_t j = 0; j < map->size(); ++j) {
      if ((map->points[j] - robot).squaredNorm() > clip2) continue;
      if (kept != j) {
        map->points[kept] = map->points[j];
        map->normals[kept] = map->normals[j];
        map->weights[kept] = map->weights[j];
      }
      ++kept;
    }
    map->points.resize(kept);
    map->normals.resize(kept);
    map->weights.resize(kept);
  }

  const double radius = fusion_radius();
  const double radius2 = radius * radius;
  const double cos_normal = max_normal_angle() >= M_PI ? -2.0 : std::cos(max_normal_angle());
  index_.reset(radius, map->size() + measured->size());
  for (size_t j = 0; j < map->size(); ++j) index_.insert(map->points[j], static_cast<int>(j));

  const Eigen::Matrix2d r = t.linear();
  const double clip2 =
      clip_radius() > 0 ? clip_radius() * clip_radius() : std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < measured->size(); ++i) {
    const Eigen::Vector2d p = t * measured->points[i];
    if ((p - robot).squaredNorm() > clip2) continue;  // would be clipped at once
    const Eigen::Vector2d n = r * measured->normals[i];
    int best = -1;
    double best_d = radius2;
    index_.forNeighbours(p, [&](int j) {
      const double d = (map->points[j] - p).squaredNorm();
      if (d <= best_d && map->normals[j].dot(n) >= cos_normal) {
        best_d = d;
        best = j;
      }
    });
    if (best < 0) {
      map->push(p, n, measured->weights[i]);
      index_.insert(p, static_cast<int>(map->size() - 1));
      continue;
    }
    double& w = map->weights[best];
    const double wi = measured->weights[i];
    map->points[best] = (w * map->points[best] + wi * p) / (w + wi);
    const Eigen::Vector2d fused = w * map->normals[best] + wi * n;
    if (fused.squaredNorm() > 1e-12) map->normals[best] = fused.normalized();
    w = std::min(w + wi, max_weight());
  }
  map->sensor_origin = robot;
  map->touch();
}

}  // namespace laser2d
}  // namespace plugslam
