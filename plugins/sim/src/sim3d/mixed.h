#pragma once
// The mixed world: a differential-drive robot (sim2d kinematics and wheel odometry) touring the
// 3D living room with a planar laser whose rays are cast in the 3D world at a fixed height, and
// an RGB-D camera on a mast. Exact ground truth for the robot base.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "plugslam/sensor_data.h"
#include "sim2d/laser.h"
#include "sim2d/simulator.h"
#include "sim3d/noise.h"
#include "sim3d/renderer.h"
#include "sim3d/world.h"

namespace plugslam {
namespace sim {
namespace sim3d {

/// Everything that defines a mixed session.
struct MixedOptions {
  double path_length = 40.0;  ///< the tour ends at the first frame past this [m]
  double rate = 10.0;         ///< frame rate of odometry, laser and camera [Hz]
  sim2d::LaserConfig laser;   ///< the planar laser (mount x, y, yaw in the robot frame)
  double laser_height = 0.3;  ///< height of the scan plane above the floor [m]
  /// Camera pose in the robot base frame (optical frame); default: 1 m up, 10 deg down.
  Eigen::Isometry3d camera_mount = defaultCameraMount();
  double odometry_noise = 1.0;  ///< scale on sim2d's preset odometry errors
  DepthNoise depth_noise;       ///< RGB-D depth errors
  ImageNoise image_noise;       ///< image noise and exposure
  uint64_t seed = 0;            ///< textures and every noise stream

  /// 0.1 m ahead of the base centre, 1 m up, looking forward, pitched 10 degrees down.
  static Eigen::Isometry3d defaultCameraMount();
};

/// One step of the mixed simulator.
struct MixedFrame {
  size_t index = 0;                                            ///< 0-based frame number
  double stamp = 0.0;                                          ///< [s]
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();      ///< true robot base pose (z = 0)
  Eigen::Isometry2d odometry = Eigen::Isometry2d::Identity();  ///< wheel odometry pose
  LaserScan scan;    ///< the planar scan (NaN = no return)
  Image rgb;         ///< RGB image
  DepthImage depth;  ///< depth [m]
};

/// Drives the robot through the living room and produces synchronised laser, RGB-D and odometry.
class MixedSimulator {
 public:
  /// Plans the tour (collision-free in a floor plan sliced from the 3D world); throws
  /// InputError on bad options.
  explicit MixedSimulator(const MixedOptions& options);
  /// Fills the next frame; false after the last.
  bool step(MixedFrame* frame);
  /// Number of frames.
  size_t frameCount() const { return sim2d_->frameCount(); }
  /// The camera intrinsics with its mount.
  CameraInfo cameraInfo() const;
  /// The 3D world.
  const World& world() const { return *world_; }

 private:
  MixedOptions options_;
  std::shared_ptr<const World> world_;
  std::unique_ptr<sim2d::Simulator> sim2d_;
  PinholeCamera camera_;
  sim2d::Rng laser_rng_;
};

/// Casts a planar scan in the 3D world from the robot base at `base` (laser plane at
/// `height`); noise from rng (nullptr = exact).
void castPlanarScan(const World& world, const Eigen::Isometry3d& base, double height,
                    const sim2d::LaserConfig& laser, sim2d::Rng* rng, LaserScan* scan);

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
