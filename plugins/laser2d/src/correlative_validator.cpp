#include "correlative_validator.h"

#include <cmath>

#include "plugslam/pose_space.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

bool CorrelativeValidator::validate(const LocalMap& candidate, const LocalMap& query,
                                    const Eigen::Isometry3d& guess, LoopClosure& closure,
                                    std::string& reason) {
  const auto* map_cloud = scene.find(candidate.scene);
  const auto* query_cloud = scene.find(query.scene);
  if (!map_cloud || !query_cloud || map_cloud->empty() || query_cloud->empty()) {
    reason = "no PointCloud2D '" + scene.name() + "' in both maps";
    return false;
  }
  const double r = resolution();
  std::vector<Eigen::Vector2d> points;
  points.reserve(query_cloud->size());
  for (const auto& p : query_cloud->points)
    if (p.norm() <= max_range()) points.push_back(p);
  points = voxelFilter(points, r);
  if (points.empty()) {
    reason = "no query point within max_range";
    return false;
  }

  CorrelativeOptions o;
  o.linear_window = search_window();
  o.angular_window = angular_window();
  o.angular_step = angular_step();
  o.min_score = min_score();
  o.min_score_margin = min_score_margin();
  o.distinct_translation = distinct_translation();
  o.distinct_rotation = distinct_rotation();

  // Only the part of the candidate the query can reach is rasterized.
  const SE2 g = Space2D::from3D(guess);
  const Eigen::Vector2d reach = Eigen::Vector2d::Constant(max_range() + search_window() + r);
  int levels = 0;
  while ((1 << levels) < 2 * static_cast<int>(std::ceil(search_window() / r)) + 1) ++levels;
  const CorrelativeGrid grid(map_cloud->points, map_cloud->normals, point_extent(), r, levels,
                             g.translation() - reach, g.translation() + reach);
  const CorrelativeMatch m = matchCorrelative(grid, points, g, o);
  if (!m.found) {
    reason = "no pose scores " + std::to_string(min_score()) + " or more";
    return false;
  }
  if (m.ambiguous) {
    reason = "ambiguous: best score " + std::to_string(m.score) + ", a distinct pose scores " +
             std::to_string(m.second_score);
    return false;
  }
  closure.edge.relative = Space2D::to3D(m.pose);
  Eigen::MatrixXd info = Eigen::MatrixXd::Zero(3, 3);
  info(0, 0) = info(1, 1) = 1.0 / (r * r);
  info(2, 2) = 1.0 / (m.angular_step * m.angular_step);
  closure.edge.information = info;
  closure.overlap = m.score;
  closure.residual = 0;
  return true;
}

}  // namespace laser2d
}  // namespace plugslam
