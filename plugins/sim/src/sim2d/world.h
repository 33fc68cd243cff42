#pragma once
// The simulator's 2D world: a set of wall segments with a uniform-grid index for ray casting.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace plugslam {
namespace sim {
namespace sim2d {

/// One wall segment from a to b (metres, world frame).
struct Segment {
  Eigen::Vector2d a;  ///< first end point
  Eigen::Vector2d b;  ///< second end point
};

/// A set of 2D wall segments, indexed by a uniform grid so rays cost a few cells each.
///
/// castRay returns +infinity when nothing is hit within max_range. Rays that graze a segment
/// exactly parallel to it do not hit it (a segment has no thickness).
class World {
 public:
  /// Builds the index over the segments; cell_size <= 0 picks one (about 1 m for office plans).
  explicit World(std::vector<Segment> segments, double cell_size = 0.0);

  /// The built-in office floor plan: 64 x 40 m of rooms, corridors, doors, alcoves and furniture.
  static World office();

  /// Loads a segment list: one `x1 y1 x2 y2` per line, '#' starts a comment, blank lines skipped.
  /// Throws ParseError (file, 1-based line) on a malformed line, InputError if unreadable/empty.
  static World loadSegments(const std::string& path);

  /// Loads a PGM occupancy image (P2 or P5). Pixel (col,row) covers the square whose lower-left
  /// corner is origin + resolution * (col, height-1-row), as ROS map_server. A pixel is occupied
  /// when (maxval - value) / maxval > occupied_threshold; each occupied pixel side facing a free
  /// pixel (or the image border) becomes a wall, and collinear sides are merged into one segment.
  static World loadPgm(const std::string& path, double resolution, const Eigen::Vector2d& origin,
                       double occupied_threshold = 0.65);

  /// Distance along the unit `direction` from `origin` to the first wall, or +infinity if none
  /// is hit within max_range. direction must have unit norm.
  double castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                 double max_range) const;

  /// True if the straight segment p-q touches any wall.
  bool crosses(const Eigen::Vector2d& p, const Eigen::Vector2d& q) const;

  /// Distance from p to the nearest wall, capped at max_distance (returned when none is closer).
  double clearance(const Eigen::Vector2d& p, double max_distance) const;

  /// The wall segments.
  const std::vector<Segment>& segments() const { return segments_; }
  /// Lower-left corner of the bounding box of all segments.
  const Eigen::Vector2d& boundsMin() const { return min_; }
  /// Upper-right corner of the bounding box of all segments.
  const Eigen::Vector2d& boundsMax() const { return max_; }

  /// Writes the segments in the loadSegments text format (for inspection or editing).
  void saveSegments(const std::string& path) const;

 private:
  int cellIndex(int cx, int cy) const { return cy * nx_ + cx; }
  // Nearest hit parameter t of the ray against segment i, or +infinity.
  double intersect(size_t i, const Eigen::Vector2d& o, const Eigen::Vector2d& d) const;

  std::vector<Segment> segments_;
  Eigen::Vector2d min_{0.0, 0.0}, max_{0.0, 0.0};
  Eigen::Vector2d grid_origin_{0.0, 0.0};
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<uint32_t>
      cell_start_;  // CSR: segments of cell c are cell_items_[start[c]..start[c+1])
  std::vector<uint32_t> cell_items_;
};

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
