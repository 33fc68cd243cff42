#pragma once
// A log-odds occupancy grid filled by ray tracing, and its image outputs (PGM, PNG, map_server
// YAML).
#include <Eigen/Core>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <unordered_map>
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
  /// Adds `log_odds` to cell (x, y) with the grid's clamp (a cell outside is ignored): merges
  /// evidence gathered elsewhere, e.g. in a TiledOccupancyGrid on the same lattice.
  void addLogOdds(int x, int y, double log_odds) { add(x, y, log_odds); }
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

/// Visits the cells of a ray from cell `a` to cell `b` (Bresenham): f(x, y, last) for each,
/// `last` true for `b` only.
template <class F>
void walkRay(const Eigen::Vector2i& a, const Eigen::Vector2i& b, F&& f) {
  int x = a.x(), y = a.y();
  const int dx = std::abs(b.x() - x), dy = -std::abs(b.y() - y);
  const int sx = x < b.x() ? 1 : -1, sy = y < b.y() ? 1 : -1;
  int err = dx + dy;
  while (x != b.x() || y != b.y()) {
    f(x, y, false);
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
  }
  f(b.x(), b.y(), true);
}

/// A log-odds grid without fixed bounds: square tiles allocated when a ray first touches them,
/// on the lattice of cells [i * resolution, (i + 1) * resolution). Memory grows with the area
/// observed, not with the number of rays: tracing the same place again allocates nothing.
class TiledOccupancyGrid {
 public:
  /// Cells per tile side (a tile of floats is one 4 KiB page).
  static constexpr int kTile = 32;

  /// An empty grid of `resolution` metres (> 0, finite; InputError otherwise).
  explicit TiledOccupancyGrid(double resolution);
  /// Traces a ray (world frame), with the same updates as OccupancyGrid::traceRay. A ray with a
  /// non-finite end or one beyond +-1e6 cells of the lattice's origin is ignored (returns false).
  bool traceRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& hit,
                bool hit_is_return = true);
  /// Forgets every cell.
  void clear();
  /// True when no cell was observed.
  bool empty() const { return tiles_.empty(); }
  /// Tiles allocated (each kTile * kTile floats).
  size_t tiles() const { return tiles_.size(); }
  /// Lattice index of the cell holding p (floor(p / resolution)).
  Eigen::Vector2i cellOf(const Eigen::Vector2d& p) const;
  /// Lowest observed cell indices, x and y (meaningless when empty()).
  const Eigen::Vector2i& minCell() const { return min_; }
  /// Highest observed cell indices, x and y (meaningless when empty()).
  const Eigen::Vector2i& maxCell() const { return max_; }
  /// Calls f(x, y, log_odds) for every observed cell (lattice indices), in no particular order.
  template <class F>
  void forEachCell(F&& f) const {
    for (const auto& [key, tile] : tiles_) {
      const int tx = static_cast<int32_t>(static_cast<uint32_t>(key >> 32));
      const int ty = static_cast<int32_t>(static_cast<uint32_t>(key));
      for (int j = 0; j < kTile; ++j)
        for (int i = 0; i < kTile; ++i) {
          const float v = tile[static_cast<size_t>(j) * kTile + i];
          if (v != 0.0f) f(tx * kTile + i, ty * kTile + j, static_cast<double>(v));
        }
    }
  }
  /// Cell size [m].
  double resolution() const { return resolution_; }

  double hit_log_odds = 0.85;    ///< as OccupancyGrid
  double miss_log_odds = -0.4;   ///< as OccupancyGrid
  double clamp_log_odds = 10.0;  ///< as OccupancyGrid

 private:
  float& cell(int x, int y);
  void add(int x, int y, double v);
  double resolution_;
  std::unordered_map<uint64_t, std::unique_ptr<float[]>> tiles_;
  uint64_t last_key_ = 0;  // the tile of the previous cell: rays walk through a tile at a time
  float* last_tile_ = nullptr;
  Eigen::Vector2i min_ = Eigen::Vector2i::Zero(), max_ = Eigen::Vector2i::Zero();
};

/// Encodes an 8-bit grayscale image as binary PGM (P5).
std::string encodePgm(const std::vector<uint8_t>& pixels, int width, int height);

}  // namespace laser2d
}  // namespace plugslam
