#pragma once
// A hash grid over 2D points (open addressing, chained per cell), rebuilt in place: its storage
// is reused between frames, so steady-state merging does not allocate.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace plugslam {
namespace laser2d {

/// Points bucketed by square cells of a fixed size.
class CellIndex {
 public:
  /// Empties the index for cells of `cell` metres, with room for `expected` points.
  void reset(double cell, size_t expected);
  /// Adds point `index` at position p.
  void insert(const Eigen::Vector2d& p, int index);
  /// Calls f(index) for every point in the 3x3 cells around p (a superset of the points within
  /// one cell size of p).
  template <class F>
  void forNeighbours(const Eigen::Vector2d& p, F&& f) const {
    const int64_t cx = cellOf(p.x()), cy = cellOf(p.y());
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy) {
        const int64_t slot = find(key(cx + dx, cy + dy));
        if (slot < 0) continue;
        for (int i = heads_[slot]; i >= 0; i = next_[i]) f(i);
      }
  }

 private:
  int64_t cellOf(double v) const { return static_cast<int64_t>(std::floor(v * inv_cell_)); }
  static uint64_t key(int64_t x, int64_t y) {
    return (static_cast<uint64_t>(x) << 32) ^ (static_cast<uint64_t>(y) & 0xffffffffULL);
  }
  int64_t find(uint64_t k) const;
  void grow();

  double inv_cell_ = 1.0;
  std::vector<uint64_t> keys_;
  std::vector<int> heads_;  // -1: empty slot
  std::vector<int> next_;   // per point: next point of the same cell, -1 at the end
  size_t used_ = 0;
};

}  // namespace laser2d
}  // namespace plugslam
