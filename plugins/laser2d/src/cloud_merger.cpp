#include "cloud_merger.h"

#include "plugslam/pose_space.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

void CloudMerger::append(PropertyContainer& into, const PropertyContainer& from,
                         const Eigen::Isometry3d& pose) {
  const SE2 t = Space2D::from3D(pose);
  const double range2 = max_range() > 0 ? max_range() * max_range() : -1;
  for (const PropertyBase& property : from) {
    if (property.type() != std::type_index(typeid(PointCloud2D))) continue;
    const auto& source = from.get<PointCloud2D>(property.name());
    PointCloud2D* target = into.find<PointCloud2D>(property.name());
    // The target keeps its own sensor origin: where its map was seen from.
    if (!target) target = &into.set(property.name(), PointCloud2D{});
    const bool normals = source.normals.size() == source.size();
    for (size_t i = 0; i < source.size(); ++i) {
      if (range2 > 0 && source.points[i].squaredNorm() > range2) continue;
      const double w = i < source.weights.size() ? source.weights[i] : 1.0;
      target->push(t * source.points[i],
                   normals ? Eigen::Vector2d(t.linear() * source.normals[i])
                           : Eigen::Vector2d::Zero(),
                   w);
    }
    // A new revision: slices must not reuse a search index built for the cloud before.
    target->touch();
  }
}

}  // namespace laser2d
}  // namespace plugslam
