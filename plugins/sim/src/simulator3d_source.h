#pragma once
// sim.Simulator3D: rendered stereo pairs or RGB-D frames with exact ground truth (sim3d).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"
#include "plugslam/source.h"
#include "sim3d/simulator.h"

namespace plugslam {
namespace sim {

/// Emits one frame per trajectory pose. Stereo: raw["left"], raw["right"] (grey Image);
/// RGB-D: raw["rgb"] (RGB Image), raw["depth"] (DepthImage, metres); both: raw["camera"]
/// (CameraInfo) and raw[ground_truth] (Eigen::Isometry3d, the left / RGB camera in the world);
/// with `odometry` set, raw[odometry] (Odometry2D, the vehicle's wheel odometry).
/// Deterministic for a given seed.
class Simulator3DSource : public Source {
 public:
  Param<std::string> world{this, "world",          "livingroom",
                           "",   "built-in world", Choices{{"livingroom", "street"}}};
  Param<std::string> camera{this,
                            "camera",
                            "rgbd",
                            "",
                            "rgbd: VGA RGB + depth; stereo: KITTI-like 1241x376 grey pair, 0.54 m",
                            Choices{{"rgbd", "stereo"}}};
  Param<std::string> trajectory{this, "trajectory", "", "",
                                "camera trajectory file (TUM, KITTI, g2o); empty = generated loop"};
  Param<std::string> trajectory_format{this,
                                       "trajectory_format",
                                       "auto",
                                       "",
                                       "format of the trajectory file",
                                       Choices{{"auto", "tum", "kitti", "g2o"}}};
  Param<std::string> kitti_times{this, "kitti_times", "", "",
                                 "timestamps of a KITTI trajectory (one per line)"};
  Param<bool> anchor{this, "anchor", true, "",
                     "move a loaded trajectory so it starts at the world's start pose"};
  Param<double> rate{this,
                     "rate",
                     0.0,
                     "Hz",
                     "camera rate; 0 = 30 (rgbd) / 10 (stereo), or a file's own poses",
                     Range{0.0, 1000.0}};
  Param<double> duration{
      this, "duration", 0.0, "s", "generated living-room loop length; 0 = 30 s", Range{0.0, 1e6}};
  Param<double> speed{this, "speed", 8.0, "m/s", "generated street drive speed", Range{0.1, 100.0}};
  Param<double> acceleration{this,
                             "acceleration",
                             0.0,
                             "m/s^2",
                             "generated street drive: start standing and speed up at this rate "
                             "to `speed` (0: at speed from the first frame)",
                             Range{0.0, 100.0}};
  // Turning is what a camera's own rotation estimate is least sure of (every pixel moves, near
  // and far alike): a panned camera stresses it beyond what the path's own turns do.
  Param<double> pan{this, "pan", 0.0, "deg",
                    "the camera's heading swings this far either side of the path's (a camera "
                    "panned by hand or on a turret); 0 = fixed on the path",
                    Range{0.0, 180.0}};
  Param<double> pan_period{this, "pan_period", 2.0, "s", "one pan swing there and back",
                           Range{0.1, 1e6}};
  // A camera driver that loses frames (a full buffer, a busy bus) delivers the next one late:
  // the motion between two delivered frames is then several steps long.
  Param<std::vector<int>> drop_frames{this, "drop_frames", {}, "",
                                          "indices of rendered frames that are not delivered"};
  Param<bool> image_noise{this, "image_noise", true, "",
                          "gaussian image noise and exposure changes"};
  Param<double> image_sigma{this,          "image_sigma",       2.0,
                            "grey levels", "image noise sigma", Range{0.0, 100.0}};
  Param<double> exposure_sigma{
      this, "exposure_sigma", 0.15, "", "amplitude of the log exposure gain", Range{0.0, 1.5}};
  Param<bool> depth_noise{this, "depth_noise", true, "",
                          "Kinect-like depth noise, quantisation and missing pixels"};
  Param<double> depth_max_range{
      this, "depth_max_range", 6.0, "m", "farther depth readings are missing", Range{0.5, 1000.0}};
  Param<int64_t> seed{this, "seed", 0, "", "seeds textures, buildings and noise", Range{0, 9.0e15}};
  Param<std::string> ground_truth{this, "ground_truth", "ground_truth", "",
                                  "raw entry for the true camera pose"};
  // The camera rides on a vehicle (a car on the street) whose base frame is the road point
  // under the camera, x forward, y left, z up: its wheel odometry is the true motion projected
  // on the base's plane with sim2d's wheel-encoder errors, so 2D and 3D share one model.
  Param<std::string> odometry{
      this, "odometry", "", "",
      "raw entry for the vehicle's wheel odometry (Odometry2D: the base, 1.65 m below the camera, "
      "x forward, z up, in the odometry frame); empty = no odometry"};
  Param<double> odometry_noise{
      this,
      "odometry_noise",
      1.0,
      "",
      "scale on sim2d's wheel-encoder errors (wheel scale 0.08 % left, 0.03 % right: 0.055 % "
      "distance scale and a heading drift of 0.0005 / wheel_base rad/m; wheel base 0.3 %: "
      "0.3 % of every turn; slip 0.002 m/sqrt(m) and 0.002 m/sqrt(rad) per wheel); 0 = exact",
      Range{0.0, 1000.0}};
  Param<double> wheel_base{this,
                           "wheel_base",
                           1.6,
                           "m",
                           "distance between the vehicle's left and right wheels, which turns "
                           "their travel errors into heading errors",
                           Range{0.1, 10.0}};

  Simulator3DSource();
  ~Simulator3DSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  /// The number of frames.
  int64_t sizeHint() const override;
  /// The raw entries next() writes (for the builder's wiring check).
  std::vector<ProvidedEntry> provides() const override;

  /// The simulator (after configure()).
  const sim3d::Simulator3D& simulator() const;

 private:
  std::unique_ptr<sim3d::Simulator3D> sim_;
  std::vector<Eigen::Isometry2d> odometry_;  // one reading per frame; empty without odometry
  size_t next_ = 0;
};

}  // namespace sim
}  // namespace plugslam
