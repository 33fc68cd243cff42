#pragma once
// Dense point-to-plane alignment of two depth images (projective association, as KinectFusion's
// ICP), from a given start. It measures how well a pose explains two depth images, with nothing
// but the depth: the bench uses it to check a dataset's reference poses against the dataset's
// own depth (scripts/bench/visual.sh, rgbd_depth_check), independently of the keypoint cue.
#include <vector>

#include "plugslam/geometry.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace rgbd {

/// A depth image as organised points and normals in its camera's frame.
struct DepthSurface {
  int width = 0;                         ///< pixels per row
  int height = 0;                        ///< rows
  CameraIntrinsics camera;               ///< the pinhole the points were back-projected through
  std::vector<Eigen::Vector3f> points;   ///< per pixel; z = 0: no reading
  std::vector<Eigen::Vector3f> normals;  ///< per pixel, unit; zero where not defined
};

/// Back-projects `depth` through the pinhole `camera` (its distortion must be kNone). A normal
/// is the cross product of the differences between the neighbours `spacing` pixels away; it is
/// left undefined at holes and across depth steps larger than `max_step` times the depth
/// (occlusion edges, where the neighbours lie on different surfaces).
DepthSurface makeDepthSurface(const DepthImage& depth, const CameraIntrinsics& camera,
                              int spacing = 2, double max_step = 0.05);

/// The pixel of `surface` that point `x` (in the surface's camera frame) projects onto, when
/// that pixel has a reading with a normal: projective association, the nearest pixel. -1 when
/// x is behind the camera, outside the image, or lands where no normal is defined.
long projectOnto(const DepthSurface& surface, const Eigen::Vector3d& x);

/// Settings of a dense alignment.
struct DepthAlignmentOptions {
  int stride = 2;              ///< use every stride-th pixel of the moving image, in both axes
  double max_distance = 0.05;  ///< [m] pairs farther apart than this are not the same surface
  double huber = 0.005;        ///< [m] robust kernel width on the point-to-plane residual
  int max_iterations = 40;     ///< Gauss-Newton steps at most
  double min_step = 1e-7;      ///< stop once the update is smaller (rad, m)
};

/// The outcome of a dense alignment.
struct DepthAlignmentResult {
  SE3 pose = SE3::Identity();  ///< fixed <- moving
  int points = 0;              ///< moving points with a reading (after the stride)
  int pairs_initial = 0;       ///< associated pairs at the start
  int pairs = 0;               ///< associated pairs at the end
  double rms_initial = 0;      ///< [m] point-to-plane RMS of the associated pairs at the start
  double rms = 0;              ///< [m] the same at the end
  int iterations = 0;          ///< Gauss-Newton steps taken
  /// Smallest over largest eigenvalue of the final normal matrix (rotation in rad and
  /// translation in m, unscaled): near zero when the surfaces leave a direction unconstrained.
  double conditioning = 0;
  bool ok = false;  ///< at least 6 pairs at the end and a solvable system
};

/// Aligns `moving` to `fixed` starting at `start` (fixed <- moving): every iteration projects
/// the moving points into the fixed image, pairs each with the point it lands on, and takes a
/// Gauss-Newton step on the Huber-weighted point-to-plane residuals n . (T p - q).
DepthAlignmentResult alignDepth(const DepthSurface& fixed, const DepthSurface& moving,
                                const SE3& start, const DepthAlignmentOptions& options = {});

}  // namespace rgbd
}  // namespace plugslam
