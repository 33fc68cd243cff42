#pragma once
// Raw readings shared by sources (io, simulators) and the plugins that consume them (laser2d,
// odometry). A source writes them into Frame::raw under the sensor's name.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

class OutArchive;
class InArchive;

/// One planar laser scan as the sensor reported it.
struct LaserScan {
  double stamp = 0;            ///< seconds
  double angle_min = 0;        ///< angle of the first beam [rad], sensor frame
  double angle_increment = 0;  ///< angle between beams [rad]
  double range_min = 0;        ///< closer readings are not returns [m]
  double range_max = 0;        ///< readings at or beyond are not returns [m]
  std::vector<double> ranges;  ///< [m]; NaN, inf or out of [range_min, range_max) = no return
  /// Sensor pose in the robot frame, as the source knows it (a preprocessor may override it).
  Eigen::Isometry2d mount = Eigen::Isometry2d::Identity();

  /// True when beam i is a real return.
  bool isReturn(size_t i) const {
    const double r = ranges[i];
    return std::isfinite(r) && r > range_min && r < range_max;
  }
  /// Angle of beam i in the sensor frame.
  double angle(size_t i) const { return angle_min + angle_increment * static_cast<double>(i); }
};

/// Wheel odometry: where the robot's base believes it is, in its odometry frame.
struct Odometry2D {
  double stamp = 0;                                        ///< seconds
  Eigen::Isometry2d pose = Eigen::Isometry2d::Identity();  ///< robot in the odometry frame
};

/// An 8-bit image, rows top to bottom, channels interleaved (1 = grey, 3 = RGB).
struct Image {
  double stamp = 0;           ///< seconds
  int width = 0;              ///< pixels per row
  int height = 0;             ///< rows
  int channels = 1;           ///< 1 (grey) or 3 (RGB)
  int stride = 0;             ///< bytes from one row to the next (>= width * channels)
  std::vector<uint8_t> data;  ///< stride * height bytes

  /// Sets the size and fills with zeros (stride = width * channels).
  void resize(int w, int h, int c) {
    width = w;
    height = h;
    channels = c;
    stride = w * c;
    data.assign(static_cast<size_t>(stride) * static_cast<size_t>(h), 0);
  }
  /// Channel c of pixel (x, y) (no bounds check).
  uint8_t at(int x, int y, int c = 0) const {
    return data[static_cast<size_t>(y) * static_cast<size_t>(stride) +
                static_cast<size_t>(x * channels + c)];
  }
};

/// A depth image in metres along the optical axis (z, not ray length); 0 = no reading.
struct DepthImage {
  double stamp = 0;         ///< seconds
  int width = 0;            ///< pixels per row
  int height = 0;           ///< rows
  std::vector<float> data;  ///< width * height depths, row-major [m]

  /// Sets the size and fills with 0 (no reading).
  void resize(int w, int h) {
    width = w;
    height = h;
    data.assign(static_cast<size_t>(w) * static_cast<size_t>(h), 0.0f);
  }
  /// Depth at pixel (x, y) (no bounds check).
  float at(int x, int y) const {
    return data[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  }
};

/// Lens distortion of one camera as its calibration states it. Coefficients are in OpenCV's
/// order, so a preprocessor hands them unchanged to cv::initUndistortRectifyMap (radial-
/// tangential) or cv::fisheye::initUndistortRectifyMap (equidistant).
struct Distortion {
  /// Distortion models (the names ROS 2's CameraInfo.distortion_model and Kalibr use in quotes).
  enum class Model : std::int32_t {
    kNone = 0,              ///< ideal pinhole: the images are rectified or undistorted
    kRadialTangential = 1,  ///< k1 k2 p1 p2 [k3 [k4 k5 k6 [s1..s4 [tx ty]]]]: 4, 5, 8, 12 or 14
                            ///< ("plumb_bob", "rational_polynomial", "radtan"; EuRoC's sensor.yaml)
    kEquidistant = 2,       ///< Kannala-Brandt fisheye k1 k2 k3 k4 ("equidistant", "fisheye")
  };
  Model model = Model::kNone;        ///< how the coefficients are applied
  std::vector<double> coefficients;  ///< OpenCV's order; empty for kNone

  /// True when the coefficient count fits the model (see Model).
  bool valid() const;
  /// True when nothing needs undoing: model kNone or every coefficient zero.
  bool isIdentity() const;
};

/// Reads a model name as datasets and ROS write it ("radial-tangential", "radtan", "plumb_bob",
/// "rational_polynomial", "equidistant", "fisheye", "none", ""; any case); false when unknown.
bool parseDistortionModel(const std::string& name, Distortion::Model& model);
/// The name the archive and messages use: "none", "radial-tangential" or "equidistant".
const char* distortionModelName(Distortion::Model model);

/// A camera's pinhole and image size, the first fields of CameraIntrinsics and CameraInfo (which
/// keep their offsets: a base of plain fields adds nothing before them).
struct CameraPinhole {
  double fx = 0;   ///< focal length along x [px]
  double fy = 0;   ///< focal length along y [px]
  double cx = 0;   ///< principal point x [px]
  double cy = 0;   ///< principal point y [px]
  int width = 0;   ///< image width [px]
  int height = 0;  ///< image height [px]
};

/// Intrinsics of one camera: pinhole, image size and lens distortion.
struct CameraIntrinsics : CameraPinhole {
  Distortion distortion;  ///< lens distortion; kNone when the images are ideal pinhole
};

/// Calibration of a camera or a two-camera rig, as the dataset states it; a preprocessor decides
/// what to do with it (rectify a raw stereo pair, register depth to colour). The first fields are
/// the (left / colour) camera's pinhole; pixel (u, v) integer coordinates are pixel centres:
/// u = fx * x / z + cx (OpenCV convention).
/// Example, EuRoC: fx..cy and distortion from cam0/sensor.yaml, baseline 0 (not rectified),
/// second = cam1's intrinsics and distortion, second_pose = inverse(T_BS0) * T_BS1, mount = T_BS0.
/// KITTI (rectified): distortion kNone, baseline 0.537, second = the same pinhole, second_pose a
/// translation (0.537, 0, 0). TUM RGB-D (depth registered by the driver): second = the colour
/// pinhole and size, second_pose identity.
struct CameraInfo : CameraPinhole {
  /// Baseline of a rectified stereo pair, right camera at +baseline along x [m]; 0 = mono, or a
  /// pair that still needs rectifying (then `second` and `second_pose` say how it sits).
  double baseline = 0;
  /// Camera pose in the robot frame (x right, y down, z forward optical frame).
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
  // Appended in plugin ABI 1.5; the fields above keep their offsets.
  /// Lens distortion of this camera; kNone when its images are rectified or undistorted.
  Distortion distortion;
  /// The rig's other camera when there is one: stereo's right camera, RGB-D's depth camera.
  std::optional<CameraIntrinsics> second;
  /// Pose of `second` in this camera's optical frame (maps its points into this frame; OpenCV's
  /// stereoRectify wants the inverse): (baseline, 0, 0) for a rectified pair, identity for depth
  /// registered to colour.
  Eigen::Isometry3d second_pose = Eigen::Isometry3d::Identity();

  /// This camera's pinhole, size and distortion.
  CameraIntrinsics intrinsics() const { return CameraIntrinsics{pinhole(), distortion}; }
  /// Sets this camera's pinhole, size and distortion.
  void setIntrinsics(const CameraIntrinsics& k) {
    static_cast<CameraPinhole&>(*this) = k;
    distortion = k.distortion;
  }
  /// This camera's pinhole and size.
  const CameraPinhole& pinhole() const { return *this; }
};

/// Serializes a laser scan.
void save(OutArchive& ar, const LaserScan& scan);
/// Deserializes a laser scan.
void load(InArchive& ar, LaserScan& scan);
/// Serializes odometry.
void save(OutArchive& ar, const Odometry2D& odom);
/// Deserializes odometry.
void load(InArchive& ar, Odometry2D& odom);
/// Serializes an image (pixels as one base64 string, so both back-ends store it compactly).
void save(OutArchive& ar, const Image& image);
/// Deserializes an image (ParseError when the pixel data does not match the size).
void load(InArchive& ar, Image& image);
/// Serializes a depth image (the float bits, little-endian, base64).
void save(OutArchive& ar, const DepthImage& depth);
/// Deserializes a depth image (ParseError when the data does not match the size).
void load(InArchive& ar, DepthImage& depth);
/// Serializes lens distortion.
void save(OutArchive& ar, const Distortion& distortion);
/// Deserializes lens distortion (ParseError for an unknown model or a count that does not fit).
void load(InArchive& ar, Distortion& distortion);
/// Serializes one camera's intrinsics.
void save(OutArchive& ar, const CameraIntrinsics& camera);
/// Deserializes one camera's intrinsics.
void load(InArchive& ar, CameraIntrinsics& camera);
/// Serializes a camera's or a rig's calibration.
void save(OutArchive& ar, const CameraInfo& camera);
/// Deserializes a calibration; files written before ABI 1.5 (no distortion, no second camera)
/// load as undistorted mono or rectified stereo.
void load(InArchive& ar, CameraInfo& camera);

}  // namespace abi_v1
}  // namespace plugslam
