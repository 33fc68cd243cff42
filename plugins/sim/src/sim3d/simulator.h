#pragma once
// The 3D simulator: a world, a camera rig and a trajectory; renders frame k on demand
// (deterministically for a given seed, in any order).
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>

#include "plugslam/sensor_data.h"
#include "plugslam/trajectory.h"
#include "sim3d/noise.h"
#include "sim3d/renderer.h"
#include "sim3d/world.h"

namespace plugslam {
namespace sim {
namespace sim3d {

/// The camera rig.
enum class Rig {
  kStereo,  ///< rectified grey stereo pair, right camera at +baseline along x
  kRgbd,    ///< RGB camera with a registered depth image
};

/// What to simulate.
struct ScenarioOptions {
  std::string world = "livingroom";  ///< "livingroom" or "street"
  Rig rig = Rig::kRgbd;              ///< camera rig
  /// Trajectory file (TUM, KITTI or g2o, see readTrajectory); empty = the world's generated loop.
  std::string trajectory_file;
  std::string trajectory_format = "auto";  ///< auto | tum | kitti | g2o
  std::string kitti_times;                 ///< KITTI timestamps file (optional)
  bool anchor = true;  ///< move a loaded trajectory so it starts at the world's start pose
  /// Camera rate [Hz]; 0 = 30 (RGB-D) or 10 (stereo) for generated loops, and the file's own
  /// poses for loaded trajectories.
  double rate = 0.0;
  double duration = 0.0;   ///< generated living-room loop length [s]; 0 = 30 s
  double speed = 8.0;      ///< generated street drive speed [m/s]
  /// Generated street drive: starts standing and speeds up at this rate [m/s^2]; 0 = at speed.
  double acceleration = 0.0;
  /// The camera's heading swings this far either side of the trajectory's [rad]; 0 = none.
  double pan = 0.0;
  double pan_period = 2.0;  ///< one swing there and back [s]
  uint64_t seed = 0;       ///< textures, buildings and every noise stream
  DepthNoise depth_noise;  ///< RGB-D depth errors
  ImageNoise image_noise;  ///< image noise and exposure
};

/// One rendered frame.
struct Sim3DFrame {
  size_t index = 0;                                        ///< 0-based frame number
  double stamp = 0.0;                                      ///< [s]
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< camera (left / RGB) in the world
  Image left;        ///< stereo: left grey image; RGB-D: the RGB image
  Image right;       ///< stereo: right grey image; RGB-D: empty
  DepthImage depth;  ///< RGB-D: depth [m]; stereo: empty
};

/// Renders the frames of one scenario.
class Simulator3D {
 public:
  /// A world, a rig with intrinsics (baseline used by stereo), the camera trajectory (camera
  /// poses in the world) and the noise settings.
  Simulator3D(std::shared_ptr<const World> world, Rig rig, const PinholeCamera& camera,
              double baseline, Trajectory trajectory, const DepthNoise& depth_noise,
              const ImageNoise& image_noise, uint64_t seed);

  /// Builds the scenario described by `options` (world, generated or loaded trajectory, the
  /// KITTI camera for stereo and VGA for RGB-D); throws InputError on bad options.
  static Simulator3D fromOptions(const ScenarioOptions& options);

  /// Number of frames (trajectory poses).
  size_t frameCount() const { return trajectory_.size(); }
  /// Renders frame `index` (< frameCount()) into `frame`.
  void render(size_t index, Sim3DFrame* frame) const;

  /// The camera trajectory (ground truth).
  const Trajectory& trajectory() const { return trajectory_; }
  /// The world.
  const World& world() const { return *world_; }
  /// The rig.
  Rig rig() const { return rig_; }
  /// The intrinsics, baseline (stereo) and an identity mount.
  CameraInfo cameraInfo() const;
  /// The intrinsics as the renderer takes them.
  const PinholeCamera& camera() const { return camera_; }

 private:
  std::shared_ptr<const World> world_;
  Rig rig_;
  PinholeCamera camera_;
  double baseline_;
  Trajectory trajectory_;
  DepthNoise depth_noise_;
  ImageNoise image_noise_;
  uint64_t seed_;
};

/// Builds a built-in world by name ("livingroom", or "street" along `road`, which when empty
/// is the built-in 160 x 100 m block loop); throws InputError listing the names.
std::shared_ptr<const World> makeWorld(const std::string& name, uint64_t seed,
                                       const RoadPath& road = {});

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
