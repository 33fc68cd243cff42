#include "correlative_matcher.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <unordered_set>

#include "plugslam/errors.h"

namespace plugslam {
namespace laser2d {
namespace {

constexpr int kBlurCells = 2;  // gaussian of sigma = one cell, cut at two cells

int floorCell(double v) { return static_cast<int>(std::floor(v)); }

}  // namespace

CorrelativeGrid::CorrelativeGrid(const std::vector<Eigen::Vector2d>& points,
                                 const std::vector<Eigen::Vector2d>& normals, double extent,
                                 double resolution, int levels, const Eigen::Vector2d& clip_min,
                                 const Eigen::Vector2d& clip_max)
    : resolution_(resolution) {
  Eigen::Vector2d lo = clip_max, hi = clip_min;
  for (const auto& p : points) {
    if ((p.array() < clip_min.array()).any() || (p.array() > clip_max.array()).any()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if ((lo.array() > hi.array()).any()) lo = hi = 0.5 * (clip_min + clip_max);  // nothing inside
  origin_ = lo - Eigen::Vector2d::Constant((kBlurCells + 1) * resolution);
  width_ = floorCell((hi.x() - origin_.x()) / resolution) + kBlurCells + 2;
  height_ = floorCell((hi.y() - origin_.y()) / resolution) + kBlurCells + 2;

  levels_.resize(static_cast<size_t>(std::max(levels, 0)) + 1);
  Level& base = levels_[0];
  base.width = width_;
  base.height = height_;
  base.cells.assign(static_cast<size_t>(width_) * height_, 0);
  // Hit cells first: a point with a normal stands for a patch of wall `extent` either side of it
  // along its tangent, so the gaps between a far wall's sparse points still score.
  std::vector<uint8_t> hit(base.cells.size(), 0);
  const auto mark = [&](const Eigen::Vector2d& q) {
    const int x = floorCell((q.x() - origin_.x()) / resolution);
    const int y = floorCell((q.y() - origin_.y()) / resolution);
    if (x >= 0 && y >= 0 && x < width_ && y < height_) hit[static_cast<size_t>(y) * width_ + x] = 1;
  };
  const bool splat = extent > 0 && normals.size() == points.size();
  const int samples = splat ? static_cast<int>(std::ceil(2 * extent / resolution)) : 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& p = points[i];
    if ((p.array() < clip_min.array()).any() || (p.array() > clip_max.array()).any()) continue;
    mark(p);
    if (samples == 0) continue;
    const Eigen::Vector2d tangent(-normals[i].y(), normals[i].x());
    for (int k = 0; k <= samples; ++k) mark(p + (-extent + 2 * extent * k / samples) * tangent);
  }
  // Then a gaussian of one cell around every hit cell (by cell distance).
  uint8_t kernel[2 * kBlurCells + 1][2 * kBlurCells + 1];
  for (int dy = -kBlurCells; dy <= kBlurCells; ++dy)
    for (int dx = -kBlurCells; dx <= kBlurCells; ++dx)
      kernel[dy + kBlurCells][dx + kBlurCells] =
          static_cast<uint8_t>(std::lround(255 * std::exp(-0.5 * (dx * dx + dy * dy))));
  for (int cy = 0; cy < height_; ++cy) {
    for (int cx = 0; cx < width_; ++cx) {
      if (!hit[static_cast<size_t>(cy) * width_ + cx]) continue;
      for (int y = std::max(cy - kBlurCells, 0); y <= std::min(cy + kBlurCells, height_ - 1); ++y)
        for (int x = std::max(cx - kBlurCells, 0); x <= std::min(cx + kBlurCells, width_ - 1);
             ++x) {
          uint8_t& cell = base.cells[static_cast<size_t>(y) * width_ + x];
          cell = std::max(cell, kernel[y - cy + kBlurCells][x - cx + kBlurCells]);
        }
    }
  }
  pool();
}

CorrelativeGrid::CorrelativeGrid(double resolution, const Eigen::Vector2d& origin, int width,
                                 int height, std::vector<uint8_t> base, int levels, uint8_t outside)
    : resolution_(resolution), origin_(origin), width_(width), height_(height), outside_(outside) {
  if (width <= 0 || height <= 0 || base.size() != static_cast<size_t>(width) * height)
    throw InputError("correlative grid: " + std::to_string(base.size()) + " cells given for " +
                     std::to_string(width) + " x " + std::to_string(height));
  levels_.resize(static_cast<size_t>(std::max(levels, 0)) + 1);
  levels_[0].width = width_;
  levels_[0].height = height_;
  levels_[0].cells = std::move(base);
  pool();
}

void CorrelativeGrid::pool() {
  // Level h from level h-1: the 2^h window at c is the union of four 2^(h-1) windows, taken as
  // the max of two columns s apart, then of two rows s apart, over a copy of level h-1 padded
  // with `outside` so that no read needs a bounds check (the loops vectorize).
  std::vector<uint8_t> padded, rows;
  for (size_t h = 1; h < levels_.size(); ++h) {
    const int s = 1 << (h - 1);
    const Level& p = levels_[h - 1];
    Level& l = levels_[h];
    l.offset = (1 << h) - 1;
    l.width = width_ + l.offset;
    l.height = height_ + l.offset;
    // The padded copy covers cells [-l.offset, base size + s) in x and y.
    const int pw = l.width + s, ph = l.height + s;
    padded.assign(static_cast<size_t>(pw) * ph, outside_);
    const int shift = l.offset - p.offset;  // where level h-1's cell (0, 0) of its own lands
    for (int y = 0; y < p.height; ++y)
      std::copy_n(p.cells.begin() + static_cast<std::ptrdiff_t>(y) * p.width, p.width,
                  padded.begin() + static_cast<std::ptrdiff_t>(y + shift) * pw + shift);
    rows.resize(static_cast<size_t>(l.width) * ph);
    for (int y = 0; y < ph; ++y) {
      const uint8_t* in = padded.data() + static_cast<size_t>(y) * pw;
      uint8_t* out = rows.data() + static_cast<size_t>(y) * l.width;
      for (int x = 0; x < l.width; ++x) out[x] = std::max(in[x], in[x + s]);
    }
    l.cells.resize(static_cast<size_t>(l.width) * l.height);
    for (int y = 0; y < l.height; ++y) {
      const uint8_t* a = rows.data() + static_cast<size_t>(y) * l.width;
      const uint8_t* b = a + static_cast<size_t>(s) * l.width;
      uint8_t* out = l.cells.data() + static_cast<size_t>(y) * l.width;
      for (int x = 0; x < l.width; ++x) out[x] = std::max(a[x], b[x]);
    }
  }
}

std::vector<Eigen::Vector2d> voxelFilter(const std::vector<Eigen::Vector2d>& points,
                                         double resolution) {
  std::unordered_set<uint64_t> seen;
  std::vector<Eigen::Vector2d> out;
  out.reserve(points.size());
  for (const auto& p : points) {
    const auto x = static_cast<uint32_t>(static_cast<int32_t>(std::floor(p.x() / resolution)));
    const auto y = static_cast<uint32_t>(static_cast<int32_t>(std::floor(p.y() / resolution)));
    if (seen.insert((static_cast<uint64_t>(x) << 32) | y).second) out.push_back(p);
  }
  return out;
}

std::vector<Eigen::Vector2d> correlativeQuery(const std::vector<Eigen::Vector2d>& points,
                                              double max_range, double resolution) {
  std::vector<Eigen::Vector2d> near;
  near.reserve(points.size());
  for (const auto& p : points)
    if (p.squaredNorm() <= max_range * max_range) near.push_back(p);
  return voxelFilter(near, resolution);
}

int correlativeLevels(double window, double resolution, int max_levels) {
  return searchLevels(static_cast<int>(std::ceil(window / resolution)), max_levels);
}

GridScorer::GridScorer(const CorrelativeGrid& grid, const std::vector<Eigen::Vector2d>& query,
                       const SearchLattice<Space2D>& lattice)
    : grid_(&grid), angles_(lattice.angles), points_(query.size()) {
  const double r = grid.resolution();
  const SE2& c = lattice.center;
  const double theta0 = std::atan2(c.linear()(1, 0), c.linear()(0, 0));
  cells_.resize(static_cast<size_t>(2 * angles_ + 1));
  for (int a = -angles_; a <= angles_; ++a) {
    const Eigen::Rotation2Dd rot(theta0 + a * lattice.angular_step);
    std::vector<Eigen::Vector2i>& cells = cells_[static_cast<size_t>(a + angles_)];
    cells.reserve(query.size());
    for (const auto& q : query) {
      const Eigen::Vector2d p = c.translation() + rot * q - grid.origin();
      cells.emplace_back(floorCell(p.x() / r), floorCell(p.y() / r));
    }
  }
}

double GridScorer::score(int level, int a, int x, int y) const {
  int64_t sum = 0;
  for (const auto& p : cells_[static_cast<size_t>(a + angles_)])
    sum += grid_->value(level, p.x() + x, p.y() + y);
  return static_cast<double>(sum) / 255.0;
}

double angularStepAt(double range, double resolution) {
  const double d = std::max(range, resolution);
  return std::acos(std::max(1 - resolution * resolution / (2 * d * d), -1.0));
}

CorrelativeMatch matchCorrelative(const CorrelativeGrid& grid,
                                  const std::vector<Eigen::Vector2d>& query, const SE2& guess,
                                  const CorrelativeOptions& options) {
  CorrelativeMatch m;
  if (query.empty()) return m;
  const double r = grid.resolution();
  double range = 0;
  for (const auto& q : query) range = std::max(range, q.norm());
  SearchLattice<Space2D> lattice;
  lattice.center = guess;
  lattice.resolution = r;
  lattice.angular_step = options.angular_step > 0 ? options.angular_step : angularStepAt(range, r);
  lattice.cells = static_cast<int>(std::ceil(options.linear_window / r - 1e-9));
  lattice.angles =
      static_cast<int>(std::ceil(options.angular_window / lattice.angular_step - 1e-9));
  lattice.levels = grid.levels();
  const GridScorer scorer(grid, query, lattice);
  SearchOptions o;
  o.min_score = options.min_score;
  o.ambiguity_margin = options.min_score_margin;
  o.distinct_translation = options.distinct_translation;
  o.distinct_rotation = options.distinct_rotation;
  const SearchResult<Space2D> found = correlativeSearch<Space2D>({&scorer}, lattice, o);
  m.angular_step = lattice.angular_step;
  m.angles = 2 * lattice.angles + 1;
  m.leaves = found.leaves;
  m.found = found.found;
  m.ambiguous = found.ambiguous;
  m.pose = found.pose;
  m.score = found.score;
  m.second_score = found.rival_score;
  m.second_pose = found.rival;
  return m;
}

}  // namespace laser2d
}  // namespace plugslam
