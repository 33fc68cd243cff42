#pragma once
// Simulated 2D laser scanners.
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "sim2d/random.h"
#include "sim2d/world.h"

namespace plugslam {
namespace sim {
namespace sim2d {

/// One laser scanner on the robot. Beam i points at angle_min + i * angle_increment in the
/// sensor frame (counter-clockwise, 0 = sensor x axis), with angle_min = -fov/2 and
/// angle_increment = fov / (beams - 1).
struct LaserConfig {
  std::string name = "laser";            ///< entry name in each frame
  Eigen::Vector3d mount{0.0, 0.0, 0.0};  ///< sensor pose in the robot frame (x, y, yaw)
  double fov = 1.5 * M_PI;               ///< field of view [rad], at most 2*pi
  int beams = 1081;                      ///< number of beams (>= 1)
  double min_range = 0.05;               ///< closer returns are invalid [m]
  double max_range = 30.0;               ///< farther returns are invalid [m]
  double range_sigma = 0.01;             ///< range noise standard deviation [m]
  double dropout = 0.0;                  ///< probability that a beam returns nothing

  /// Angle of the first beam in the sensor frame [rad].
  double angleMin() const { return -0.5 * fov; }
  /// Angle between consecutive beams [rad].
  double angleIncrement() const { return beams > 1 ? fov / (beams - 1) : 0.0; }
  /// Throws InputError naming the field if a value is out of range.
  void validate() const;
};

/// One scan. A beam with no valid return (nothing within max_range, closer than min_range,
/// noise pushed it out of [min_range, max_range], or dropped out) holds NaN: a range is valid
/// iff std::isfinite(range).
struct LaserScan {
  std::string name;                      ///< the laser's name
  double angle_min = 0.0;                ///< first beam angle in the sensor frame [rad]
  double angle_increment = 0.0;          ///< beam spacing [rad]
  double min_range = 0.0;                ///< [m]
  double max_range = 0.0;                ///< [m]
  Eigen::Vector3d mount{0.0, 0.0, 0.0};  ///< sensor pose in the robot frame (x, y, yaw)
  std::vector<double> ranges;            ///< one range per beam [m], NaN = no return
};

/// Casts every beam of `config` from the robot at `robot_pose` (world x, y, theta); noise and
/// dropout are drawn from rng (pass nullptr for an exact scan).
void simulateScan(const World& world, const Eigen::Vector3d& robot_pose, const LaserConfig& config,
                  Rng* rng, LaserScan* scan);

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
