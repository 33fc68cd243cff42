#pragma once
// Global scan-to-map matching for loop closures after large drift (issue 5, item 1): a query
// cloud is matched against a likelihood grid of a map's cloud over a wide window of translations
// and rotations around a guess, exhaustively but pruned by branch and bound over max-pooled grids
// (Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM", ICRA 2016). Used by
// laser2d.CorrelativeValidator and laser2d.GlobalMatchDetector.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "plugslam/correlative_search.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace laser2d {

/// A likelihood grid of a point cloud (1 on a point, a gaussian fall-off of one cell around it)
/// and its max-pooled levels: level h holds, at cell c, the max over the 2^h x 2^h cells from c.
class CorrelativeGrid {
 public:
  /// Rasterizes `points` at `resolution` over their bounding box clipped to [clip_min, clip_max]
  /// (points outside are dropped), with `levels` pooled levels above the base (0 = base only).
  /// With unit `normals` (one per point), each point also covers `extent` metres either side of
  /// it along its tangent.
  CorrelativeGrid(const std::vector<Eigen::Vector2d>& points,
                  const std::vector<Eigen::Vector2d>& normals, double extent, double resolution,
                  int levels, const Eigen::Vector2d& clip_min, const Eigen::Vector2d& clip_max);
  /// A grid from precomputed base values (`width` x `height`, row-major from cell (0, 0) at
  /// world `origin`, 0..255), with `levels` pooled levels above it; cells outside the grid have
  /// the value `outside`.
  CorrelativeGrid(double resolution, const Eigen::Vector2d& origin, int width, int height,
                  std::vector<uint8_t> base, int levels, uint8_t outside = 0);
  /// Cell size [m].
  double resolution() const { return resolution_; }
  /// World position of the bottom-left corner of cell (0, 0).
  const Eigen::Vector2d& origin() const { return origin_; }
  /// Number of pooled levels above the base.
  int levels() const { return static_cast<int>(levels_.size()) - 1; }
  /// Base width in cells.
  int width() const { return width_; }
  /// Base height in cells.
  int height() const { return height_; }
  /// Value of cell (x, y) at `level`, in 0..255 (255 = on a point); `outside` (0 unless given)
  /// outside the grid.
  int value(int level, int x, int y) const {
    const Level& l = levels_[static_cast<size_t>(level)];
    const int xi = x + l.offset, yi = y + l.offset;
    if (xi < 0 || yi < 0 || xi >= l.width || yi >= l.height) return outside_;
    return l.cells[static_cast<size_t>(yi) * l.width + xi];
  }

 private:
  void pool();  // builds the pooled levels above the base
  struct Level {
    int offset = 0, width = 0, height = 0;  // covers cells [-offset, base size)
    std::vector<uint8_t> cells;  // 8 bits: a score needs no more, and large maps stay cache-sized
  };
  double resolution_;
  Eigen::Vector2d origin_;
  int width_ = 0, height_ = 0;
  uint8_t outside_ = 0;
  std::vector<Level> levels_;
};

/// Scores the poses of a lattice for a query cloud against a grid: the query is turned for every
/// heading and discretized into the grid's cells once, so a pose costs one lookup a point.
class GridScorer : public LatticeScorer {
 public:
  /// `query`: points in the robot frame; `lattice` in the grid's frame, at its resolution.
  GridScorer(const CorrelativeGrid& grid, const std::vector<Eigen::Vector2d>& query,
             const SearchLattice<Space2D>& lattice);
  double score(int level, int a, int x, int y) const override;
  double maxScore() const override { return static_cast<double>(points_); }

 private:
  const CorrelativeGrid* grid_;
  int angles_ = 0;
  size_t points_ = 0;
  std::vector<std::vector<Eigen::Vector2i>> cells_;  // per heading index + angles_
};

/// The heading step [rad] that moves a point at `range` by one `resolution` cell (Hess et al.,
/// eq. 7).
double angularStepAt(double range, double resolution);

/// Options of the correlative search; windows are half-widths around the guess.
struct CorrelativeOptions {
  double linear_window = 6.0;         ///< [m], in x and in y
  double angular_window = 0.6;        ///< [rad]
  double angular_step = 0.0;          ///< [rad]; 0: from the resolution and the query's extent
  double min_score = 0.55;            ///< best pose must score at least this
  double min_score_margin = 0.03;     ///< ...and this much above any distinct pose
  double distinct_translation = 0.5;  ///< [m] poses farther apart than this are distinct...
  double distinct_rotation = 0.2;     ///< [rad] ...or rotated more than this
};

/// Outcome of a correlative search.
struct CorrelativeMatch {
  bool found = false;                 ///< a pose scored min_score or more
  bool ambiguous = false;             ///< a distinct pose scored within the margin of the best
  SE2 pose = SE2::Identity();         ///< best pose of the query's origin in the grid's frame
  double score = 0;                   ///< mean grid value (0..1) of the query's points at `pose`
  double second_score = 0;            ///< a distinct pose's score when ambiguous
  SE2 second_pose = SE2::Identity();  ///< that pose, when ambiguous
  double angular_step = 0;            ///< [rad] step used
  int angles = 0;                     ///< rotations searched
  int leaves = 0;                     ///< poses scored exactly (search effort)
};

/// Finds the pose of `query` (points in its own frame) in `grid`'s frame, within the windows
/// around `guess`, maximizing the mean grid value of its points; branch and bound, exact on the
/// discretized poses (grid cells x angular steps).
CorrelativeMatch matchCorrelative(const CorrelativeGrid& grid,
                                  const std::vector<Eigen::Vector2d>& query, const SE2& guess,
                                  const CorrelativeOptions& options);

/// Keeps the first point of each `resolution` cell (in the points' own frame).
std::vector<Eigen::Vector2d> voxelFilter(const std::vector<Eigen::Vector2d>& points,
                                         double resolution);

/// A query for matchCorrelative: the points within `max_range` of the origin, one per
/// `resolution` cell.
std::vector<Eigen::Vector2d> correlativeQuery(const std::vector<Eigen::Vector2d>& points,
                                              double max_range, double resolution);

/// Pooled levels for a search of +-`window` at `resolution`: the top level covers the window
/// (branch and bound starts there), at most `max_levels`.
int correlativeLevels(double window, double resolution, int max_levels = 16);

}  // namespace laser2d
}  // namespace plugslam
