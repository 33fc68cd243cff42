#pragma once
// A local map: the scene container built by the tracker over a stretch of frames, and a node of
// the pose graph. Poses are stored embedded in 3D so the back-end and the writers are shared
// by 2D and 3D pipelines; `dimension` says which one it is.
#include <Eigen/Geometry>
#include <cstdint>

#include "plugslam/property_container.h"

namespace plugslam {
inline namespace abi_v1 {

/// One local map and how it was reached from the previous one.
struct LocalMap {
  int64_t id = 0;                                            ///< 0, 1, 2, ... in creation order
  int dimension = 2;                                         ///< 2 or 3
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< map frame in the world
  PropertyContainer scene;                                   ///< one entry per cue
  uint64_t first_seq = 0, last_seq = 0;                      ///< frames merged into it
  double first_stamp = 0, last_stamp = 0;
  int64_t previous = -1;  ///< id of the map it was split from (-1 for the first)
  /// Pose of this map's origin in the previous map's frame, as the tracker measured it.
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  /// Information of `relative` in the tangent space (3x3 in 2D: x, y, theta; 6x6 in 3D).
  Eigen::MatrixXd information;
};

}  // namespace abi_v1
}  // namespace plugslam
