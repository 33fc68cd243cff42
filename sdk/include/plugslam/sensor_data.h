#pragma once
// Raw readings shared by sources (io, simulators) and the plugins that consume them (laser2d,
// odometry). A source writes them into Frame::raw under the sensor's name.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
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

/// Pinhole intrinsics of a camera (or of the left camera of a rectified stereo pair). Pixel
/// (u, v) integer coordinates are pixel centres: u = fx * x / z + cx (OpenCV convention).
struct CameraInfo {
  double fx = 0;      ///< focal length along x [px]
  double fy = 0;      ///< focal length along y [px]
  double cx = 0;      ///< principal point x [px]
  double cy = 0;      ///< principal point y [px]
  int width = 0;      ///< image width [px]
  int height = 0;     ///< image height [px]
  double baseline = 0;  ///< stereo baseline, right camera at +baseline along x [m]; 0 = mono
  /// Camera pose in the robot frame (x right, y down, z forward optical frame).
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
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
/// Serializes camera intrinsics.
void save(OutArchive& ar, const CameraInfo& camera);
/// Deserializes camera intrinsics.
void load(InArchive& ar, CameraInfo& camera);

}  // namespace abi_v1
}  // namespace plugslam
