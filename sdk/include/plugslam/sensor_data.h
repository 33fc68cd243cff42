#pragma once
// Raw readings shared by sources (io, simulators) and the plugins that consume them (laser2d,
// odometry). A source writes them into Frame::raw under the sensor's name.
#include <Eigen/Geometry>
#include <cmath>
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

/// Serializes a laser scan.
void save(OutArchive& ar, const LaserScan& scan);
/// Deserializes a laser scan.
void load(InArchive& ar, LaserScan& scan);
/// Serializes odometry.
void save(OutArchive& ar, const Odometry2D& odom);
/// Deserializes odometry.
void load(InArchive& ar, Odometry2D& odom);

}  // namespace abi_v1
}  // namespace plugslam
