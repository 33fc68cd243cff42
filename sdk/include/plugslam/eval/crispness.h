#pragma once
// Map crispness: how tightly scans taken far apart in time agree where they overlap.
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "plugslam/trajectory.h"

namespace plugslam {
inline namespace abi_v1 {

/// One 2D scan: points in the robot frame and the robot pose that places them in the world.
struct PosedScan {
  std::vector<Eigen::Vector2d> points;
  Eigen::Isometry2d pose = Eigen::Isometry2d::Identity();
};

/// Options of computeCrispness.
struct CrispnessOptions {
  /// Neighbours only come from scans whose index differs by at least this much.
  int min_index_gap = 50;
  /// And at most this much (0: no limit). A small window [min, max] scores local consistency,
  /// which a drifting front-end without loop closure can be judged on.
  int max_index_gap = 0;
  /// Neighbours farther than this (m) do not count; points without one are left out.
  double radius = 0.3;
  /// Worker threads (1: deterministic single thread; results are identical for any value).
  int threads = 1;
};

/// Crispness result; mean is in metres.
struct CrispnessResult {
  double mean = 0.0;               ///< mean nearest-neighbour distance over points that have one
  std::size_t points = 0;          ///< points in all scans
  std::size_t matched_points = 0;  ///< points with a neighbour within the radius
  std::size_t scans = 0;
  int min_index_gap = 50;
  int max_index_gap = 0;  ///< 0: no upper limit
  double radius = 0.3;
  /// Share of points with a neighbour within the radius (matched_points / points; 0 without
  /// points): a map in pieces can look crisp when few of its points match, coverage shows it.
  double coverage() const { return points ? static_cast<double>(matched_points) / points : 0.0; }
};

/// For every point placed at its scan's pose, the distance to the nearest point of a scan at
/// least min_index_gap (and, if max_index_gap > 0, at most max_index_gap) scans away, if within radius; returns the mean over matched points (0 if
/// none). Throws InputError on a non-positive radius or gap, or non-finite points.
CrispnessResult computeCrispness(const std::vector<PosedScan>& scans,
                                 const CrispnessOptions& options = {});

/// Places scans (points in the robot frame, one timestamp each) at the trajectory pose nearest
/// in time, projected to the plane. Throws InputError naming the first scan with no pose within
/// max_time_diff, or if the two lists differ in length.
std::vector<PosedScan> placeScans(const std::vector<std::vector<Eigen::Vector2d>>& points,
                                  const std::vector<double>& stamps, const Trajectory& trajectory,
                                  double max_time_diff);

/// The planar part (x, y, yaw about z) of a 3D pose, to place 2D scans with a TUM trajectory.
Eigen::Isometry2d planarPose(const Eigen::Isometry3d& pose);

}  // namespace abi_v1
}  // namespace plugslam
