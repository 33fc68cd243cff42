#pragma once
// Writers of image sequences in the layouts of the real datasets, so one reader serves
// simulated and real data:
//  KITTI odometry: image_0/NNNNNN.png, image_1/NNNNNN.png (8-bit grey), calib.txt (P0..P3, Tr),
//                  times.txt, poses/<sequence>.txt (left camera, relative to the first frame).
//  TUM RGB-D:      rgb/<stamp>.png, depth/<stamp>.png (16-bit, 5000 per metre, 0 = none),
//                  rgb.txt, depth.txt, groundtruth.txt (t x y z qx qy qz qw, world frame).
#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"
#include "plugslam/trajectory.h"

namespace plugslam {
namespace io {

/// Writes a stereo sequence in the KITTI odometry layout under `dir` (created).
class KittiWriter {
 public:
  /// `camera` gives P0/P1 (baseline > 0 required); `sequence` names poses/<sequence>.txt.
  KittiWriter(std::string dir, const CameraInfo& camera, std::string sequence = "00");
  /// Writes the pair as frame number size() and remembers its stamp and left-camera pose.
  void add(double stamp, const Image& left, const Image& right, const Eigen::Isometry3d& pose);
  /// Writes calib.txt, times.txt and the poses file; call once after the last frame.
  void finish();
  /// Frames written so far.
  size_t size() const { return stamps_.size(); }

 private:
  std::string dir_;
  CameraInfo camera_;
  std::string sequence_;
  std::vector<double> stamps_;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> poses_;
};

/// Writes an RGB-D sequence in the TUM RGB-D layout under `dir` (created).
class TumWriter {
 public:
  /// depth_scale: 16-bit units per metre (TUM: 5000).
  explicit TumWriter(std::string dir, double depth_scale = 5000.0);
  /// Writes rgb/<stamp>.png and depth/<stamp>.png and remembers the camera pose.
  void add(double stamp, const Image& rgb, const DepthImage& depth, const Eigen::Isometry3d& pose);
  /// Writes rgb.txt, depth.txt and groundtruth.txt; call once after the last frame.
  void finish();
  /// Frames written so far.
  size_t size() const { return stamps_.size(); }

 private:
  std::string dir_;
  double depth_scale_;
  std::vector<double> stamps_;
  Trajectory poses_;
};

}  // namespace io
}  // namespace plugslam
