#pragma once
// The laser2d cue: planar points with unit normals, as the preprocessor emits them (robot frame)
// and as the point map keeps them (local-map frame).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "plugslam/archive.h"

namespace plugslam {
namespace laser2d {

/// Points with unit normals (normals face the sensor that saw them) and per-point weights.
struct PointCloud2D {
  std::vector<Eigen::Vector2d> points;   ///< positions [m]
  std::vector<Eigen::Vector2d> normals;  ///< unit normals, one per point
  /// Per-point weight: 1 for a measurement, the number of fused observations in a map.
  std::vector<double> weights;
  /// Where the sensor was, in the cloud's frame (the ray origin for occupancy mapping).
  Eigen::Vector2d sensor_origin = Eigen::Vector2d::Zero();
  /// Changes whenever the cloud is modified (a process-wide unique value, see touch()); lets a
  /// slice keep its search index while the cloud is unchanged.
  uint64_t revision = 0;

  /// Number of points.
  size_t size() const { return points.size(); }
  /// True without points.
  bool empty() const { return points.empty(); }
  /// Removes every point, keeping the capacity.
  void clear();
  /// Appends one point.
  void push(const Eigen::Vector2d& p, const Eigen::Vector2d& n, double w) {
    points.push_back(p);
    normals.push_back(n);
    weights.push_back(w);
  }
  /// Marks the cloud as modified (a new unique revision).
  void touch();
  /// Throws InputError unless points, normals and weights have the same length.
  void checkConsistent() const;
};

/// Serializes a cloud.
void save(OutArchive& ar, const PointCloud2D& cloud);
/// Deserializes a cloud (ParseError when the arrays disagree in length).
void load(InArchive& ar, PointCloud2D& cloud);

}  // namespace laser2d
}  // namespace plugslam
