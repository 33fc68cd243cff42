#pragma once
// The viewer stream's drawables: what modules and sinks show, as plain typed values. They carry no
// protocol: the runtime encodes them for its Foxglove WebSocket server and its MCAP recordings
// (JSON with the @foxglove/schemas schemas named in each comment). Frames are named: "world" is
// fixed, "map/<id>" is local map <id>'s origin, "base_link" the robot, "camera/<sensor>" a camera.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "plugslam/sensor_data.h"

namespace plugslam {
inline namespace abi_v1 {
namespace view {

/// An RGBA colour, each channel in [0, 1].
struct Color {
  float r = 1, g = 1, b = 1, a = 1;
};

/// Where frame `child` is in frame `parent` (foxglove.FrameTransform).
struct FrameTransform {
  double stamp = 0;                                             ///< seconds
  std::string parent = "world";                                 ///< parent frame
  std::string child;                                            ///< child frame
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  ///< child in parent
};

/// Transforms sent together (foxglove.FrameTransforms).
struct FrameTransforms {
  std::vector<FrameTransform> transforms;  ///< any number, any frames
};

/// One pose in a frame (foxglove.PoseInFrame).
struct PoseInFrame {
  double stamp = 0;                                        ///< seconds
  std::string frame = "world";                             ///< frame of `pose`
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the pose
};

/// Poses in one frame, e.g. the stretch of trajectory tracked in one local map
/// (foxglove.PosesInFrame).
struct PosesInFrame {
  double stamp = 0;                     ///< seconds
  std::string frame = "world";          ///< frame of every pose
  std::vector<Eigen::Isometry3d> poses;  ///< in order
};

/// Points in 2D or 3D with optional colours: a scan, a local map's points, a landmark map
/// (foxglove.PointCloud, float32 x y z and, with colours, uint8 red green blue alpha).
struct PointCloud {
  double stamp = 0;                                        ///< seconds
  std::string frame = "world";                             ///< frame of `pose`
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< cloud origin in `frame`
  std::vector<Eigen::Vector3f> points;                     ///< in the cloud's origin [m]
  std::vector<std::array<uint8_t, 4>> colors;              ///< RGBA per point, or empty
};

/// A 2D grid of occupancy in the x-y plane of `pose` (foxglove.Grid, one uint8 field
/// "occupancy").
struct Grid {
  static constexpr uint8_t kUnknown = 255;  ///< a cell never observed
  double stamp = 0;                          ///< seconds
  std::string frame = "world";               ///< frame of `pose`
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< corner of cell (0, 0)
  double cell_size = 0.05;                   ///< [m]
  int width = 0;                             ///< cells along x
  int height = 0;                            ///< cells along y
  /// Row-major from cell (0, 0) (x fastest): occupancy probability in percent (0 free .. 100
  /// occupied), or kUnknown.
  std::vector<uint8_t> cells;
  /// When set, fills every field but stamp and frame later, off the pipeline's thread (ray
  /// tracing is too slow for it): the receiver calls it once before encoding. It must own what
  /// it reads.
  std::function<void(Grid&)> fill;
};

/// Line segments or a polyline (foxglove.LinePrimitive).
struct Lines {
  /// How `points` join: consecutive (strip), closed (loop) or in pairs (list).
  enum class Type { kStrip = 0, kLoop = 1, kList = 2 };
  Type type = Type::kList;               ///< joining rule
  std::vector<Eigen::Vector3d> points;   ///< vertices in the entity's frame
  Color color;                           ///< one colour for all
  double thickness = 2;                  ///< pixels when scale_invariant, else metres
  bool scale_invariant = true;           ///< thickness in pixels
};

/// A named visual element of a scene (foxglove.SceneEntity).
struct SceneEntity {
  double stamp = 0;             ///< seconds
  std::string frame = "world";  ///< frame of its primitives
  std::string id;               ///< replaces an earlier entity of the same id on the channel
  std::vector<Lines> lines;     ///< line primitives
};

/// Entities added or replaced, and entities removed (foxglove.SceneUpdate).
struct SceneUpdate {
  std::vector<SceneEntity> entities;  ///< added or replaced
  std::vector<std::string> deleted;   ///< ids removed
  double stamp = 0;                   ///< seconds (of the deletions)
};

/// A camera image (foxglove.CompressedImage: the runtime compresses it).
struct CameraImage {
  std::string frame;  ///< the camera's frame ("camera/<sensor>")
  Image image;        ///< pixels and stamp
};

/// A camera's intrinsics and lens distortion (foxglove.CameraCalibration).
struct CameraCalibration {
  double stamp = 0;   ///< seconds
  std::string frame;  ///< the camera's frame
  CameraInfo info;    ///< intrinsics and size
};

/// The run's progress (plugslam.Status); the runtime adds each receiver's dropped messages.
struct Status {
  double stamp = 0;            ///< data time of the last frame [s]
  uint64_t frame = 0;          ///< frames processed
  int64_t total = -1;          ///< frames in the source, or -1
  double hz = 0;               ///< frames per second of wall time, recently
  uint64_t loops = 0;          ///< loop closures accepted
  uint64_t local_maps = 0;     ///< local maps built
  uint64_t tracking_failures = 0;  ///< frames the tracker could not align
  std::string state;           ///< "running", "paused", "finished" or "idle"
  uint64_t run = 0;            ///< which run of the host (a shell runs several): new = new map
};

/// One log line (foxglove.Log).
struct LogLine {
  /// Severity, as foxglove.LogLevel numbers it.
  enum class Level { kDebug = 1, kInfo = 2, kWarning = 3, kError = 4, kFatal = 5 };
  double stamp = 0;             ///< wall time, seconds since the epoch
  Level level = Level::kInfo;   ///< severity
  std::string message;          ///< the text
  std::string name = "plugslam";  ///< who logged it
};

/// Any drawable; a channel carries one alternative.
using Drawable = std::variant<FrameTransforms, PoseInFrame, PosesInFrame, PointCloud, Grid,
                              SceneUpdate, CameraImage, CameraCalibration, Status, LogLine>;

/// The index of T in Drawable (a channel's kind).
template <class T, size_t I = 0>
constexpr size_t kindOf() {
  if constexpr (I >= std::variant_size_v<Drawable>) {
    static_assert(I < std::variant_size_v<Drawable>, "not a drawable type");
    return I;
  } else if constexpr (std::is_same_v<std::variant_alternative_t<I, Drawable>, T>) {
    return I;
  } else {
    return kindOf<T, I + 1>();
  }
}

}  // namespace view
}  // namespace abi_v1
}  // namespace plugslam
