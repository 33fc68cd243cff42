#pragma once
// Deserializers for the ROS 2 messages the io plugin consumes, in CDR (the rmw encoding of ROS 2
// bags: a 4-byte encapsulation header, then XCDR1 with each primitive aligned to its size from the
// end of that header; little or big endian as the header says). The decoded structs are the ROS 1
// reader's (ros_messages.h), so both bag sources share everything after decoding.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "readers/ros_messages.h"

namespace plugslam {
namespace io {

/// sensor_msgs/msg/Image.
struct ImageMsg {
  RosHeader header;                ///< stamp and camera frame
  std::uint32_t height{0};         ///< rows
  std::uint32_t width{0};          ///< columns
  std::string encoding;            ///< "mono8", "rgb8", "bgr8", "16UC1", "32FC1", ...
  bool is_bigendian{false};        ///< byte order of multi-byte pixels
  std::uint32_t step{0};           ///< bytes per row
  std::vector<std::uint8_t> data;  ///< step * height bytes
};

/// sensor_msgs/msg/CompressedImage.
struct CompressedImageMsg {
  RosHeader header;                ///< stamp and camera frame
  std::string format;              ///< "jpeg", "png", "rgb8; jpeg compressed bgr8", ...
  std::vector<std::uint8_t> data;  ///< the encoded image
};

/// sensor_msgs/msg/CameraInfo.
struct CameraInfoMsg {
  RosHeader header;                 ///< stamp and camera frame
  std::uint32_t height{0};          ///< rows of the calibrated image
  std::uint32_t width{0};           ///< columns
  std::string distortion_model;     ///< "plumb_bob", "rational_polynomial", "equidistant", ...
  std::vector<double> d;            ///< distortion coefficients
  std::array<double, 9> k{};        ///< intrinsic matrix, row-major
  std::array<double, 9> r{};        ///< rectification rotation, row-major
  std::array<double, 12> p{};       ///< projection matrix, row-major
  std::uint32_t binning_x{0};       ///< horizontal binning
  std::uint32_t binning_y{0};       ///< vertical binning
  std::array<std::uint32_t, 4> roi{};  ///< x_offset, y_offset, height, width
  bool do_rectify{false};           ///< roi.do_rectify
};

/// ROS 2 type names as rosbag2 and MCAP's ros2 profile write them.
inline constexpr const char* kRos2LaserScan = "sensor_msgs/msg/LaserScan";
/// nav_msgs/msg/Odometry.
inline constexpr const char* kRos2Odometry = "nav_msgs/msg/Odometry";
/// sensor_msgs/msg/Image.
inline constexpr const char* kRos2Image = "sensor_msgs/msg/Image";
/// sensor_msgs/msg/CompressedImage.
inline constexpr const char* kRos2CompressedImage = "sensor_msgs/msg/CompressedImage";
/// sensor_msgs/msg/CameraInfo.
inline constexpr const char* kRos2CameraInfo = "sensor_msgs/msg/CameraInfo";
/// tf2_msgs/msg/TFMessage.
inline constexpr const char* kRos2TfMessage = "tf2_msgs/msg/TFMessage";

/// Decoders of one CDR message each; ParseError("CDR message", 0, byte offset and field) when
/// the bytes are short, the encapsulation unknown or bytes are left over.
void decodeCdr(const std::uint8_t* data, std::size_t size, LaserScanMsg& out);
void decodeCdr(const std::uint8_t* data, std::size_t size, OdometryMsg& out);
void decodeCdr(const std::uint8_t* data, std::size_t size, ImageMsg& out);
void decodeCdr(const std::uint8_t* data, std::size_t size, CompressedImageMsg& out);
void decodeCdr(const std::uint8_t* data, std::size_t size, CameraInfoMsg& out);
void decodeCdr(const std::uint8_t* data, std::size_t size, TfMsg& out);

}  // namespace io
}  // namespace plugslam
