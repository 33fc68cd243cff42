#pragma once
// laser2d.OccupancyMapWriter: the occupancy grid of a run, from the kept scans placed at their
// corrected poses, written as map.pgm + map.yaml (ROS map_server) and map.png.
#include <string>
#include <unordered_map>
#include <vector>

#include "plugslam/sink.h"

namespace plugslam {
namespace laser2d {

/// Keeps frames' clouds (compact) and ray-traces them at the end of the run. A cloud is kept when
/// its pose in its local map is new (farther than min_distance or min_angle from every cloud kept
/// in that map), up to max_scans_per_map per map: memory grows with the mapped space, not with
/// time (a robot standing still or localizing in saved maps adds nothing).
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

  Param<double> min_distance{this, "min_distance", 0.05, "m",
                             "keep a cloud only this far from every kept cloud of its local map "
                             "(or min_angle turned)",
                             Range{0, 1e3}};
  Param<double> min_angle{this, "min_angle", 0.05, "rad",
                          "keep a cloud turned this much from every kept cloud of its local map "
                          "(or min_distance away)",
                          Range{0, 4}};
  Param<int> max_scans_per_map{this, "max_scans_per_map", 100, "",
                               "clouds kept per local map at most (0: no limit)",
                               Range{0, 1e9}};

  OccupancyMapWriter();
  void begin(const std::string& out_dir) override;
  void consume(const Frame& frame) override;
  void end(const RunResult& result) override;

  /// Scans kept so far.
  size_t keptScans() const { return scans_.size(); }
  /// Frames that brought a cloud so far (kept or not).
  size_t seenFrames() const { return frames_; }
  /// Scans placed into the grid by the last end().
  size_t placedScans() const { return placed_; }
  /// Paths written by the last end() (pgm, yaml, png), empty if nothing was written.
  const std::vector<std::string>& written() const { return written_; }

 private:
  static constexpr int64_t kNoMap = -1;  // a frame without an estimate
  struct KeptScan {
    double stamp;
    uint64_t seq;
    float origin[2];
    std::vector<float> xy;  // robot frame, x0 y0 x1 y1 ...
    int64_t map;
    double in_map[3];  // x, y, theta in the local map (for the novelty test)
    double live[3];    // x, y, theta in the world as estimated when processed (for `save`)
  };
  // True when a cloud at `in_map` in local map `map` adds to what is kept.
  bool isNew(int64_t map, const double in_map[3]) const;
  std::string out_dir_;
  std::vector<KeptScan> scans_;
  std::unordered_map<int64_t, std::vector<size_t>> by_map_;  // indices into scans_
  size_t frames_ = 0;  // frames with a cloud seen (kept or not)
  size_t placed_ = 0;
  std::vector<std::string> written_;
};

}  // namespace laser2d
}  // namespace plugslam
