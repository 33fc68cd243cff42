#pragma once
// Ray-cast rendering of a sim3d World through a pinhole camera. Each pixel's ray is intersected
// exactly with the planes of the faces; the faces' projected outlines only select which pixels
// to test (a conservative scan conversion), so depth is the exact ray-plane distance.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "plugslam/sensor_data.h"
#include "sim3d/world.h"

namespace plugslam {
namespace sim {
namespace sim3d {

/// Pinhole intrinsics; pixel (u, v) looks along ((u - cx) / fx, (v - cy) / fy, 1).
struct PinholeCamera {
  double fx = 525.0;  ///< [px]
  double fy = 525.0;  ///< [px]
  double cx = 319.5;  ///< [px]
  double cy = 239.5;  ///< [px]
  int width = 640;    ///< [px]
  int height = 480;   ///< [px]

  /// Throws InputError naming the field when a value is out of range.
  void validate() const;
  /// The calibration a source reports for this camera (mono, identity mount, no distortion).
  CameraInfo info() const;
  /// KITTI odometry 00 left camera (1241 x 376).
  static PinholeCamera kitti();
  /// A VGA Kinect-like camera (640 x 480, f = 525).
  static PinholeCamera vga();
};

/// Per-pixel results of one render, row-major.
struct RenderBuffers {
  int width = 0;                  ///< [px]
  int height = 0;                 ///< [px]
  std::vector<double> depth;      ///< z along the optical axis [m], 0 = no hit
  std::vector<int32_t> face;      ///< face index, -1 = no hit
  std::vector<double> incidence;  ///< |cos| of the angle between ray and surface normal
};

/// Options of one render.
struct RenderOptions {
  double near = 0.05;  ///< nothing closer along z is drawn [m]
  double far = 250.0;  ///< objects entirely beyond this along z are skipped [m]
  bool shade = true;   ///< false: depth only (image untouched)
};

/// Renders `world` seen by a camera at `T_world_camera` (optical frame: x right, y down,
/// z forward). Fills `buffers` and, when `image` is not null and options.shade, an 8-bit image
/// with image->channels 1 (grey) or 3 (RGB; any other value is taken as 3).
void render(const World& world, const PinholeCamera& camera,
            const Eigen::Isometry3d& T_world_camera, RenderBuffers* buffers, Image* image,
            const RenderOptions& options = {});

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
