#pragma once
// sim.SimulatorMixed: a robot with a planar laser, wheel odometry and an RGB-D camera in the 3D
// living room (sim3d::MixedSimulator), for mixed-cue pipelines.
#include <cstdint>
#include <memory>
#include <string>

#include "plugslam/source.h"
#include "sim3d/mixed.h"

namespace plugslam {
namespace sim {

/// Emits raw[laser] (LaserScan), raw["rgb"] (Image), raw["depth"] (DepthImage), raw["camera"]
/// (CameraInfo with the camera's mount on the robot), raw[odometry] (Odometry2D) and
/// raw[ground_truth] (Eigen::Isometry3d, the robot base). Deterministic for a given seed.
class SimulatorMixedSource : public Source {
 public:
  Param<double> path_length{this, "path_length",        40.0,
                            "m",  "length of the tour", Range{1.0, 100000.0}};
  Param<double> rate{this, "rate", 10.0, "Hz", "frame rate", Range{0.5, 100.0}};
  Param<std::string> laser{this, "laser", "front_laser", "", "raw entry for the laser scan"};
  Param<double> laser_height{
      this, "laser_height", 0.3, "m", "height of the scan plane", Range{0.01, 2.6}};
  Param<int> beams{this, "beams", 1081, "", "laser beams", Range{1, 100000}};
  Param<double> fov{this, "fov", 1.5 * M_PI, "rad", "laser field of view", Range{0.01, 2 * M_PI}};
  Param<double> max_range{this, "max_range", 20.0, "m", "laser max range", Range{0.1, 1000.0}};
  Param<double> range_noise{
      this, "range_noise", 0.01, "m", "laser range noise sigma", Range{0.0, 10.0}};
  Param<double> dropout{this,           "dropout", 0.005, "", "probability of a missing beam",
                        Range{0.0, 1.0}};
  Param<double> odometry_noise{this,
                               "odometry_noise",
                               1.0,
                               "",
                               "scale on the odometry errors (0 = perfect)",
                               Range{0.0, 1000.0}};
  Param<bool> image_noise{this, "image_noise", true, "", "image noise and exposure changes"};
  Param<bool> depth_noise{this, "depth_noise", true, "", "Kinect-like depth noise"};
  Param<int64_t> seed{this, "seed", 0, "", "seeds textures and noise", Range{0, 9.0e15}};
  Param<std::string> odometry{this, "odometry", "odom", "", "raw entry for the wheel odometry"};
  Param<std::string> ground_truth{this, "ground_truth", "ground_truth", "",
                                  "raw entry for the true robot pose"};

  SimulatorMixedSource();
  ~SimulatorMixedSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  /// The number of frames.
  int64_t sizeHint() const override;
  /// The raw entries next() writes (for the builder's wiring check).
  std::vector<ProvidedEntry> provides() const override;

 private:
  std::unique_ptr<sim3d::MixedSimulator> sim_;
};

}  // namespace sim
}  // namespace plugslam
