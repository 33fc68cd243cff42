#pragma once
// Local bundle adjustment of the landmark cue: the recent frames of one local map and the
// landmarks they observed, refined together through the SDK's solver. Fusing one observation at
// a time takes each frame's pose as exact; a bundle lets the landmarks and the frames' poses
// settle on what all of their observations say.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "plugslam/landmarks/landmark_map.h"
#include "plugslam/solver/projection_factors.h"

namespace plugslam {
inline namespace abi_v1 {

/// One observation of a landmark in a bundle: its track id, (u, v, 1/z) and the information of
/// each of the three (1/z: 0 for a keypoint without depth).
struct BundleObservation {
  uint64_t landmark = 0;                                  ///< the landmark's track id
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();     ///< (u, v, 1/z)
  Eigen::Vector3d information = Eigen::Vector3d::Zero();  ///< diagonal [1/px^2, 1/px^2, m^2]
};

/// One frame of a bundle: the robot in the local map's frame, its camera and what it observed.
struct BundleFrame {
  uint64_t seq = 0;                                         ///< the frame's index in the run
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();   ///< the robot in the map's frame
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  ///< the camera on the robot
  PinholeCamera camera;                                     ///< the pinhole its pixels are in
  bool fixed = false;  ///< the pose is kept as it is (the gauge, or a pose others depend on)
  std::vector<BundleObservation> observations;  ///< the landmarks it matched or created
};

/// How a bundle is solved.
struct BundleOptions {
  int iterations = 5;         ///< Levenberg-Marquardt iterations
  double kernel_scale = 2.0;  ///< Huber width in standard deviations of each residual
};

/// What a bundle adjustment did.
struct BundleResult {
  int frames = 0;          ///< frames in the bundle
  int landmarks = 0;       ///< landmarks refined (observed by two frames or more)
  int observations = 0;    ///< their observations
  double chi2_before = 0;  ///< robust cost before
  double chi2_after = 0;   ///< and after
};

/// Refines the landmarks of `map` that two or more of `frames` observed (one of them not `fixed`,
/// when any is not), and the poses of the frames not `fixed`, by minimising the observations' robust reprojection error; writes the
/// refined positions into `map` and the poses into `frames`. A landmark no longer in the map is
/// skipped. Leaves everything as it was when the solve does not lower the cost.
BundleResult adjustBundle(std::vector<BundleFrame>& frames, LandmarkMap& map,
                          const BundleOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
