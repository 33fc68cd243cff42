#pragma once
// The 2D simulator: a differential-drive robot touring a World at a fixed rate, with laser
// scanners, wheel odometry and exact ground truth. The ground-truth trajectory is computed once
// at construction (it depends on the world, tour and limits only, not on the seed); noise is
// drawn frame by frame in step(), from streams derived from the seed.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim2d/laser.h"
#include "sim2d/planner.h"
#include "sim2d/robot.h"
#include "sim2d/world.h"

namespace plugslam {
namespace sim {
namespace sim2d {

/// Everything that defines a simulated session.
struct SimConfig {
  std::shared_ptr<const World> world;  ///< the walls (required)
  /// Places visited in order, cyclically, along planned collision-free paths. With a single
  /// place, the robot starts there and explores: it drives to random reachable places drawn
  /// from the seed (which then also changes the ground truth).
  std::vector<Eigen::Vector2d> tour;
  double path_length = 50.0;        ///< the session ends at the first frame past this [m]
  double rate = 10.0;               ///< frame rate of odometry and lasers [Hz]
  int substeps = 5;                 ///< control / integration steps per frame
  DriveLimits drive;                ///< robot geometry and limits
  PlannerOptions planner;           ///< path planning grid and clearance
  std::vector<LaserConfig> lasers;  ///< any number of scanners (names must be unique)
  OdometryNoise odometry;           ///< wheel odometry errors
  uint64_t seed = 0;                ///< seeds every random stream
};

/// One synchronised step: ground truth, odometry and all scans at the same instant.
struct SimFrame {
  size_t index = 0;                       ///< 0-based frame number
  double time = 0.0;                      ///< [s], index / rate
  Eigen::Vector3d ground_truth{0, 0, 0};  ///< true robot pose in the world (x, y, theta)
  Eigen::Vector3d odometry{0, 0, 0};      ///< integrated wheel odometry (starts at ground truth)
  double wheel_left = 0.0;                ///< measured left wheel travel since last frame [m]
  double wheel_right = 0.0;               ///< measured right wheel travel since last frame [m]
  std::vector<LaserScan> lasers;          ///< one scan per configured laser, in config order
};

/// A pose (x, y, theta) as an isometry.
Eigen::Isometry2d toIsometry(const Eigen::Vector3d& pose);

/// Produces the frames of one session, deterministically for a given config and seed.
class Simulator {
 public:
  /// Plans the tour and drives it; throws InputError if the config is invalid or the tour cannot
  /// be driven without collision.
  explicit Simulator(SimConfig config);

  /// Fills `frame` with the next step; false (frame untouched) after the last frame.
  bool step(SimFrame& frame);

  /// Rewinds to frame 0 with the random streams reseeded (replays identical frames).
  void reset();

  /// Number of frames in the session.
  size_t frameCount() const { return ground_truth_.size(); }
  /// Ground-truth distance driven over the whole session [m].
  double pathLength() const { return path_length_; }
  /// Ground-truth pose of every frame.
  const std::vector<Eigen::Vector3d>& groundTruth() const { return ground_truth_; }
  /// Smallest distance from a ground-truth frame position to any wall [m].
  double minClearance() const { return min_clearance_; }
  /// The planned path the robot follows (for display).
  const std::vector<Eigen::Vector2d>& plannedPath() const { return planned_; }
  /// The session's configuration.
  const SimConfig& config() const { return config_; }
  /// The world.
  const World& world() const { return *config_.world; }

 private:
  void buildTrajectory();

  SimConfig config_;
  std::vector<Eigen::Vector2d> planned_;
  std::vector<Eigen::Vector3d> ground_truth_;  // per frame
  std::vector<Eigen::Vector2d> wheels_;        // true (dl, dr) per substep, frame k uses
                                               // [(k-1)*substeps, k*substeps)
  double path_length_ = 0.0;
  double min_clearance_ = 0.0;
  size_t next_ = 0;
  std::unique_ptr<WheelOdometry> odometry_;
  std::vector<Rng> laser_rngs_;
};

/// The seed's four sessions: "stage-0".."stage-3" in the built-in office, tours of about 43,
/// 79, 481 and 628 m with two 1081-beam 270-degree lasers ("front_laser", "rear_laser"),
/// 10 Hz, realistic odometry noise. Throws InputError listing the names for an unknown one.
SimConfig presetSession(const std::string& name, uint64_t seed = 0);

/// The preset names, in order.
std::vector<std::string> presetNames();

/// The path length the seed reports for a preset session [m].
double presetSeedLength(const std::string& name);

/// The two-laser rig of the presets: front at (0.2, 0, 0), rear at (-0.2, 0, pi).
std::vector<LaserConfig> defaultLasers();

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
