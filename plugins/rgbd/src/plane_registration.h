#pragma once
// Wide-baseline registration of two depth images by their planes: where a camera sees a painted
// wall, a bare room corner, a floor, its keypoints are too few to relocalise from, but the
// surfaces themselves fix the pose. Three planes whose normals span space (two walls and the
// floor of a corner) fix all six directions; their pairwise angles match the same three planes
// seen from anywhere, so no prediction is needed. Every matching triple is a hypothesis, and
// each is checked against the whole of both images: points of the moving image must lie on the
// fixed image's surface, never in the space in front of it that the fixed camera saw empty.
#include <vector>

#include "depth_alignment.h"
#include "depth_model.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace rgbd {

/// A plane of a depth image: n . x = d in its camera's frame, n pointing at the camera.
struct DepthPlane {
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();  ///< unit normal, towards the camera
  double d = 0;                                  ///< n . x = d (negative: the camera is in front)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< mean of its points
  int support = 0;                                     ///< pixels on it
};

/// Settings of plane extraction and registration.
struct PlaneRegistrationOptions {
  /// [rad] a pixel's normal within this of its region's joins it; normals of one plane seen
  /// from two places agree within it, so triples are matched with the same tolerance.
  double max_angle = 0.15;
  /// [m] a pixel within this plus three sigmas of its reading's noise of the region's plane
  /// joins it (and a point is on the other image's surface within the same).
  double max_distance = 0.02;
  double min_share = 0.03;  ///< a plane holds at least this share of the image's readings
  int max_planes = 10;      ///< the largest planes kept per image
  /// Normals of a triple must span space: |det [n1 n2 n3]| at least this (0.25: no two of
  /// them within 15 degrees of each other's plane).
  double min_spread = 0.25;
  int check_points = 1500;  ///< points of the moving image each hypothesis is checked on
};

/// The largest planar regions of `surface` (region growing over its organised normals), largest
/// first. `noise` widens the distance tolerance with range.
std::vector<DepthPlane> extractPlanes(const DepthSurface& surface, const DepthNoiseModel& noise,
                                      const PlaneRegistrationOptions& options = {});

/// How well a pose explains the moving image against the fixed one.
struct SurfaceAgreement {
  int on = 0;        ///< moving points on the fixed surface, with a matching normal
  int in_front = 0;  ///< moving points in the space the fixed camera saw empty
  int checked = 0;   ///< moving points checked (with a reading and a normal)
  /// Of the moving points the fixed camera could judge, the share on its surface.
  double share() const { return on + in_front > 0 ? double(on) / double(on + in_front) : 0.0; }
};

/// Checks pose `t` (fixed <- moving) on about `options.check_points` points of `moving`.
SurfaceAgreement checkAgreement(const DepthSurface& fixed, const DepthSurface& moving,
                                const SE3& t, const DepthNoiseModel& noise,
                                const PlaneRegistrationOptions& options = {});

/// A pose hypothesis from matched planes, with its agreement.
struct PlaneHypothesis {
  SE3 pose = SE3::Identity();  ///< fixed <- moving
  SurfaceAgreement agreement;  ///< at `pose`
  int planes = 0;              ///< planes matched (3)
};

/// Every pose that maps three planes of `moving` onto three of `fixed` with matching normals,
/// checked on both images; best first (most points on the surface net of those in front).
std::vector<PlaneHypothesis> registerPlanes(const DepthSurface& fixed,
                                            const std::vector<DepthPlane>& fixed_planes,
                                            const DepthSurface& moving,
                                            const std::vector<DepthPlane>& moving_planes,
                                            const DepthNoiseModel& noise,
                                            const PlaneRegistrationOptions& options = {});

}  // namespace rgbd
}  // namespace plugslam
