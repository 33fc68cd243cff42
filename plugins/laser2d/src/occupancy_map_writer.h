#pragma once
// laser2d.OccupancyMapWriter: the occupancy grid of a run, from the kept scans placed at their
// corrected poses, written as map.pgm + map.yaml (ROS map_server) and map.png.
#include <string>
#include <vector>

#include "plugslam/sink.h"

namespace plugslam {
namespace laser2d {

/// Keeps each frame's clouds (compact) and ray-traces them at the end of the run.
class OccupancyMapWriter final : public Sink {
 public:
  Param<double> resolution{this, "resolution", 0.05, "m", "cell size", Range{1e-3, 100}};
  Param<std::string> file{this, "file", "map", "",
                          "output base name (in the output folder unless absolute): "
                          "<file>.pgm, <file>.yaml, <file>.png"};
  Param<double> max_range{this,
                          "max_range",
                          0.0,
                          "m",
                          "ignore points farther than this from the sensor (0: keep all)",
                          Range{0, 1e4}};
  Param<std::vector<std::string>> measurements{
      this, "measurements", {"front"}, "", "PointCloud2D measurement entries to map"};
  Param<double> max_time_offset{this,
                                "max_time_offset",
                                1e-6,
                                "s",
                                "a scan is placed at the trajectory pose this close in time",
                                Range{0, 1e6}};

  OccupancyMapWriter();
  void begin(const std::string& out_dir) override;
  void consume(const Frame& frame) override;
  void end(const RunResult& result) override;

  /// Scans kept so far.
  size_t keptScans() const { return scans_.size(); }
  /// Scans placed into the grid by the last end().
  size_t placedScans() const { return placed_; }
  /// Paths written by the last end() (pgm, yaml, png), empty if nothing was written.
  const std::vector<std::string>& written() const { return written_; }

 private:
  struct KeptScan {
    double stamp;
    uint64_t seq;
    float origin[2];
    std::vector<float> xy;  // robot frame, x0 y0 x1 y1 ...
  };
  std::string out_dir_;
  std::vector<KeptScan> scans_;
  Trajectory live_;  // each frame's pose as estimated when it was processed (for `save`)
  size_t placed_ = 0;
  std::vector<std::string> written_;
};

}  // namespace laser2d
}  // namespace plugslam
