#pragma once
// The field order of the messages both ROS wire formats carry, written once: the ROS 1
// serialization (ros_messages.cpp) and CDR (cdr_messages.cpp) differ only in their cursors
// (header layout, alignment, byte order), which provide header(), f32(), f64(), str() and
// f32Array() with the same meaning.
#include <cstddef>
#include <cstdint>

#include "readers/ros_messages.h"

namespace plugslam {
namespace io {
namespace layout {

/// One whole message read by `fields` with a Cursor over the bytes: the cursor's ParseError when
/// they are short, or when bytes are left over.
template <typename Cursor, typename Msg, typename Fields>
void decodeWhole(const std::uint8_t* data, std::size_t size, Msg& out, Fields fields) {
  Cursor c(data, size);
  fields(c, out);
  c.finish();
}

/// sensor_msgs/LaserScan, header first.
template <typename Cursor>
void laserScan(Cursor& c, LaserScanMsg& out) {
  c.header(out.header);
  out.angle_min = c.f32("angle_min");
  out.angle_max = c.f32("angle_max");
  out.angle_increment = c.f32("angle_increment");
  out.time_increment = c.f32("time_increment");
  out.scan_time = c.f32("scan_time");
  out.range_min = c.f32("range_min");
  out.range_max = c.f32("range_max");
  c.f32Array(out.ranges, "ranges");
  c.f32Array(out.intensities, "intensities");
}

/// nav_msgs/Odometry, header first.
template <typename Cursor>
void odometry(Cursor& c, OdometryMsg& out) {
  c.header(out.header);
  out.child_frame_id = c.str("child_frame_id");
  for (double& v : out.position) v = c.f64("pose.pose.position");
  for (double& v : out.orientation) v = c.f64("pose.pose.orientation");
  for (double& v : out.pose_covariance) v = c.f64("pose.covariance");
  for (double& v : out.linear) v = c.f64("twist.twist.linear");
  for (double& v : out.angular) v = c.f64("twist.twist.angular");
  for (double& v : out.twist_covariance) v = c.f64("twist.covariance");
}

}  // namespace layout
}  // namespace io
}  // namespace plugslam
