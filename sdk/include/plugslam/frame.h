#pragma once
// One synchronised time step as it flows through the pipeline (DESIGN.md, "Data flow").
#include <Eigen/Geometry>
#include <cstdint>

#include "plugslam/property_container.h"

namespace plugslam {
inline namespace abi_v1 {

/// Where the tracker put the robot at this frame (2D poses are embedded as rotations about z).
struct FrameEstimate {
  bool valid = false;                                     ///< a tracker ran on this frame
  int64_t local_map = -1;                                 ///< id of the local map it belongs to
  Eigen::Isometry3d in_map = Eigen::Isometry3d::Identity();  ///< pose in the local map's frame
  /// Pose in the world at the time: the pipeline composes it from the map's origin.
  Eigen::Isometry3d world = Eigen::Isometry3d::Identity();
  /// The local map is frozen (localization in saved maps): nothing will correct `world` later,
  /// so a sink may use it as final. Last members: plugins built before them read the rest.
  bool frozen = false;
  /// The alignment failed: the pose is the motion model's prediction, not a measured one.
  bool lost = false;
  /// The alignment converged but could not be checked (its cues barely measured the motion and
  /// no hypothesis without the prediction could be made): the pose may be wrong.
  bool unchecked = false;
};

/// All readings of one time step, then their preprocessed cues and the pose estimate.
struct Frame {
  uint64_t seq = 0;               ///< 0-based index in the run
  double stamp = 0;               ///< seconds
  PropertyContainer raw;          ///< readings by sensor name, filled by the Source
  PropertyContainer measurement;  ///< one entry per cue, filled by the PreProcessors
  FrameEstimate estimate;         ///< filled by the tracker (and the pipeline: world)
};

}  // namespace abi_v1
}  // namespace plugslam
