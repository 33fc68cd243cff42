#pragma once
// Deserializers for the ROS1 messages the io plugin consumes (little-endian ROS serialization).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "readers/rosbag_reader.h"

namespace plugslam {
namespace io {

/// std_msgs/Header.
struct RosHeader {
  std::uint32_t seq{0};  ///< sequence number
  RosTime stamp;         ///< acquisition time
  std::string frame_id;  ///< coordinate frame
};

/// sensor_msgs/LaserScan, with float32 fields widened to double.
struct LaserScanMsg {
  RosHeader header;                 ///< stamp = time of the first beam
  double angle_min{0.0};            ///< first beam angle (rad)
  double angle_max{0.0};            ///< last beam angle (rad)
  double angle_increment{0.0};      ///< angle between beams (rad)
  double time_increment{0.0};       ///< time between beams (s)
  double scan_time{0.0};            ///< time between scans (s)
  double range_min{0.0};            ///< minimum valid range (m)
  double range_max{0.0};            ///< maximum valid range (m)
  std::vector<double> ranges;       ///< metres; NaN/inf or outside [range_min, range_max] invalid
  std::vector<double> intensities;  ///< device-specific, may be empty
};

/// nav_msgs/Odometry.
struct OdometryMsg {
  RosHeader header;                           ///< pose frame (e.g. odom)
  std::string child_frame_id;                 ///< twist frame (e.g. base_link)
  std::array<double, 3> position{};           ///< pose.pose.position x y z
  std::array<double, 4> orientation{};        ///< pose.pose.orientation x y z w
  std::array<double, 36> pose_covariance{};   ///< row-major 6x6 (x y z rotx roty rotz)
  std::array<double, 3> linear{};             ///< twist.twist.linear
  std::array<double, 3> angular{};            ///< twist.twist.angular
  std::array<double, 36> twist_covariance{};  ///< row-major 6x6
  /// Heading (rotation about z) of the orientation quaternion.
  double yaw() const;
};

/// geometry_msgs/TransformStamped.
struct TransformMsg {
  RosHeader header;                     ///< parent frame and stamp
  std::string child_frame_id;           ///< child frame
  std::array<double, 3> translation{};  ///< child origin in the parent frame [m]
  std::array<double, 4> rotation{};     ///< x y z w
};

/// tf2_msgs/TFMessage (and ROS 1's older tf/tfMessage, the same definition).
struct TfMsg {
  std::vector<TransformMsg> transforms;  ///< one per parent -> child edge
};

/// A ROS 1 message type as a bag's connection names it: bags check both before decoding.
struct RosType {
  const char* name;  ///< the type name, e.g. "sensor_msgs/LaserScan"
  const char* md5;   ///< md5sum of the message definition
};

/// sensor_msgs/LaserScan.
inline constexpr RosType kRosLaserScan{"sensor_msgs/LaserScan", "90c7ef2dc6895d81024acba2ac42f369"};
/// nav_msgs/Odometry.
inline constexpr RosType kRosOdometry{"nav_msgs/Odometry", "cd5e73d190d741a2f92e81eda573aca7"};
/// tf2_msgs/TFMessage (/tf, /tf_static).
inline constexpr RosType kRosTfMessage{"tf2_msgs/TFMessage", "94810edda583a504dfda3829e70d7eec"};
/// The same message as the older tf package names it (the same md5sum).
inline constexpr const char* kTfMessageOldType = "tf/tfMessage";

/// Deserializes a LaserScan; ParseError (no file, line 0, byte offset in the message) if short.
void decodeLaserScan(const std::uint8_t* data, std::size_t size, LaserScanMsg& out);
/// Deserializes an Odometry; ParseError (no file, line 0, byte offset in the message) if short.
void decodeOdometry(const std::uint8_t* data, std::size_t size, OdometryMsg& out);

/// Deserializes a TFMessage; ParseError (no file, line 0, byte offset in the message) if short.
void decodeTf(const std::uint8_t* data, std::size_t size, TfMsg& out);

/// Checks the connection's type and md5sum, then decodes; ParseError names the bag and offsets.
void decodeLaserScan(const RosbagReader& bag, const RosbagMessage& message, LaserScanMsg& out);
/// Checks the connection's type and md5sum, then decodes; ParseError names the bag and offsets.
void decodeOdometry(const RosbagReader& bag, const RosbagMessage& message, OdometryMsg& out);
/// Checks the connection's type (either name) and md5sum, then decodes; ParseError names the bag
/// and offsets.
void decodeTf(const RosbagReader& bag, const RosbagMessage& message, TfMsg& out);

}  // namespace io
}  // namespace plugslam
