#pragma once
// Synthetic 2D worlds for the laser2d tests: line segments, and laser scans ray cast into them.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "plugslam/geometry.h"
#include "plugslam/sensor_data.h"

namespace plugslam::laser2d::test {

/// A wall from a to b.
struct Segment {
  Eigen::Vector2d a, b;
};

/// The four walls of the axis-aligned rectangle [x0, x1] x [y0, y1].
std::vector<Segment> box(double x0, double y0, double x1, double y1);
/// A room [0, w] x [0, h] with two pillars, so every direction is constrained.
std::vector<Segment> room(double w, double h);
/// An irregular 14 x 10 m building: outer walls, a partition with a door and a few boxes, so a
/// scan matches it in one place only (loop search and validation tests).
std::vector<Segment> building();
/// A corridor along x: walls y = +-half_width from x = x0 to x1, an end wall at x = x1 only.
std::vector<Segment> corridor(double x0, double x1, double half_width);

/// Options of castScan.
struct ScanSpec {
  int beams = 360;
  double fov = 2 * M_PI * 359.0 / 360.0;  ///< first beam at -fov/2
  double range_max = 30.0;
  double noise = 0.0;  ///< range noise std. dev. [m]
  uint32_t seed = 1;
  SE2 mount = SE2::Identity();  ///< sensor in the robot frame
};

/// The scan a sensor at robot pose `robot` (world frame) sees; beams without a hit get +inf.
LaserScan castScan(const std::vector<Segment>& world, const SE2& robot, const ScanSpec& spec);

/// Distance from point p to the segment s.
double distanceToSegment(const Eigen::Vector2d& p, const Segment& s);

}  // namespace plugslam::laser2d::test
