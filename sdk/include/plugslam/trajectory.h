#pragma once
// Timestamped pose sequences and their file formats (TUM, KITTI, g2o vertices).
#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

/// One pose with its timestamp in seconds (or a frame index / vertex id when the format has none).
struct StampedPose {
  double t = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// File formats a trajectory can be read from or written to.
enum class TrajectoryFormat { Auto, Tum, Kitti, G2o };

/// A sequence of poses with strictly increasing timestamps.
class Trajectory {
 public:
  Trajectory() = default;
  /// Takes poses already in time order; throws InputError if a timestamp is not finite or does
  /// not increase.
  explicit Trajectory(std::vector<StampedPose> poses);

  /// Appends a pose; throws InputError if t is not finite or not after the last timestamp.
  void push_back(double t, const Eigen::Isometry3d& pose);

  /// Number of poses.
  std::size_t size() const { return poses_.size(); }
  /// True when there is no pose.
  bool empty() const { return poses_.empty(); }
  /// The i-th pose (no bounds check).
  const StampedPose& operator[](std::size_t i) const { return poses_[i]; }
  /// All poses in time order.
  const std::vector<StampedPose>& poses() const { return poses_; }
  /// Iterator to the first pose.
  std::vector<StampedPose>::const_iterator begin() const { return poses_.begin(); }
  /// Iterator past the last pose.
  std::vector<StampedPose>::const_iterator end() const { return poses_.end(); }

  /// Timestamp of the first pose; throws InputError when empty.
  double startTime() const;
  /// Timestamp of the last pose; throws InputError when empty.
  double endTime() const;
  /// Sum of the distances between consecutive positions (m).
  double pathLength() const;
  /// Distance travelled from the first pose up to each pose (m); same size as the trajectory.
  std::vector<double> cumulativeDistances() const;
  /// Index of the pose whose timestamp is closest to t, if within max_dt seconds.
  std::optional<std::size_t> nearest(double t, double max_dt) const;
  /// Left-multiplies every pose by T (changes the world frame).
  void transform(const Eigen::Isometry3d& T);

 private:
  std::vector<StampedPose> poses_;
};

/// Name of a format as the CLI spells it ("auto", "tum", "kitti", "g2o").
std::string toString(TrajectoryFormat format);
/// Parses "auto", "tum", "kitti" or "g2o"; throws InputError otherwise.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);

/// Guesses the format from the extension (.tum, .kitti, .g2o) or else from the first data line
/// (8 numbers: TUM, 12 numbers: KITTI, VERTEX_/EDGE_ tags: g2o); throws ParseError if unsure.
TrajectoryFormat detectTrajectoryFormat(const std::string& path);

/// Reads a trajectory in the given format (Auto detects it). kitti_times_path is used only for
/// KITTI: one timestamp per line; when empty the KITTI line index is the timestamp.
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::Auto,
                          const std::string& kitti_times_path = "");
/// Reads a TUM file: `t x y z qx qy qz qw` per line, '#' starts a comment.
Trajectory readTumTrajectory(const std::string& path);
/// Reads a KITTI poses file (12 numbers, row-major 3x4 per line); times from times_path or the
/// 0-based line index when times_path is empty.
Trajectory readKittiTrajectory(const std::string& path, const std::string& times_path = "");
/// Reads the VERTEX_SE2 / VERTEX_SE3:QUAT vertices of a g2o file as poses with t = vertex id,
/// sorted by id; every other line is ignored.
Trajectory readG2oTrajectory(const std::string& path);

/// Writes `t x y z qx qy qz qw` lines atomically (temp file + rename); throws InputError on I/O
/// failure.
void writeTumTrajectory(const Trajectory& trajectory, const std::string& path);
/// Writes KITTI 3x4 rows atomically; also writes the timestamps to times_path when not empty.
void writeKittiTrajectory(const Trajectory& trajectory, const std::string& path,
                          const std::string& times_path = "");

}  // namespace abi_v1
}  // namespace plugslam
