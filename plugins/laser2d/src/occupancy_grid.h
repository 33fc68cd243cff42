#pragma once
// A log-odds occupancy grid filled by ray tracing, and its image outputs (PGM, PNG, map_server
// YAML).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace plugslam {
namespace laser2d {

/// Log-odds grid over a fixed rectangle; cell (0, 0) is the bottom-left (min x, min y).
class OccupancyGrid {
 public:
  /// A grid of `resolution` metres covering [min, max] (grown to whole cells).
  OccupancyGrid(double resolution, const Eigen::Vector2d& min, const Eigen::Vector2d& max);
  /// Traces a ray from `origin` to `hit` (world frame): cells on the way become freer, the end
  /// cell more occupied (unless `hit_is_return` is false: a max-range ray only clears).
  void traceRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& hit,
                bool hit_is_return = true);
  /// Width in cells.
  int width() const { return width_; }
  /// Height in cells.
  int height() const { return height_; }
  /// Cell size [m].
  double resolution() const { return resolution_; }
  /// World position of the bottom-left corner of cell (0, 0).
  const Eigen::Vector2d& origin() const { return origin_; }
  /// Log-odds of cell (x, y).
  double logOdds(int x, int y) const { return cells_[static_cast<size_t>(y) * width_ + x]; }
  /// Cell of a world point (may be outside the grid).
  Eigen::Vector2i cellOf(const Eigen::Vector2d& p) const;
  /// Occupancy probability of cell (x, y).
  double probability(int x, int y) const;
  /// True when the cell was never observed.
  bool unknown(int x, int y) const { return logOdds(x, y) == 0.0; }
  /// The map_server image: row 0 at the top (max y); occupied 0, free 254, unknown 205.
  std::vector<uint8_t> image() const;

  double hit_log_odds = 0.85;    ///< added to the end cell of a return
  double miss_log_odds = -0.4;   ///< added to every cell a ray crosses
  double clamp_log_odds = 10.0;  ///< |log-odds| bound, so the map can still change its mind

 private:
  void add(int x, int y, double v);
  double resolution_;
  Eigen::Vector2d origin_;
  int width_, height_;
  std::vector<float> cells_;  // compact: a map can be large
};

/// Encodes an 8-bit grayscale image as binary PGM (P5).
std::string encodePgm(const std::vector<uint8_t>& pixels, int width, int height);
/// Encodes an 8-bit grayscale image as PNG (zlib deflate, no filter).
std::string encodePng(const std::vector<uint8_t>& pixels, int width, int height);

}  // namespace laser2d
}  // namespace plugslam
