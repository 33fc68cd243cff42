#pragma once
// What the RGB-D dataset sources share: the colour camera's intrinsics (parameters or a K file),
// the depth camera's (registered or not) and depth units, and reading one colour + depth pair.
#include <string>
#include <vector>

#include "sources/camera_sequence_source.h"

namespace plugslam {
namespace io {

/// Base of io.TumRgbd and io.RgbdFolder. raw[rgb] (Image as stored, RGB for colour files),
/// raw[depth] (DepthImage in metres, 0 = no reading) and raw[camera] (CameraInfo: the colour
/// pinhole, `second` = the depth camera, `second_pose` = the depth camera in the colour frame).
/// A negative focal length (ICL-NUIM's fy = -480, from POV-Ray's left-handed frame) says the
/// dataset's camera axis points the other way: the source mirrors that axis in the camera and
/// in the world (pose -> S pose S, S = diag(+-1, +-1, 1)), so the images stay as they are, the
/// focal length is positive and every frame is right-handed.
class RgbdSequenceSource : public CameraSequenceSource {
 public:
  Param<std::string> rgb{this, "rgb", "rgb", "", "raw entry for the colour image"};
  Param<std::string> depth{this, "depth", "depth", "", "raw entry for the depth image"};
  Param<double> fx{this, "fx", 0.0, "px", "colour focal length x (or intrinsics_file)",
                   Range{-1e6, 1e6}};
  Param<double> fy{this, "fy", 0.0, "px", "colour focal length y; < 0 = the dataset's y is up",
                   Range{-1e6, 1e6}};
  Param<double> cx{this, "cx", 0.0, "px", "colour principal point x", Range{-1e6, 1e6}};
  Param<double> cy{this, "cy", 0.0, "px", "colour principal point y", Range{-1e6, 1e6}};
  Param<std::string> intrinsics_file{this, "intrinsics_file", "", "",
                                     "3x3 camera matrix file (relative to path) instead of fx.. "
                                     "cy, e.g. 7-Scenes' camera-intrinsics.txt"};
  Param<std::string> distortion_model{
      this,   "distortion_model", "none", "", "colour lens distortion model",
      Choices{{"none", "radial-tangential", "equidistant"}}};
  Param<std::vector<double>> distortion{this, "distortion", std::vector<double>{}, "",
                                        "colour distortion coefficients, OpenCV order "
                                        "(radial-tangential: k1 k2 p1 p2 [k3])"};
  Param<double> depth_scale{this,
                            "depth_scale",
                            5000.0,
                            "1/m",
                            "depth image units per metre (TUM, ICL: 5000; Kinect mm: 1000)",
                            Range{1e-6, 1e9}};
  Param<double> depth_fx{this, "depth_fx", 0.0, "px",
                         "depth camera focal length x; 0 = depth registered to colour",
                         Range{-1e6, 1e6}};
  Param<double> depth_fy{this, "depth_fy", 0.0, "px", "depth camera focal length y",
                         Range{-1e6, 1e6}};
  Param<double> depth_cx{this, "depth_cx", 0.0, "px", "depth camera principal point x",
                         Range{-1e6, 1e6}};
  Param<double> depth_cy{this, "depth_cy", 0.0, "px", "depth camera principal point y",
                         Range{-1e6, 1e6}};
  Param<std::vector<double>> depth_pose{
      this, "depth_pose", std::vector<double>{}, "m, rad",
      "depth camera in the colour camera's frame [x y z rx ry rz] (rotation vector); empty = "
      "identity"};

 protected:
  /// One frame's colour and depth files and its time.
  struct RgbdPair {
    double stamp = 0.0;
    std::string rgb, depth;  // file paths
  };

  std::vector<ProvidedEntry> imageEntries() const override {
    return {{rgb(), typeid(Image)}, {depth(), typeid(DepthImage)}};
  }
  /// Reads pairs_[i] (index() fills pairs_).
  void read(std::size_t i, Frame& frame) final;
  /// Sets calibration_ from the parameters; `dir` resolves intrinsics_file; the sizes are the
  /// first colour and depth images'.
  void setCalibration(const std::string& dir, const std::string& first_rgb,
                      const std::string& first_depth);
  /// Reads one colour + depth pair into the frame (sizes checked against the calibration).
  void readPair(const std::string& rgb_file, const std::string& depth_file, double stamp,
                Frame& frame) const;
  /// A dataset pose in the source's right-handed frames (see the class comment).
  Eigen::Isometry3d fromDataset(const Eigen::Isometry3d& pose) const;

  std::vector<RgbdPair> pairs_;

 private:
  Eigen::Vector3d mirror_ = Eigen::Vector3d::Ones();
};

}  // namespace io
}  // namespace plugslam
