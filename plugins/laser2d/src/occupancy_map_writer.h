#pragma once
// laser2d.OccupancyMapWriter: the occupancy grid of a run, from the kept scans placed at their
// corrected poses, written as map.pgm + map.yaml (ROS map_server) and map.png.
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "occupancy_grid.h"
#include "plugslam/geometry.h"
#include "plugslam/sink.h"
#include "plugslam/view/publisher.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// Draws the map from two kinds of evidence. A frame whose pose may still be corrected (mapping:
/// loop closures move its local map) keeps its cloud (compact) until the end, where it is
/// ray-traced at the corrected pose; a cloud is kept only when its pose in its local map is new
/// (farther than min_distance or min_angle from every cloud kept in that map), up to
/// max_scans_per_map per map, so this memory grows with the mapped space. A frame in a frozen
/// map (localization in a saved session: nothing will move it) is ray-traced at once into a
/// tiled grid, when it is min_distance or min_angle from the last frame traced and was not lost
/// (its pose measured, not predicted), and nothing of it is kept: localizing for hours costs the
/// area of the place, not the time spent in it.
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
                             "(or min_angle turned); in a frozen map, trace a frame only this far "
                             "from the last one traced",
                             Range{0, 1e3}};
  Param<double> min_angle{this, "min_angle", 0.05, "rad",
                          "keep a cloud turned this much from every kept cloud of its local map "
                          "(or min_distance away); in a frozen map, the same from the last frame "
                          "traced",
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
  /// Scans placed into the grid by the last end() (kept clouds; traced frames not included).
  size_t placedScans() const { return placed_; }
  /// Frames in frozen maps traced into the grid so far (none of them kept; frames too close to
  /// the last one traced, or lost, are not).
  size_t tracedFrames() const { return traced_frames_; }
  /// Tiles of the grid the frames in frozen maps were traced into (its memory, in 4 KiB pages).
  size_t tracedTiles() const { return traced_ ? traced_->tiles() : 0; }
  /// Paths written by the last end() (pgm, yaml, png), empty if nothing was written.
  const std::vector<std::string>& written() const { return written_; }

 private:
  // The frame's non-empty clouds among `measurements`; counts the frame as seen when any.
  std::vector<const PointCloud2D*> cloudsOf(const Frame& frame);
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
  // Ray-traces a cloud at its final world pose into traced_.
  void trace(const PointCloud2D& cloud, const SE2& world);
  // Publishes local map `map`'s grid on /grid, in the map's frame, from its kept scans.
  void publishGrid(int64_t map, double stamp);
  view::Channel<view::Grid> grid_channel_{"/grid", view::Latch::kPerKey};
  int64_t last_map_ = kNoMap;  // local map of the last frame, to see one close
  std::string out_dir_;
  std::vector<KeptScan> scans_;
  std::unordered_map<int64_t, std::vector<size_t>> by_map_;  // indices into scans_
  size_t frames_ = 0;  // frames with a cloud seen (kept or not)
  size_t placed_ = 0;
  std::unique_ptr<TiledOccupancyGrid> traced_;  // frames of frozen maps, created on first use
  size_t traced_frames_ = 0;
  bool last_traced_valid_ = false;
  double last_traced_[3] = {0, 0, 0};  // world x, y, theta of the last frame traced
  std::vector<std::string> written_;
};

}  // namespace laser2d
}  // namespace plugslam
