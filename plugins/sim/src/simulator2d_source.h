#pragma once
// sim.Simulator2D: the built-in 2D simulator (sim2d) as a frame source with exact ground truth.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"
#include "plugslam/source.h"
#include "sim2d/simulator.h"

namespace plugslam {
namespace sim {

/// Emits one frame per simulator step: raw[laser name] = LaserScan (mount from the rig),
/// raw[odometry] = Odometry2D, raw[ground_truth] = Eigen::Isometry2d (true robot pose).
/// Deterministic for a given session and seed.
class Simulator2DSource : public Source {
 public:
  Param<std::string> session{this,
                             "session",
                             "stage-1",
                             "",
                             "preset session (tour, length, rig, noise)",
                             Choices{sim2d::presetNames()}};
  Param<int64_t> seed{this, "seed", 0, "", "seeds every noise stream", Range{0, 9.0e15}};
  Param<std::string> world{this, "world", "", "",
                           "segment list or .pgm occupancy image; empty = the built-in office"};
  Param<double> world_resolution{
      this, "world_resolution", 0.05, "m", "metres per pixel of a .pgm world", Range{1e-4, 100.0}};
  Param<std::vector<double>> world_origin{
      this, "world_origin", {0.0, 0.0}, "m", "lower-left corner (x, y) of a .pgm world"};
  Param<std::vector<double>> start{
      this, "start", {}, "m", "start place (x, y) in a custom world, explored from there"};
  Param<std::vector<std::string>> lasers{this,
                                         "lasers",
                                         {"front_laser", "rear_laser"},
                                         "",
                                         "scanners to simulate and emit (names of the rig)"};
  Param<double> range_noise{
      this, "range_noise", 0.01, "m", "range noise standard deviation", Range{0.0, 10.0}};
  Param<double> dropout{
      this, "dropout", 0.005, "", "probability that a beam returns nothing", Range{0.0, 1.0}};
  Param<double> odometry_noise{this,
                               "odometry_noise",
                               1.0,
                               "",
                               "scale on the preset's odometry errors (0 = perfect odometry)",
                               Range{0.0, 1000.0}};
  Param<std::string> odometry{this, "odometry", "odom", "", "raw entry for the wheel odometry"};
  Param<std::string> ground_truth{this, "ground_truth", "ground_truth", "",
                                  "raw entry for the true robot pose"};

  Simulator2DSource();
  ~Simulator2DSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  /// The session's frame count.
  int64_t sizeHint() const override;
  /// The raw entries next() writes (for the builder's wiring check).
  std::vector<ProvidedEntry> provides() const override;

  /// The simulator (after configure()); for tools that need the world or the ground truth.
  const sim2d::Simulator& simulator() const;

 private:
  std::unique_ptr<sim2d::Simulator> sim_;
};

}  // namespace sim
}  // namespace plugslam
